// Surfaces without a closed-form ray parameter, found by interval bisection
// (glint_core::shape::implicit::solve) in f32: the segment is bisected, nearest half
// first; a piece is dropped only when the enclosure of f over it excludes 0, and a
// piece on which f is monotonic holds a crossing exactly when its ends differ in sign,
// which is then refined inside its bracket. Each shape supplies f(t) and an enclosure
// of f and of the sign of df/dt over [a, b] (`RayFunction`); the superellipsoid is the
// first.

// A function of the ray parameter: which shape, its record, and the object-space ray.
struct RayFunction {
    kind: u32,
    index: u32,
    o: vec3<f32>,
    d: vec3<f32>,
}

// An enclosure of f over a piece: its range, and the sign of df/dt where it is known
// (+1 rising, −1 falling, 0 either).
struct Enclosure {
    lo: f32,
    hi: f32,
    slope: i32,
}

fn rf_value(f: RayFunction, t: f32) -> f32 {
    return superellipsoid_value(f.index, abs(f.o + t * f.d));
}

fn rf_enclose(f: RayFunction, a: f32, b: f32) -> Enclosure {
    return superellipsoid_enclose(f, a, b);
}

const F32_EPSILON: f32 = 1.1920929e-7;

// Inside is f < 0; NaN counts as outside, as on the CPU.
fn inside(v: f32) -> bool {
    return v < 0.0;
}

// Bisection levels at most: 2⁻²⁴ of the segment is an f32's resolution.
const SOLVE_DEPTH: u32 = 24u;
// Enclosures evaluated for one ray at most; past the budget, pieces are checked for a
// sign change at their ends only, so the search always ends.
const SOLVE_BUDGET: u32 = 2048u;

