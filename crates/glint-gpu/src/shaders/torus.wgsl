// The torus of major radius 1 around the y axis (glint_core::shape::torus): a quartic
// in a unit-speed parameter from the ray's point nearest the centre, solved by
// Ferrari's method with Newton polish (glint_core::math::roots), in f32 where the CPU
// uses f64.

const KIND_TORUS: u32 = 6u;

struct Roots {
    count: u32,
    t: array<f32, 4>,
}

fn push_quadratic(out: ptr<function, Roots>, qa: f32, qb: f32, qc: f32) {
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 {
        return;
    }
    let s = sqrt(disc);
    let qq = -0.5 * (qb + select(s, -s, qb < 0.0));
    let n = (*out).count;
    if qq == 0.0 {
        (*out).t[n] = 0.0;
        (*out).t[n + 1u] = 0.0;
    } else {
        (*out).t[n] = qq / qa;
        (*out).t[n + 1u] = qc / qq;
    }
    (*out).count = n + 2u;
}

fn largest_cubic_root(b: f32, c: f32, d: f32) -> f32 {
    let p = c - b * b / 3.0;
    let q = 2.0 * b * b * b / 27.0 - b * c / 3.0 + d;
    let half_q = q / 2.0;
    let third_p = p / 3.0;
    let disc = half_q * half_q + third_p * third_p * third_p;
    var x = 0.0;
    if disc > 0.0 {
        let s = sqrt(disc);
        let u = -half_q + s;
        let v = -half_q - s;
        x = sign(u) * pow(abs(u), 1.0 / 3.0) + sign(v) * pow(abs(v), 1.0 / 3.0);
    } else if third_p != 0.0 {
        let rho = sqrt(-third_p);
        let cos_arg = clamp(-half_q / (rho * rho * rho), -1.0, 1.0);
        x = 2.0 * rho * cos(acos(cos_arg) / 3.0);
    }
    var m = x - b / 3.0;
    for (var i = 0; i < 2; i += 1) {
        let f = ((m + b) * m + c) * m + d;
        let df = (3.0 * m + 2.0 * b) * m + c;
        if df == 0.0 {
            break;
        }
        m -= f / df;
    }
    return m;
}

// Real roots of t⁴ + a·t³ + b·t² + c·t + d, ascending.
fn solve_quartic(a: f32, b: f32, c: f32, d: f32) -> Roots {
    let a2 = a * a;
    let p = b - 3.0 * a2 / 8.0;
    let q = c - a * b / 2.0 + a2 * a / 8.0;
    let r = d - a * c / 4.0 + a2 * b / 16.0 - 3.0 * a2 * a2 / 256.0;
    var roots = Roots(0u, array<f32, 4>(0.0, 0.0, 0.0, 0.0));
    if abs(q) < 1e-6 * (1.0 + abs(p) + abs(r)) {
        var z = Roots(0u, array<f32, 4>(0.0, 0.0, 0.0, 0.0));
        push_quadratic(&z, 1.0, p, r);
        for (var i = 0u; i < z.count; i += 1u) {
            if z.t[i] >= 0.0 {
                let y = sqrt(z.t[i]);
                roots.t[roots.count] = y;
                roots.t[roots.count + 1u] = -y;
                roots.count += 2u;
            }
        }
    } else {
        let m = max(largest_cubic_root(p, p * p / 4.0 - r, -q * q / 8.0), 1.1754944e-38);
        let s = sqrt(2.0 * m);
        let k = q / (2.0 * s);
        push_quadratic(&roots, 1.0, s, p / 2.0 + m - k);
        push_quadratic(&roots, 1.0, -s, p / 2.0 + m + k);
    }
    for (var i = 0u; i < roots.count; i += 1u) {
        var t = roots.t[i] - a / 4.0;
        for (var k = 0; k < 4; k += 1) {
            let slope = ((4.0 * t + 3.0 * a) * t + 2.0 * b) * t + c;
            if slope == 0.0 {
                break;
            }
            let step = ((((t + a) * t + b) * t + c) * t + d) / slope;
            if !finite(step) {
                break;
            }
            t -= step;
        }
        roots.t[i] = t;
    }
    // Insertion sort of at most four.
    for (var i = 1u; i < roots.count; i += 1u) {
        let v = roots.t[i];
        var j = i;
        while j > 0u && roots.t[j - 1u] > v {
            roots.t[j] = roots.t[j - 1u];
            j -= 1u;
        }
        roots.t[j] = v;
    }
    return roots;
}

