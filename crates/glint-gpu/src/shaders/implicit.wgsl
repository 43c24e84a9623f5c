// Surfaces without a closed-form ray parameter, found by interval bisection
// (glint_core::shape::implicit::solve) in f32: the segment is bisected, nearest half
// first; a piece is dropped only when the enclosure of f over it excludes 0, and a
// piece on which f is monotonic holds a crossing exactly when its ends differ in sign,
// which is then refined inside its bracket. Each shape supplies f(t) and an enclosure
// of f and of the sign of df/dt over [a, b] (`RayFunction`); the superellipsoid is the
// first.

// Whether the scene has shapes solved numerically (superellipsoids, implicit surfaces,
// blobs), set per pipeline (render.rs): without them the driver drops this code from
// the kernels. On lavapipe that matters beyond size: it runs code that no lane takes
// with every lane masked off, and each loop so passed counts towards its cap of
// 65 535 loop iterations per invocation (`Gpu::caps_loop_iterations`).
override SOLVED_SHAPES: bool = true;
// Which of them it has: the solver is one function for the three (a copy per shape
// multiplied lavapipe's compile time), and these keep the others' code, loops
// included, out of its every step.
override IMPLICITS: bool = true;
override BLOBS: bool = true;
// The same for the other shapes whose code holds loops (render.rs `specialization`).
override MESHES: bool = true;
override QUADRICS: bool = true;
override TORI: bool = true;
override CSG_SHAPES: bool = true;

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
    let p = f.o + t * f.d;
    if IMPLICITS && f.kind == KIND_IMPLICIT {
        return implicit_value(implicit_record(f.index), p);
    }
    if BLOBS && f.kind == KIND_BLOB {
        return blob_value(blob_record(f.index), p);
    }
    return superellipsoid_value(f.index, abs(p));
}

fn rf_enclose(f: RayFunction, a: f32, b: f32) -> Enclosure {
    if IMPLICITS && f.kind == KIND_IMPLICIT {
        return implicit_enclosure(f, a, b);
    }
    if BLOBS && f.kind == KIND_BLOB {
        return blob_enclosure(f, a, b);
    }
    return superellipsoid_enclose(f, a, b);
}

const F32_EPSILON: f32 = 1.1920929e-7;
const TAU: f32 = 6.28318530717959;

// Inside is f < 0; NaN counts as outside, as on the CPU.
fn inside(v: f32) -> bool {
    return v < 0.0;
}

// Bisection levels at most: 2⁻²⁴ of the segment is an f32's resolution.
const SOLVE_DEPTH: u32 = 24u;
// Enclosures evaluated for one ray at most; past the budget, pieces are checked for a
// sign change at their ends only, so the search always ends.
const SOLVE_BUDGET: u32 = 16384u;

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

// What `solve` found: the first crossing after t = 0, or, for CSG, every crossing
// paired into spans (glint_core::shape::span::pair_crossings) — an entering crossing
// opens a span, the next leaving one closes it, and a span still open at the end is
// left for the caller to close.
struct Crossings {
    first: ShapeHit,
    spans: SpanList,
    open: bool,
    open_t: f32,
    open_part: u32,
}

// The first sign change of f in [t0, t1] after t = 0, as a hit.
fn solve_first(f: RayFunction, t0: f32, t1: f32) -> ShapeHit {
    return solve(f, t0, t1, false, false, 0.0, 0u).first;
}

// Every crossing of f in [t0, t1] paired into spans of surface part 0; `starts_inside`
// opens a span at t0 with part `part0` (a box face where f is negative on the box).
fn solve_spans(f: RayFunction, t0: f32, t1: f32, starts_inside: bool, part0: u32) -> Crossings {
    return solve(f, t0, t1, true, starts_inside, t0, part0);
}