// glint_core::math::polynomial::refine_root in f32: secant steps kept inside the
// bracket, every fourth a bisection, with the Illinois halving of a stale end.
fn refine_crossing(f: RayFunction, a_in: f32, b_in: f32, fa_in: f32, fb_in: f32) -> f32 {
    var a = a_in;
    var b = b_in;
    var fa = fa_in;
    var fb = fb_in;
    let a_negative = inside(fa);
    var side = 0;
    for (var i = 0u; i < 64u; i += 1u) {
        let width = b - a;
        if !(width > 4.0 * F32_EPSILON * max(abs(a), abs(b))) {
            break;
        }
        let secant = a - fa * width / (fb - fa);
        let margin = 1e-3 * width;
        var x = 0.5 * (a + b);
        if finite(secant) && i % 4u != 3u {
            x = clamp(secant, a + margin, b - margin);
        }
        let fx = rf_value(f, x);
        if inside(fx) == a_negative {
            a = x;
            fa = fx;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = x;
            fb = fx;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    return select(b, a, abs(fa) <= abs(fb));
}

// The first sign change of f in [t0, t1] after t_min and before t_max, as a hit.
fn solve_first(f: RayFunction, t0: f32, t1: f32) -> ShapeHit {
    var hit = no_hit();
    if !(finite(t0) && finite(t1)) || t0 >= t1 {
        return hit;
    }
    let resolution = max((t1 - t0) * (1.0 / 16777216.0), 8.0 * F32_EPSILON * max(abs(t0), abs(t1)));
    var lo: array<f32, 26>;
    var hi: array<f32, 26>;
    var f_lo: array<f32, 26>;
    var f_hi: array<f32, 26>;
    var level: array<u32, 26>;
    lo[0] = t0;
    hi[0] = t1;
    f_lo[0] = rf_value(f, t0);
    f_hi[0] = rf_value(f, t1);
    level[0] = 0u;
    var top = 1u;
    var budget = SOLVE_BUDGET;
    while top > 0u {
        top -= 1u;
        let a = lo[top];
        let b = hi[top];
        let fa = f_lo[top];
        let fb = f_hi[top];
        let depth = level[top];
        if budget > 0u {
            budget -= 1u;
            let e = rf_enclose(f, a, b);
            if e.lo > 0.0 || e.hi < 0.0 {
                continue;
            }
            if e.slope == 0 && b - a > resolution && depth < SOLVE_DEPTH {
                let m = 0.5 * (a + b);
                let fm = rf_value(f, m);
                // The far half below the near one, so the near half comes out first.
                lo[top] = m;
                hi[top] = b;
                f_lo[top] = fm;
                f_hi[top] = fb;
                level[top] = depth + 1u;
                lo[top + 1u] = a;
                hi[top + 1u] = m;
                f_lo[top + 1u] = fa;
                f_hi[top + 1u] = fm;
                level[top + 1u] = depth + 1u;
                top += 2u;
                continue;
            }
        }
        if inside(fa) != inside(fb) {
            let t = refine_crossing(f, a, b, fa, fb);
            if t > 0.0 {
                hit.found = true;
                hit.t = t;
                return hit;
            }
        }
    }
    return hit;
}

// ---- the superellipsoid (glint_core::shape::superellipsoid) ----

// g = (|x|^(2/e2) + |z|^(2/e2))^(e2/e1) + |y|^(2/e1), inside g ≤ 1, within [−1, 1]³;
// f = g^(e1/2) − 1 keeps the values well scaled for any exponent.
const SUPERELLIPSOID_MARGIN: f32 = 1e-4;

fn superellipsoid_exponents(index: u32) -> vec2<f32> {
    let at = params.superellipsoid_offset + 2u * index;
    return vec2<f32>(floats[at], floats[at + 1u]);
}

// x^y for x ≥ 0 and y > 0, with 0^y = 0 whatever the driver's pow does at 0.
fn pow_positive(x: f32, y: f32) -> f32 {
    return select(pow(x, y), 0.0, x <= 0.0);
}

// f at a point given by its absolute coordinates.
fn superellipsoid_value(index: u32, a: vec3<f32>) -> f32 {
    let e = superellipsoid_exponents(index);
    let ring = pow_positive(a.x, 2.0 / e.y) + pow_positive(a.z, 2.0 / e.y);
    let g = pow_positive(ring, e.y / e.x) + pow_positive(a.y, 2.0 / e.x);
    return pow_positive(g, 0.5 * e.x) - 1.0;
}

fn superellipsoid_enclose(f: RayFunction, a: f32, b: f32) -> Enclosure {
    let pa = f.o + a * f.d;
    let pb = f.o + b * f.d;
    let c_lo = min(pa, pb);
    let c_hi = max(pa, pb);
    // |c| over the piece: f grows with every |coordinate|, so its range comes from the
    // corners nearest to and farthest from the axis planes.
    let straddles = (c_lo < vec3<f32>(0.0)) & (c_hi > vec3<f32>(0.0));
    let abs_lo = select(min(abs(c_lo), abs(c_hi)), vec3<f32>(0.0), straddles);
    let abs_hi = max(abs(c_lo), abs(c_hi));
    let v_lo = superellipsoid_value(f.index, abs_lo);
    let v_hi = superellipsoid_value(f.index, abs_hi);
    // Widened for the rounding of pow and of the corners in f32.
    let slack = 1e-5 * (1.0 + max(abs(v_lo), abs(v_hi)));
    // df/dt = Σ ∂f/∂cᵢ·dᵢ, and ∂f/∂cᵢ has the sign of cᵢ.
    var rising = false;
    var falling = false;
    var unknown = false;
    for (var axis = 0u; axis < 3u; axis += 1u) {
        let d = f.d[axis];
        if d == 0.0 {
            continue;
        }
        if straddles[axis] || c_lo[axis] == 0.0 || c_hi[axis] == 0.0 {
            unknown = true;
        } else if (c_lo[axis] > 0.0) == (d > 0.0) {
            rising = true;
        } else {
            falling = true;
        }
    }
    var slope = 0;
    if rising && !falling && !unknown {
        slope = 1;
    } else if falling && !rising && !unknown {
        slope = -1;
    }
    return Enclosure(v_lo - slack, v_hi + slack, slope);
}

fn intersect_superellipsoid(index: u32, r: Ray, t_max: f32) -> ShapeHit {
    let b = box_span(r, vec3<f32>(-1.0 - SUPERELLIPSOID_MARGIN), vec3<f32>(1.0 + SUPERELLIPSOID_MARGIN));
    if !b.found {
        return no_hit();
    }
    let f = RayFunction(KIND_SUPERELLIPSOID, index, r.origin, r.dir);
    var hit = solve_first(f, max(b.span.enter, 0.0), min(b.span.exit, t_max));
    hit.found = hit.found && hit.t < t_max;
    return hit;
}

// ∇g, pointing out of the solid; the point itself where the gradient vanishes.
fn superellipsoid_surface(index: u32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let p = ray_at(r, hit.t);
    let e = superellipsoid_exponents(index);
    let ring = pow_positive(abs(p.x), 2.0 / e.y) + pow_positive(abs(p.z), 2.0 / e.y);
    var ring_slope = 0.0;
    if ring > 0.0 {
        ring_slope = (e.y / e.x) * pow(ring, e.y / e.x - 1.0);
    }
    let g = vec3<f32>(
        ring_slope * superellipsoid_term(p.x, e.y),
        superellipsoid_term(p.y, e.x),
        ring_slope * superellipsoid_term(p.z, e.y),
    );
    var normal = p;
    if finite3(g) && dot(g, g) > 0.0 {
        normal = g;
    }
    return SurfacePoint(p, normal, box_uv(p, vec3<f32>(-1.0), vec3<f32>(1.0)));
}

// d(|c|^(2/e))/dc.
fn superellipsoid_term(c: f32, e: f32) -> f32 {
    if c == 0.0 {
        return 0.0;
    }
    return sign(c) * (2.0 / e) * pow(abs(c), 2.0 / e - 1.0);
}