// The torus's quartic along the ray, in the unit direction `u` from the point `p`
// nearest the centre (ray parameter t0): q(s) = s⁴ + c.x s³ + c.y s² + c.z s + c.w, where
// t = t0 + s / speed. `miss`: the ray passes outside the bounding sphere.
struct TorusQuartic {
    miss: bool,
    speed: f32,
    t0: f32,
    c: vec4<f32>,
}

fn torus_quartic(minor: f32, r: Ray) -> TorusQuartic {
    let speed = length(r.dir);
    let u = r.dir / speed;
    let t0 = -dot(r.origin, u) / speed;
    let p = r.origin + u * (t0 * speed);
    let outer = 1.0 + minor;
    let k = dot(p, p) + 1.0 - minor * minor;
    let pu = dot(p, u);
    let c = vec4<f32>(
        4.0 * pu,
        4.0 * pu * pu + 2.0 * k - 4.0 * (u.x * u.x + u.z * u.z),
        4.0 * pu * k - 8.0 * (p.x * u.x + p.z * u.z),
        k * k - 4.0 * (p.x * p.x + p.z * p.z),
    );
    return TorusQuartic(dot(p, p) > outer * outer, speed, t0, c);
}

// The torus's spans along the ray: between consecutive roots where the quartic is
// negative at the middle, touching spans merged (Torus::spans).
fn torus_spans(minor: f32, r: Ray) -> SpanList {
    var out = span_list();
    let q = torus_quartic(minor, r);
    if q.miss {
        return out;
    }
    let c = q.c;
    let roots = solve_quartic(c.x, c.y, c.z, c.w);
    for (var i = 0u; i + 1u < roots.count; i += 1u) {
        let s0 = roots.t[i];
        let s1 = roots.t[i + 1u];
        let a = q.t0 + s0 / q.speed;
        let b = q.t0 + s1 / q.speed;
        let m = 0.5 * (s0 + s1);
        let value = (((m + c.x) * m + c.y) * m + c.z) * m + c.w;
        if a < b && value < 0.0 {
            if out.count > 0u && out.spans[out.count - 1u].exit >= a {
                out.spans[out.count - 1u].exit = b;
            } else {
                push_span(&out, Span(a, 0u, b, 0u));
            }
        }
    }
    return out;
}

fn intersect_torus(minor: f32, r: Ray, t_max: f32) -> ShapeHit {
    let q = torus_quartic(minor, r);
    if q.miss {
        return no_hit();
    }
    let roots = solve_quartic(q.c.x, q.c.y, q.c.z, q.c.w);
    for (var i = 0u; i < roots.count; i += 1u) {
        let t = q.t0 + roots.t[i] / q.speed;
        if t > 0.0 && t < t_max {
            return shape_hit(t, 0u);
        }
    }
    return no_hit();
}

fn torus_surface(minor: f32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let p = ray_at(r, hit.t);
    let ring = normalize_or(vec3<f32>(p.x, 0.0, p.z), vec3<f32>(1.0, 0.0, 0.0));
    let tube = normalize_or(p - ring, ring);
    let point = ring + minor * tube;
    let k = dot(point, point) + 1.0 - minor * minor;
    let normal = k * point - 2.0 * vec3<f32>(point.x, 0.0, point.z);
    let v = 0.5 + atan2(tube.y, dot(tube, ring)) / (2.0 * PI);
    return SurfacePoint(point, normal, vec2<f32>(azimuth_u(point), v));
}
