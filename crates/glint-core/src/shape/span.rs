//! Solids as sets of ray intervals: the query CSG is built on.
//!
//! A closed solid meets a line `P + t·d` in a union of intervals. Reporting all of them
//! (not only the nearest hit) lets set operations be evaluated along each ray, so a CSG
//! tree never has to be turned into a surface ("don't have to evaluate the CSG to
//! raytrace", Roth, "Ray Casting for Modeling Solids", 1982).

use glam::{DVec3, Vec3};

use super::{Primitive, ShapeHit};
use crate::math::Ray;

/// Where a ray is inside a solid: from `enter` to `exit`, `enter.t < exit.t`. Each end
/// is a [`ShapeHit`] so the surface there can be derived later, like a nearest hit's.
/// Ends may be ±∞ (a half-space, an unclipped quadric); their `part` is then meaningless.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub enter: ShapeHit,
    pub exit: ShapeHit,
}

/// A `visit` callback for a numerical solver's crossings (nearest first): an entering
/// crossing opens a span at surface `part`, the next leaving one closes it into `out`.
/// `enter` may start open (the ray starts inside); whatever is still open afterwards is
/// left in it for the caller to close.
pub(crate) fn pair_crossings<'a>(
    out: &'a mut Vec<Span>,
    enter: &'a mut Option<ShapeHit>,
    part: u32,
) -> impl FnMut(f64, bool) -> bool + 'a {
    move |t, entering| {
        let here = ShapeHit { t: t as f32, part };
        if entering {
            *enter = Some(here);
        } else if let Some(e) = enter.take().filter(|e| e.t < here.t) {
            out.push(Span { enter: e, exit: here });
        }
        true
    }
}

impl Span {
    pub const fn new(t_in: f32, part_in: u32, t_out: f32, part_out: u32) -> Self {
        Span { enter: ShapeHit { t: t_in, part: part_in }, exit: ShapeHit { t: t_out, part: part_out } }
    }

    /// The whole line.
    pub const ALL: Span = Span::new(f32::NEG_INFINITY, 0, f32::INFINITY, 0);
}

/// A primitive with an inside. Besides the nearest hit it reports every interval of
/// the *whole* line (`−∞ < t < ∞`, so CSG knows whether the ray starts inside) where the
/// ray is in the solid: sorted, disjoint, each with `enter.t < exit.t`, appended to `out`.
pub trait Solid: Primitive {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>);
}

/// The first surface crossing in `(0, t_max)` of sorted spans: an entry, or the exit of a
/// span the ray starts in.
pub fn first_crossing(spans: &[Span], t_max: f32) -> Option<ShapeHit> {
    for span in spans {
        for end in [span.enter, span.exit] {
            if end.t > 0.0 {
                return (end.t < t_max).then_some(end);
            }
        }
    }
    None
}

