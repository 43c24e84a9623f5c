// General quadrics, optionally clipped by a box (glint_core::shape::quadric): the solid
// f(p) = pᵀQp + g·p + J ≤ 0, its spans along the ray from the quadratic in t (solved
// around the point of the ray nearest the box's centre), clipped to the box, whose
// faces close the solid where it is cut. In f32 where the CPU uses f64.

const KIND_QUADRIC: u32 = 11u;
const BOX_FACE: u32 = 1u;
// Bounds beyond this are "none" (an unbounded quadric stores infinities).
const UNBOUNDED: f32 = 1e30;

fn quadric_float(q: u32, i: u32) -> f32 {
    return floats[params.quadric_offset + 16u * q + i];
}

fn quadric_min(q: u32) -> vec3<f32> {
    return vec3<f32>(quadric_float(q, 10u), quadric_float(q, 11u), quadric_float(q, 12u));
}

fn quadric_max(q: u32) -> vec3<f32> {
    return vec3<f32>(quadric_float(q, 13u), quadric_float(q, 14u), quadric_float(q, 15u));
}

fn quadric_bounded(q: u32) -> bool {
    return all(abs(quadric_min(q)) < vec3<f32>(UNBOUNDED)) && all(abs(quadric_max(q)) < vec3<f32>(UNBOUNDED));
}

// Q·v for the symmetric matrix of the coefficients [A B C D E F …].
fn quadric_q(q: u32, v: vec3<f32>) -> vec3<f32> {
    let a = quadric_float(q, 0u);
    let b = quadric_float(q, 1u);
    let c = quadric_float(q, 2u);
    let d = 0.5 * quadric_float(q, 3u);
    let e = 0.5 * quadric_float(q, 4u);
    let f = 0.5 * quadric_float(q, 5u);
    return vec3<f32>(a * v.x + d * v.y + e * v.z, d * v.x + b * v.y + f * v.z, e * v.x + f * v.y + c * v.z);
}

fn quadric_g(q: u32) -> vec3<f32> {
    return vec3<f32>(quadric_float(q, 6u), quadric_float(q, 7u), quadric_float(q, 8u));
}

fn quadric_value(q: u32, p: vec3<f32>) -> f32 {
    return dot(p, quadric_q(q, p)) + dot(quadric_g(q), p) + quadric_float(q, 9u);
}

fn quadric_gradient(q: u32, p: vec3<f32>) -> vec3<f32> {
    return 2.0 * quadric_q(q, p) + quadric_g(q);
}

// An interval of the ray inside a solid, with the parts its ends lie on.
struct Span {
    enter: f32,
    enter_part: u32,
    exit: f32,
    exit_part: u32,
}

fn span_all() -> Span {
    return Span(-INF, 0u, INF, 0u);
}

// glint_core::shape::span::box_span: the ray's interval inside the box, faces numbered
// BOX_FACE + 2·axis (+1 for the upper face); `found` false when it misses.
struct BoxSpan {
    found: bool,
    span: Span,
}

fn box_span(r: Ray, lo: vec3<f32>, hi: vec3<f32>) -> BoxSpan {
    var s = span_all();
    for (var axis = 0u; axis < 3u; axis += 1u) {
        let o = r.origin[axis];
        let d = r.dir[axis];
        if d == 0.0 {
            if o < lo[axis] || o > hi[axis] {
                return BoxSpan(false, s);
            }
            continue;
        }
        let t_lo = (lo[axis] - o) / d;
        let t_hi = (hi[axis] - o) / d;
        let face = BOX_FACE + 2u * axis;
        var t_in = t_hi;
        var in_part = face + 1u;
        var t_out = t_lo;
        var out_part = face;
        if t_lo < t_hi {
            t_in = t_lo;
            in_part = face;
            t_out = t_hi;
            out_part = face + 1u;
        }
        if t_in > s.enter {
            s.enter = t_in;
            s.enter_part = in_part;
        }
        if t_out < s.exit {
            s.exit = t_out;
            s.exit_part = out_part;
        }
    }
    return BoxSpan(s.enter < s.exit, s);
}

// The spans where a·t² + b·t + c ≤ 0 (glint_core::shape::span::quadratic_spans).
struct QuadraticSpans {
    count: u32,
    spans: array<Span, 2>,
}

fn quadratic_spans(a: f32, b: f32, c: f32) -> QuadraticSpans {
    var out = QuadraticSpans(0u, array<Span, 2>(span_all(), span_all()));
    if a == 0.0 {
        if b > 0.0 {
            out.count = 1u;
            out.spans[0].exit = -c / b;
        } else if b < 0.0 {
            out.count = 1u;
            out.spans[0].enter = -c / b;
        } else if c <= 0.0 {
            out.count = 1u;
        }
        return out;
    }
    let discriminant = fma(b, b, -4.0 * a * c);
    if !(discriminant > 0.0) {
        out.count = select(0u, 1u, a < 0.0);
        return out;
    }
    let root = sqrt(discriminant);
    let q = -0.5 * (b + select(root, -root, b < 0.0));
    var r0 = 0.0;
    var r1 = 0.0;
    if q != 0.0 {
        r0 = q / a;
        r1 = c / q;
    }
    let lo = min(r0, r1);
    let hi = max(r0, r1);
    if a > 0.0 {
        if lo == hi {
            return out;
        }
        out.count = 1u;
        out.spans[0] = Span(lo, 0u, hi, 0u);
    } else {
        out.count = 2u;
        out.spans[0] = Span(-INF, 0u, lo, 0u);
        out.spans[1] = Span(hi, 0u, INF, 0u);
    }
    return out;
}