// glint_core::shape::implicit::solve::crossings, nearest first: all of them (`all`) or
// up to the first after t = 0.
fn solve(f: RayFunction, t0: f32, t1: f32, all: bool, starts_inside: bool, open_t: f32, open_part: u32) -> Crossings {
    var c = Crossings(no_hit(), span_list(), starts_inside, open_t, open_part);
    // Pushed through a local: naga's SPIR-V writer fails on a pointer into `c`.
    var spans: SpanList;
    if !(finite(t0) && finite(t1)) || t0 >= t1 {
        return c;
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
    while top > 0u && !c.first.found {
        top -= 1u;
        let a = lo[top];
        let b = hi[top];
        let fa = f_lo[top];
        let fb = f_hi[top];
        let depth = level[top];
        // Whether the piece is settled: no root (pruned), or one iff its ends differ.
        var settle = true;
        var pruned = false;
        if budget > 0u {
            budget -= 1u;
            let e = rf_enclose(f, a, b);
            pruned = e.lo > 0.0 || e.hi < 0.0;
            settle = pruned || e.slope != 0 || !(b - a > resolution) || depth >= SOLVE_DEPTH;
        }
        if !settle {
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
        } else if !pruned && inside(fa) != inside(fb) {
            let t = refine_crossing(f, a, b, fa, fb);
            if !all {
                c.first.found = t > 0.0;
                c.first.t = t;
            } else if inside(fb) {
                c.open = true;
                c.open_t = t;
                c.open_part = 0u;
            } else {
                if c.open && c.open_t < t {
                    spans = c.spans;
                    push_span(&spans, Span(c.open_t, c.open_part, t, 0u));
                    c.spans = spans;
                }
                c.open = false;
            }
        }
    }
    return c;
}

// The box a solved shape is searched in: an implicit surface's and a blob's own, the
// superellipsoid's [−1, 1]³ with a margin.
struct SolvedBox {
    lo: vec3<f32>,
    hi: vec3<f32>,
}

fn solved_box(kind: u32, index: u32) -> SolvedBox {
    if IMPLICITS && kind == KIND_IMPLICIT {
        let rec = implicit_record(index);
        return SolvedBox(rec.lo, rec.hi);
    }
    if BLOBS && kind == KIND_BLOB {
        let blob = blob_record(index);
        return SolvedBox(blob.lo, blob.hi);
    }
    return SolvedBox(vec3<f32>(-1.0 - SUPERELLIPSOID_MARGIN), vec3<f32>(1.0 + SUPERELLIPSOID_MARGIN));
}

// The nearest hit on a superellipsoid, implicit surface or blob. One function for the
// three, so a kernel holds one copy of the solver: Mesa inlines every call, and a
// copy per shape multiplied lavapipe's compile time (IMPLICITS and BLOBS above keep
// it as lean as one shape's where the scene has one kind). An implicit surface whose
// function is negative on its box's faces is bounded by them (glint_core's
// ImplicitShape::intersect).
fn intersect_solved(kind: u32, index: u32, r: Ray, t_max: f32) -> ShapeHit {
    let bx = solved_box(kind, index);
    let b = box_span(r, bx.lo, bx.hi);
    if !b.found {
        return no_hit();
    }
    let f = RayFunction(kind, index, r.origin, r.dir);
    let faces = IMPLICITS && kind == KIND_IMPLICIT;
    let enter = b.span.enter;
    let exit = b.span.exit;
    if faces && enter > 0.0 && enter < t_max && inside(rf_value(f, enter)) {
        // Entering the box where f is negative: the box face is the surface.
        return ShapeHit(true, enter, b.span.enter_part, vec3<f32>(0.0));
    }
    var hit = solve_first(f, max(enter, 0.0), min(exit, t_max));
    hit.found = hit.found && hit.t < t_max;
    if faces && !hit.found && exit > 0.0 && exit < t_max && inside(rf_value(f, exit)) {
        // Started inside and found no surface before the box: leave through its face.
        hit = ShapeHit(true, exit, b.span.exit_part, vec3<f32>(0.0));
    }
    return hit;
}

// A solved shape's spans along the whole line (Solid::spans), for CSG: every crossing
// inside its box, and for an implicit surface the box faces where its function is
// negative there, as on the CPU. One function for the three, as above.
fn solved_spans(kind: u32, index: u32, r: Ray) -> SpanList {
    let bx = solved_box(kind, index);
    let b = box_span(r, bx.lo, bx.hi);
    if !b.found {
        return span_list();
    }
    let f = RayFunction(kind, index, r.origin, r.dir);
    let faces = IMPLICITS && kind == KIND_IMPLICIT;
    let enter = b.span.enter;
    let exit = b.span.exit;
    let c = solve_spans(f, enter, exit, faces && inside(rf_value(f, enter)), b.span.enter_part);
    var spans = c.spans;
    if faces && c.open && c.open_t < exit {
        push_span(&spans, Span(c.open_t, c.open_part, exit, b.span.exit_part));
    }
    return spans;
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

// ---- implicit surfaces (glint_core::shape::implicit): bytecode on a stack ----
//
// A program is the CPU's postfix ImplicitOp records, stored as word pairs (opcode, the
// constant's bits). One interpreter per number type: f32 values, value-and-gradient
// duals for normals, and dual intervals (ranges of f and of df/dt) for the solver —
// three loops of the same shape, as WGSL has no generics to write one (the CPU's
// `bytecode::run` is one generic function).
// Interval ends are widened outwards after every operation by the f32 rounding (and by
// WGSL's stated accuracy for exp, sin and cos), so an enclosure holds every value the
// exact function takes; only pruning gets less sharp.

const OP_CONST: u32 = 0u;
const OP_X: u32 = 1u;
const OP_Y: u32 = 2u;
const OP_Z: u32 = 3u;
const OP_ADD: u32 = 4u;
const OP_SUB: u32 = 5u;
const OP_MUL: u32 = 6u;
const OP_DIV: u32 = 7u;
const OP_NEG: u32 = 8u;
const OP_POWI: u32 = 9u;
const OP_RECIP: u32 = 10u;
const OP_SQRT: u32 = 11u;
const OP_ABS: u32 = 12u;
const OP_SIN: u32 = 13u;
const OP_COS: u32 = 14u;
const OP_EXP: u32 = 15u;
const OP_MIN: u32 = 16u;
const OP_MAX: u32 = 17u;
// glint_core::shape::implicit::bytecode::MAX_STACK.
const IMPLICIT_STACK: u32 = 32u;
// Words per implicit record: min, max and the Lipschitz bound as float bits, the first
// word of its program, its length. (Integers are kept in the word array: stored as
// floats, small ones would be denormals, which a device may flush to zero.)
const IMPLICIT_WORDS: u32 = 9u;

struct ImplicitRecord {
    lo: vec3<f32>,
    hi: vec3<f32>,
    lipschitz: f32,
    // Word index of the first (opcode, argument) pair, and the number of pairs.
    first: u32,
    len: u32,
}

fn implicit_record(index: u32) -> ImplicitRecord {
    let at = params.implicit_offset + IMPLICIT_WORDS * index;
    let f = bitcast<vec4<f32>>(vec4<u32>(words[at], words[at + 1u], words[at + 2u], words[at + 3u]));
    let g = bitcast<vec3<f32>>(vec3<u32>(words[at + 4u], words[at + 5u], words[at + 6u]));
    return ImplicitRecord(f.xyz, vec3<f32>(f.w, g.x, g.y), g.z, words[at + 7u], words[at + 8u]);
}

fn powi(x: f32, n: u32) -> f32 {
    var result = 1.0;
    var base = x;
    var e = n;
    while e > 0u {
        if (e & 1u) != 0u {
            result *= base;
        }
        base *= base;
        e >>= 1u;
    }
    return result;
}

// f at `p` (glint_core::shape::implicit::bytecode::value).
fn implicit_value(rec: ImplicitRecord, p: vec3<f32>) -> f32 {
    var stack: array<f32, IMPLICIT_STACK>;
    var top = 0u;
    for (var i = 0u; i < rec.len; i += 1u) {
        let code = words[rec.first + 2u * i];
        let arg = bitcast<f32>(words[rec.first + 2u * i + 1u]);
        let kind = op_kind(code);
        if kind == PUSH {
            stack[top] = select(arg, p[min(code, 3u) - 1u], code != OP_CONST);
            top += 1u;
        }
        if kind == BINARY {
            top -= 1u;
            let a = stack[top - 1u];
            let b = stack[top];
            var v = a + b;
            if code == OP_SUB {
                v = a - b;
            }
            if code == OP_MUL {
                v = a * b;
            }
            if code == OP_DIV {
                v = a / b;
            }
            if code == OP_MIN {
                v = min(a, b);
            }
            if code == OP_MAX {
                v = max(a, b);
            }
            stack[top - 1u] = v;
        }
        if kind == UNARY {
            let a = stack[top - 1u];
            var v = -a;
            if code == OP_POWI {
                v = powi(a, u32(arg));
            }
            if code == OP_RECIP {
                v = 1.0 / a;
            }
            if code == OP_SQRT {
                v = sqrt(max(a, 0.0));
            }
            if code == OP_ABS {
                v = abs(a);
            }
            if code == OP_SIN {
                v = sin(a);
            }
            if code == OP_COS {
                v = cos(a);
            }
            if code == OP_EXP {
                v = exp(a);
            }
            stack[top - 1u] = v;
        }
    }
    return stack[0];
}

// How an instruction uses the stack.
const PUSH: u32 = 0u;
const BINARY: u32 = 1u;
const UNARY: u32 = 2u;

fn op_kind(code: u32) -> u32 {
    if code <= OP_Z {
        return PUSH;
    }
    let binary = code == OP_ADD || code == OP_SUB || code == OP_MUL || code == OP_DIV || code == OP_MIN || code == OP_MAX;
    return select(UNARY, BINARY, binary);
}

// f and ∇f at `p` (forward-mode duals: value in w, gradient in xyz).
fn implicit_gradient(rec: ImplicitRecord, p: vec3<f32>) -> vec4<f32> {
    var stack: array<vec4<f32>, IMPLICIT_STACK>;
    var top = 0u;
    for (var i = 0u; i < rec.len; i += 1u) {
        let code = words[rec.first + 2u * i];
        let arg = bitcast<f32>(words[rec.first + 2u * i + 1u]);
        let kind = op_kind(code);
        if kind == PUSH {
            var v = vec4<f32>(0.0, 0.0, 0.0, arg);
            if code != OP_CONST {
                let axis = min(code, 3u) - 1u;
                v = vec4<f32>(0.0, 0.0, 0.0, p[axis]);
                v[axis] = 1.0;
            }
            stack[top] = v;
            top += 1u;
        }
        if kind == BINARY {
            top -= 1u;
            let a = stack[top - 1u];
            let b = stack[top];
            var v = a + b;
            if code == OP_SUB {
                v = a - b;
            }
            if code == OP_MUL {
                v = vec4<f32>(a.xyz * b.w + b.xyz * a.w, a.w * b.w);
            }
            if code == OP_DIV {
                let q = a.w / b.w;
                v = vec4<f32>((a.xyz - b.xyz * q) / b.w, q);
            }
            if code == OP_MIN {
                v = select(a, b, b.w < a.w);
            }
            if code == OP_MAX {
                v = select(a, b, b.w > a.w);
            }
            stack[top - 1u] = v;
        }
        if kind == UNARY {
            let a = stack[top - 1u];
            // The chain rule: the new value and the slope at a.
            var value = -a.w;
            var slope = -1.0;
            if code == OP_POWI {
                let n = u32(arg);
                value = powi(a.w, n);
                slope = select(f32(n) * powi(a.w, max(n, 1u) - 1u), 0.0, n == 0u);
            }
            if code == OP_RECIP {
                value = 1.0 / a.w;
                slope = -value * value;
            }
            if code == OP_SQRT {
                value = sqrt(max(a.w, 0.0));
                slope = select(0.0, 0.5 / value, a.w > 0.0);
            }
            if code == OP_ABS {
                value = abs(a.w);
                slope = select(1.0, -1.0, a.w < 0.0);
            }
            if code == OP_SIN {
                value = sin(a.w);
                slope = cos(a.w);
            }
            if code == OP_COS {
                value = cos(a.w);
                slope = -sin(a.w);
            }
            if code == OP_EXP {
                value = exp(a.w);
                slope = value;
            }
            stack[top - 1u] = vec4<f32>(a.xyz * slope, value);
        }
    }
    return stack[0];
}

// ---- intervals [x, y] ----

const ENTIRE = vec2<f32>(-INF, INF);
const SMALLEST_NORMAL: f32 = 1.17549435e-38;

// [lo, hi] widened by `ulps` units of f32 rounding on each side.
fn widen(lo: f32, hi: f32, ulps: f32) -> vec2<f32> {
    return vec2<f32>(lo - (abs(lo) * ulps * F32_EPSILON + SMALLEST_NORMAL), hi + (abs(hi) * ulps * F32_EPSILON + SMALLEST_NORMAL));
}

fn iv_contains_zero(a: vec2<f32>) -> bool {
    return !(a.x > 0.0 || a.y < 0.0);
}

fn iv_add(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return widen(a.x + b.x, a.y + b.y, 1.0);
}

fn iv_sub(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return widen(a.x - b.y, a.y - b.x, 1.0);
}

// A product end; 0 times anything (an infinite end too) is 0.
fn mul_end(a: f32, b: f32) -> f32 {
    return select(a * b, 0.0, a == 0.0 || b == 0.0);
}

fn iv_mul(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    let p = vec4<f32>(mul_end(a.x, b.x), mul_end(a.x, b.y), mul_end(a.y, b.x), mul_end(a.y, b.y));
    return widen(min(min(p.x, p.y), min(p.z, p.w)), max(max(p.x, p.y), max(p.z, p.w)), 1.0);
}

fn iv_recip(a: vec2<f32>) -> vec2<f32> {
    if iv_contains_zero(a) {
        return ENTIRE;
    }
    return widen(1.0 / a.y, 1.0 / a.x, 1.0);
}

fn iv_powi(a: vec2<f32>, n: u32) -> vec2<f32> {
    if n == 0u {
        return vec2<f32>(1.0);
    }
    let ulps = f32(min(n, 64u));
    if n % 2u == 1u || a.x >= 0.0 {
        return widen(powi(a.x, n), powi(a.y, n), ulps);
    }
    if a.y <= 0.0 {
        return widen(powi(a.y, n), powi(a.x, n), ulps);
    }
    let w = widen(0.0, powi(max(-a.x, a.y), n), ulps);
    return vec2<f32>(max(w.x, 0.0), w.y);
}

fn iv_abs(a: vec2<f32>) -> vec2<f32> {
    if a.x >= 0.0 {
        return a;
    }
    if a.y <= 0.0 {
        return -a.yx;
    }
    return vec2<f32>(0.0, max(-a.x, a.y));
}

// WGSL promises exp within 3 + 2·|x| ulps.
fn iv_exp(a: vec2<f32>) -> vec2<f32> {
    let w = widen(exp(a.x), exp(a.y), 3.0 + 2.0 * max(abs(a.x), abs(a.y)));
    return vec2<f32>(max(w.x, 0.0), w.y);
}

// sin (crest π/2) or cos (crest 0) over an interval: the ends, and ±1 where a crest or
// trough lies inside; widened by WGSL's stated absolute error, 2⁻¹¹.
fn iv_periodic(a: vec2<f32>, is_sin: bool) -> vec2<f32> {
    let width = a.y - a.x;
    if !(width < TAU) || max(abs(a.x), abs(a.y)) > 1e5 {
        return vec2<f32>(-1.0, 1.0);
    }
    var e = vec2<f32>(cos(a.x), cos(a.y));
    var crest = 0.0;
    if is_sin {
        e = vec2<f32>(sin(a.x), sin(a.y));
        crest = 0.5 * PI;
    }
    var lo = min(e.x, e.y);
    var hi = max(e.x, e.y);
    let slack = 1e-5 * (1.0 + max(abs(a.x), abs(a.y)));
    for (var k = 0u; k < 2u; k += 1u) {
        let phase = crest + f32(k) * PI;
        let x = phase + ceil((a.x - phase) / TAU) * TAU;
        if x <= a.y + slack || x - TAU >= a.x - slack {
            if k == 0u {
                hi = 1.0;
            } else {
                lo = -1.0;
            }
        }
    }
    let err = 1.0 / 2048.0;
    return vec2<f32>(max(lo - err, -1.0), min(hi + err, 1.0));
}

// ---- dual intervals: ranges of a value (xy) and of its derivative in t (zw) ----

fn di(v: vec2<f32>, d: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(v, d);
}

fn di_mul(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return di(iv_mul(a.xy, b.xy), iv_add(iv_mul(a.xy, b.zw), iv_mul(a.zw, b.xy)));
}

fn di_recip(a: vec4<f32>) -> vec4<f32> {
    let r = iv_recip(a.xy);
    return di(r, iv_mul(-a.wz, iv_mul(r, r)));
}

fn di_both_signs(d: vec2<f32>) -> vec2<f32> {
    let m = max(abs(d.x), abs(d.y));
    return vec2<f32>(-m, m);
}

// The minimum (`is_max` false) or maximum of two dual intervals.
fn di_extreme(a: vec4<f32>, b: vec4<f32>, is_max: bool) -> vec4<f32> {
    let a_wins = select((a.y < b.x), (a.x > b.y), is_max);
    let b_wins = select((b.y < a.x), (b.x > a.y), is_max);
    if a_wins {
        return a;
    }
    if b_wins {
        return b;
    }
    var v = vec2<f32>(min(a.x, b.x), min(a.y, b.y));
    if is_max {
        v = vec2<f32>(max(a.x, b.x), max(a.y, b.y));
    }
    return di(v, vec2<f32>(min(a.z, b.z), max(a.w, b.w)));
}

fn di_unary(code: u32, arg: f32, a: vec4<f32>) -> vec4<f32> {
    var r = -a.yxwz;
    if code == OP_POWI {
        let n = u32(arg);
        r = di(vec2<f32>(1.0), vec2<f32>(0.0));
        if n > 0u {
            let d = iv_mul(iv_mul(vec2<f32>(f32(n)), iv_powi(a.xy, n - 1u)), a.zw);
            r = di(iv_powi(a.xy, n), d);
        }
    }
    if code == OP_RECIP {
        r = di_recip(a);
    }
    if code == OP_SQRT {
        let w = widen(sqrt(max(a.x, 0.0)), sqrt(max(a.y, 0.0)), 1.0);
        let v = vec2<f32>(max(w.x, 0.0), w.y);
        var d = ENTIRE;
        if a.x > 0.0 {
            d = iv_mul(a.zw, iv_recip(iv_mul(vec2<f32>(2.0), v)));
        }
        r = di(v, d);
    }
    if code == OP_ABS {
        r = di(iv_abs(a.xy), di_both_signs(a.zw));
        if a.x > 0.0 {
            r = a;
        }
        if a.y < 0.0 {
            r = -a.yxwz;
        }
    }
    if code == OP_SIN {
        r = di(iv_periodic(a.xy, true), iv_mul(iv_periodic(a.xy, false), a.zw));
    }
    if code == OP_COS {
        r = di(iv_periodic(a.xy, false), iv_mul(-iv_periodic(a.xy, true).yx, a.zw));
    }
    if code == OP_EXP {
        let v = iv_exp(a.xy);
        r = di(v, iv_mul(v, a.zw));
    }
    return r;
}

// Enclosures of f(o + t·d) and of df/dt over t in [a, b]
// (glint_core::shape::implicit::bytecode::enclose_along).
fn implicit_enclose(rec: ImplicitRecord, o: vec3<f32>, dir: vec3<f32>, a: f32, b: f32) -> vec4<f32> {
    var stack: array<vec4<f32>, IMPLICIT_STACK>;
    var top = 0u;
    for (var i = 0u; i < rec.len; i += 1u) {
        let code = words[rec.first + 2u * i];
        let arg = bitcast<f32>(words[rec.first + 2u * i + 1u]);
        let kind = op_kind(code);
        if kind == PUSH {
            var v = di(vec2<f32>(arg), vec2<f32>(0.0));
            if code != OP_CONST {
                let axis = min(code, 3u) - 1u;
                let ends = vec2<f32>(o[axis] + mul_end(a, dir[axis]), o[axis] + mul_end(b, dir[axis]));
                v = di(widen(min(ends.x, ends.y), max(ends.x, ends.y), 1.0), vec2<f32>(dir[axis]));
            }
            stack[top] = v;
            top += 1u;
        }
        if kind == BINARY {
            top -= 1u;
            let x = stack[top - 1u];
            let y = stack[top];
            var v = di(iv_add(x.xy, y.xy), iv_add(x.zw, y.zw));
            if code == OP_SUB {
                v = di(iv_sub(x.xy, y.xy), iv_sub(x.zw, y.zw));
            }
            if code == OP_MUL {
                v = di_mul(x, y);
            }
            if code == OP_DIV {
                v = di_mul(x, di_recip(y));
            }
            if code == OP_MIN || code == OP_MAX {
                v = di_extreme(x, y, code == OP_MAX);
            }
            stack[top - 1u] = v;
        }
        if kind == UNARY {
            stack[top - 1u] = di_unary(code, arg, stack[top - 1u]);
        }
    }
    return stack[0];
}

// The solver's enclosure of an implicit f over [a, b]: interval arithmetic, tightened
// where the user gave a Lipschitz bound L by the mean-value form
// |f(t) − f(m)| ≤ L·|d|·|t − m|.
fn implicit_enclosure(f: RayFunction, a: f32, b: f32) -> Enclosure {
    let rec = implicit_record(f.index);
    let e = implicit_enclose(rec, f.o, f.d, a, b);
    var v = e.xy;
    if rec.lipschitz > 0.0 {
        let m = 0.5 * (a + b);
        let reach = rec.lipschitz * length(f.d) * 0.5 * (b - a);
        let fm = rf_value(f, m);
        let meet = vec2<f32>(max(v.x, fm - reach), min(v.y, fm + reach));
        // Keep the plain enclosure if rounding made them disjoint.
        if finite(fm) && meet.x <= meet.y {
            v = meet;
        }
    }
    var slope = 0;
    if e.z > 0.0 {
        slope = 1;
    } else if e.w < 0.0 {
        slope = -1;
    }
    return Enclosure(v.x, v.y, slope);
}

// The hit point moved onto the surface by one Newton step (refused when it is not
// small against the box), and the gradient there as the normal.
fn implicit_surface(index: u32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let rec = implicit_record(index);
    let p = ray_at(r, hit.t);
    if hit.part >= BOX_FACE {
        return box_face_point(hit.part, p, rec.lo, rec.hi);
    }
    let g = implicit_gradient(rec, p);
    let step = g.xyz * (g.w / dot(g.xyz, g.xyz));
    let size = max(max(rec.hi.x - rec.lo.x, rec.hi.y - rec.lo.y), rec.hi.z - rec.lo.z);
    var point = p;
    if finite3(step) && length(step) < 1e-4 * size {
        point = p - step;
    }
    var normal = implicit_gradient(rec, point).xyz;
    if !(finite3(normal) && dot(normal, normal) > 0.0) {
        normal = g.xyz;
    }
    if !(finite3(normal) && dot(normal, normal) > 0.0) {
        normal = -r.dir;
    }
    return SurfacePoint(point, normal, box_uv(point, rec.lo, rec.hi));
}

// ---- blobs (glint_core::shape::blob) ----
//
// The CPU isolates the roots of the field's quartic pieces; the GPU solves the same
// surface with the interval solver: f = threshold − Σ fields (inside where the fields
// exceed the threshold), each field s·(1 − r²)² within its capsule's reach, whose
// range over a piece follows from the range of r², exact for a linear ray.

// Words per blob record: min, max and threshold as float bits, the float index of its
// first component, the component count.
const BLOB_WORDS: u32 = 9u;
// Floats per component: component_from_blob (3 columns), offset, strength, half length.
const COMPONENT_FLOATS: u32 = 14u;

struct BlobRecord {
    lo: vec3<f32>,
    hi: vec3<f32>,
    threshold: f32,
    first: u32,
    count: u32,
}

fn blob_record(index: u32) -> BlobRecord {
    let at = params.blob_offset + BLOB_WORDS * index;
    let f = bitcast<vec4<f32>>(vec4<u32>(words[at], words[at + 1u], words[at + 2u], words[at + 3u]));
    let g = bitcast<vec3<f32>>(vec3<u32>(words[at + 4u], words[at + 5u], words[at + 6u]));
    return BlobRecord(f.xyz, vec3<f32>(f.w, g.x, g.y), g.z, words[at + 7u], words[at + 8u]);
}

struct BlobComponent {
    m: mat3x3<f32>,
    offset: vec3<f32>,
    strength: f32,
    half_length: f32,
}

fn blob_component(at: u32) -> BlobComponent {
    let c = array<f32, 14>(
        floats[at], floats[at + 1u], floats[at + 2u], floats[at + 3u], floats[at + 4u], floats[at + 5u],
        floats[at + 6u], floats[at + 7u], floats[at + 8u], floats[at + 9u], floats[at + 10u], floats[at + 11u],
        floats[at + 12u], floats[at + 13u],
    );
    let m = mat3x3<f32>(vec3<f32>(c[0], c[1], c[2]), vec3<f32>(c[3], c[4], c[5]), vec3<f32>(c[6], c[7], c[8]));
    return BlobComponent(m, vec3<f32>(c[9], c[10], c[11]), c[12], c[13]);
}

// From a component-space point to its capsule's segment: the radial vector.
fn capsule_radial(c: BlobComponent, q: vec3<f32>) -> vec3<f32> {
    return q - vec3<f32>(0.0, clamp(q.y, -c.half_length, c.half_length), 0.0);
}

// threshold − Σ fields at a blob-space point.
fn blob_value(blob: BlobRecord, p: vec3<f32>) -> f32 {
    var sum = 0.0;
    for (var k = 0u; k < blob.count; k += 1u) {
        let c = blob_component(blob.first + COMPONENT_FLOATS * k);
        let r2 = dot(capsule_radial(c, c.m * p + c.offset), capsule_radial(c, c.m * p + c.offset));
        if r2 < 1.0 {
            sum += c.strength * (1.0 - r2) * (1.0 - r2);
        }
    }
    return blob.threshold - sum;
}

// ∇ Σ fields (pointing inward): −4s·(1 − r²)·Mᵀ(q − c) per component.
fn blob_gradient(blob: BlobRecord, p: vec3<f32>) -> vec3<f32> {
    var g = vec3<f32>(0.0);
    for (var k = 0u; k < blob.count; k += 1u) {
        let c = blob_component(blob.first + COMPONENT_FLOATS * k);
        let radial = capsule_radial(c, c.m * p + c.offset);
        let r2 = dot(radial, radial);
        if r2 < 1.0 {
            g += (transpose(c.m) * radial) * (-4.0 * c.strength * (1.0 - r2));
        }
    }
    return g;
}

// The range of x² for x in `a`.
fn iv_square(a: vec2<f32>) -> vec2<f32> {
    return iv_powi(a, 2u);
}

// Enclosures of threshold − Σ fields and of its t-derivative over t in [a, b].
fn blob_enclosure(f: RayFunction, a: f32, b: f32) -> Enclosure {
    let blob = blob_record(f.index);
    var value = vec2<f32>(0.0);
    var slope = vec2<f32>(0.0);
    for (var k = 0u; k < blob.count; k += 1u) {
        let c = blob_component(blob.first + COMPONENT_FLOATS * k);
        let q0 = c.m * (f.o + a * f.d) + c.offset;
        let q1 = c.m * (f.o + b * f.d) + c.offset;
        let dq = c.m * f.d;
        let x = widen(min(q0.x, q1.x), max(q0.x, q1.x), 2.0);
        let y = widen(min(q0.y, q1.y), max(q0.y, q1.y), 2.0);
        let z = widen(min(q0.z, q1.z), max(q0.z, q1.z), 2.0);
        // Past the segment's ends along y: max(|y| − h, 0), signed like y.
        let ay = iv_abs(y);
        let excess = vec2<f32>(max(ay.x - c.half_length, 0.0), max(ay.y - c.half_length, 0.0));
        let r2 = iv_add(iv_add(iv_square(x), iv_square(z)), iv_square(excess));
        if r2.x >= 1.0 {
            continue;
        }
        let w = vec2<f32>(1.0 - min(r2.y, 1.0), 1.0 - r2.x);
        let field = iv_mul(vec2<f32>(c.strength), iv_mul(w, w));
        value = iv_add(value, field);
        // d(r²)/dt = 2(x·dx + z·dz + e·sign(y)·dy), e the excess.
        var ey = excess;
        if y.y <= 0.0 {
            ey = -excess.yx;
        } else if y.x < 0.0 {
            ey = vec2<f32>(-excess.y, excess.y);
        }
        let dr2 = iv_mul(vec2<f32>(2.0), iv_add(iv_add(iv_mul(x, vec2<f32>(dq.x)), iv_mul(z, vec2<f32>(dq.z))), iv_mul(ey, vec2<f32>(dq.y))));
        slope = iv_add(slope, iv_mul(iv_mul(vec2<f32>(-2.0 * c.strength), w), dr2));
    }
    let v = iv_sub(vec2<f32>(blob.threshold), value);
    var sign = 0;
    if slope.y < 0.0 {
        sign = 1;
    } else if slope.x > 0.0 {
        sign = -1;
    }
    return Enclosure(v.x, v.y, sign);
}

// One Newton step back onto the surface, then the outward normal −∇ Σ fields.
fn blob_surface(index: u32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let blob = blob_record(index);
    let p = ray_at(r, hit.t);
    let g = blob_gradient(blob, p);
    // The CPU's value is Σ − threshold, the negative of blob_value.
    let step = g * (-blob_value(blob, p) / dot(g, g));
    let size = max(max(blob.hi.x - blob.lo.x, blob.hi.y - blob.lo.y), blob.hi.z - blob.lo.z);
    var point = p;
    if finite3(step) && length(step) < 1e-4 * size {
        point = p - step;
    }
    var normal = -blob_gradient(blob, point);
    if !(finite3(normal) && dot(normal, normal) > 0.0) {
        normal = -r.dir;
    }
    return SurfacePoint(point, normal, box_uv(point, blob.lo, blob.hi));
}