/// Where `a·t² + b·t + c ≤ 0`: up to two spans, both ends labelled `part`. Roots use the
/// cancellation-free form `q = −(b + sign(b)·√D)/2` (Numerical Recipes §5.6).
pub(crate) fn quadratic_spans(a: f64, b: f64, c: f64, part: u32) -> ([Span; 2], usize) {
    let span = |lo: f64, hi: f64| Span::new(lo as f32, part, hi as f32, part);
    let none = [Span::ALL; 2];
    if a == 0.0 {
        // Linear: b·t + c ≤ 0.
        return match b.partial_cmp(&0.0) {
            Some(std::cmp::Ordering::Greater) => ([span(f64::NEG_INFINITY, -c / b), Span::ALL], 1),
            Some(std::cmp::Ordering::Less) => ([span(-c / b, f64::INFINITY), Span::ALL], 1),
            _ if c <= 0.0 => ([Span::ALL; 2], 1),
            _ => (none, 0),
        };
    }
    let discriminant = b.mul_add(b, -4.0 * a * c);
    if discriminant.is_nan() || discriminant <= 0.0 {
        // No two distinct roots: the sign of `a` everywhere (a tangent touches, no span).
        return if a < 0.0 { ([Span::ALL; 2], 1) } else { (none, 0) };
    }
    let q = -0.5 * (b + discriminant.sqrt().copysign(b));
    let (r0, r1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    let (r0, r1) = if r0 <= r1 { (r0, r1) } else { (r1, r0) };
    if a > 0.0 {
        if r0 as f32 == r1 as f32 {
            return (none, 0);
        }
        ([span(r0, r1), Span::ALL], 1)
    } else {
        ([span(f64::NEG_INFINITY, r0), span(r1, f64::INFINITY)], 2)
    }
}

/// Part numbers of an axis-aligned box's faces: `BOX_FACE + 2·axis + (1 on the max side)`.
pub(crate) const BOX_FACE: u32 = 1;

/// The span of the line inside the box `[min, max]` (the slab method); faces are
/// labelled from [`BOX_FACE`]. Infinite bounds give infinite ends.
pub(crate) fn box_span(ray: &Ray, min: Vec3, max: Vec3) -> Option<Span> {
    let (mut near, mut near_part) = (f32::NEG_INFINITY, 0);
    let (mut far, mut far_part) = (f32::INFINITY, 0);
    for axis in 0..3 {
        let (o, d) = (ray.origin[axis], ray.dir[axis]);
        if d == 0.0 {
            if o < min[axis] || o > max[axis] {
                return None;
            }
            continue;
        }
        let t_min = (min[axis] - o) / d;
        let t_max = (max[axis] - o) / d;
        let face = BOX_FACE + 2 * axis as u32;
        let (t_in, in_part, t_out, out_part) =
            if t_min < t_max { (t_min, face, t_max, face + 1) } else { (t_max, face + 1, t_min, face) };
        // Comparisons false for NaN (an infinite bound minus an infinite origin) keep
        // the slab unbounded, which is what an infinite bound means.
        if t_in > near {
            (near, near_part) = (t_in, in_part);
        }
        if t_out < far {
            (far, far_part) = (t_out, out_part);
        }
    }
    (near < far).then_some(Span::new(near, near_part, far, far_part))
}

/// The outward normal and the point moved onto the face for a box face part.
pub(crate) fn box_face(part: u32, p: Vec3, min: Vec3, max: Vec3) -> (Vec3, Vec3) {
    let axis = ((part - BOX_FACE) / 2) as usize;
    let upper = (part - BOX_FACE) % 2 == 1;
    let mut point = p.clamp(min, max);
    point[axis] = if upper { max[axis] } else { min[axis] };
    let mut normal = Vec3::ZERO;
    normal[axis] = if upper { 1.0 } else { -1.0 };
    (point, normal)
}

/// uv for surfaces without a natural parameterization (quadrics, blobs, implicit
/// surfaces, superellipsoids): longitude around the y axis through the box centre, and
/// height within the box.
pub(crate) fn box_uv(p: Vec3, min: Vec3, max: Vec3) -> glam::Vec2 {
    let centre = if (min + max).is_finite() { 0.5 * (min + max) } else { Vec3::ZERO };
    let height = max.y - min.y;
    let v = if height.is_finite() && height > 0.0 { ((p.y - min.y) / height).clamp(0.0, 1.0) } else { 0.5 };
    glam::Vec2::new(super::azimuth_u(p - centre), v)
}

/// A ray in f64, with the parameter shifted so the origin is the line's point closest
/// to `centre`: polynomial coefficients built from it stay small (Haines et al., Ray
/// Tracing Gems ch. 7). `t = t0 + s`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalRay {
    pub t0: f64,
    pub origin: DVec3,
    pub dir: DVec3,
}

impl LocalRay {
    pub fn new(ray: &Ray, centre: Vec3) -> Self {
        let (o, d, c) = (ray.origin.as_dvec3(), ray.dir.as_dvec3(), centre.as_dvec3());
        let t0 = (c - o).dot(d) / d.length_squared();
        let t0 = if t0.is_finite() { t0 } else { 0.0 };
        LocalRay { t0, origin: o + t0 * d, dir: d }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_spans_cover_every_sign_case() {
        // (t − 1)(t − 3) ≤ 0 on [1, 3].
        let (s, n) = quadratic_spans(1.0, -4.0, 3.0, 7);
        assert_eq!(n, 1);
        assert_eq!((s[0].enter.t, s[0].exit.t, s[0].enter.part), (1.0, 3.0, 7));
        // −(t − 1)(t − 3) ≤ 0 outside (1, 3).
        let (s, n) = quadratic_spans(-1.0, 4.0, -3.0, 0);
        assert_eq!(n, 2);
        assert_eq!((s[0].enter.t, s[0].exit.t), (f32::NEG_INFINITY, 1.0));
        assert_eq!((s[1].enter.t, s[1].exit.t), (3.0, f32::INFINITY));
        // No real roots: everything or nothing.
        assert_eq!(quadratic_spans(1.0, 0.0, 1.0, 0).1, 0);
        assert_eq!(quadratic_spans(-1.0, 0.0, -1.0, 0).1, 1);
        // Linear.
        let (s, n) = quadratic_spans(0.0, 2.0, -4.0, 0);
        assert_eq!((n, s[0].exit.t), (1, 2.0));
    }

    #[test]
    fn box_span_labels_faces_and_handles_parallel_rays() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        let s = box_span(&ray, Vec3::splat(-1.0), Vec3::ONE).unwrap();
        assert_eq!((s.enter.t, s.exit.t), (4.0, 6.0));
        assert_eq!((s.enter.part, s.exit.part), (BOX_FACE + 5, BOX_FACE + 4));
        let outside = Ray::new(Vec3::new(2.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(box_span(&outside, Vec3::splat(-1.0), Vec3::ONE).is_none());
        let unbounded = box_span(&ray, Vec3::NEG_INFINITY, Vec3::INFINITY).unwrap();
        assert_eq!((unbounded.enter.t, unbounded.exit.t), (f32::NEG_INFINITY, f32::INFINITY));
    }
}