// The quadric's spans along the ray, clipped to its box (Quadric::spans_array).
fn quadric_spans(q: u32, r: Ray) -> SpanList {
    var out = span_list();
    var clip = span_all();
    var centre = vec3<f32>(0.0);
    if quadric_bounded(q) {
        let b = box_span(r, quadric_min(q), quadric_max(q));
        if !b.found {
            return out;
        }
        clip = b.span;
        centre = 0.5 * (quadric_min(q) + quadric_max(q));
    }
    var t0 = dot(centre - r.origin, r.dir) / dot(r.dir, r.dir);
    if !finite(t0) {
        t0 = 0.0;
    }
    let o = r.origin + t0 * r.dir;
    let qd = quadric_q(q, r.dir);
    let a = dot(r.dir, qd);
    let b = 2.0 * dot(o, qd) + dot(quadric_g(q), r.dir);
    let c = quadric_value(q, o);
    let spans = quadratic_spans(a, b, c);
    for (var k = 0u; k < spans.count; k += 1u) {
        var s = spans.spans[k];
        s.enter = t0 + s.enter;
        s.exit = t0 + s.exit;
        s = clip_span(s, clip);
        if s.enter < s.exit {
            push_span(&out, s);
        }
    }
    return out;
}

// The first span end in (0, t_max) (glint_core::shape::span::first_crossing).
// Where a ray first crosses the boundary of span `s` ahead of its origin: the entry, or
// the exit when the origin lies inside; no hit when the span lies wholly behind.
fn span_crossing(s: Span) -> ShapeHit {
    if s.enter > 0.0 {
        return shape_hit(s.enter, s.enter_part);
    }
    if s.exit > 0.0 {
        return shape_hit(s.exit, s.exit_part);
    }
    return no_hit();
}

// `crossing` when it lies before `t_max`, else no hit.
fn nearer_than(crossing: ShapeHit, t_max: f32) -> ShapeHit {
    if crossing.t < t_max {
        return crossing;
    }
    return no_hit();
}

fn first_crossing(l: SpanList, t_max: f32) -> ShapeHit {
    for (var k = 0u; k < l.count; k += 1u) {
        let c = span_crossing(l.spans[k]);
        if c.found {
            return nearer_than(c, t_max);
        }
    }
    return no_hit();
}

fn intersect_quadric(q: u32, r: Ray, t_max: f32) -> ShapeHit {
    return first_crossing(quadric_spans(q, r), t_max);
}

fn box_uv(p: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec2<f32> {
    var centre = vec3<f32>(0.0);
    if all(abs(lo + hi) < vec3<f32>(UNBOUNDED)) {
        centre = 0.5 * (lo + hi);
    }
    let height = hi.y - lo.y;
    var v = 0.5;
    if abs(height) < UNBOUNDED && height > 0.0 {
        v = clamp((p.y - lo.y) / height, 0.0, 1.0);
    }
    return vec2<f32>(azimuth_u(p - centre), v);
}

// glint_core::shape::span::box_face: the point on face `part` of the box, its normal.
fn box_face_point(part: u32, p: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> SurfacePoint {
    let axis = (part - BOX_FACE) / 2u;
    let upper = (part - BOX_FACE) % 2u == 1u;
    var point = clamp(p, lo, hi);
    point[axis] = select(lo[axis], hi[axis], upper);
    var normal = vec3<f32>(0.0);
    normal[axis] = select(-1.0, 1.0, upper);
    return SurfacePoint(point, normal, box_uv(point, lo, hi));
}

fn quadric_surface(q: u32, r: Ray, hit: ShapeHit) -> SurfacePoint {
    let p = ray_at(r, hit.t);
    let lo = quadric_min(q);
    let hi = quadric_max(q);
    if hit.part >= BOX_FACE {
        return box_face_point(hit.part, p, lo, hi);
    }
    // One Newton step along the gradient puts the point back on the surface.
    let g = quadric_gradient(q, p);
    let step = g * (quadric_value(q, p) / dot(g, g));
    var point = p;
    if finite3(step) {
        point = p - step;
    }
    var normal = quadric_gradient(q, point);
    if !(finite3(normal) && dot(normal, normal) > 0.0) {
        normal = -r.dir;
    }
    return SurfacePoint(point, normal, box_uv(point, lo, hi));
}
