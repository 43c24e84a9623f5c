//! Blobby objects (metaballs): the surface where a sum of fields equals a threshold.
//!
//! Each component is a capsule — a sphere when its segment has zero length — placed by
//! an affine map, so ellipsoids and rotated cylinders come from the same record. Its
//! field is `s·(1 − r²)²` for `r < 1` and 0 beyond (`r` is the distance from the
//! segment in component space, `s` the strength, which may be negative): the
//! compact-support falloff of Wyvill, McPheeters & Wyvill ("Data Structure for Soft
//! Objects", 1986) in the degree-4 form POV-Ray uses. The solid is `Σ fields > threshold`.
//!
//! Along a ray every component's `r²` is a quadratic in `t` on at most three pieces (the
//! capsule's two caps and its side), so between consecutive piece ends the total field
//! is one quartic polynomial. Each such segment is solved with the monotonic-piece root
//! isolation of [`crate::math::polynomial`], which finds every sign change — a thin neck
//! is a sign change like any other. The field at each segment end is computed once and
//! shared by both neighbours, so the crossings of adjacent segments always alternate:
//! no speckles where one segment's rounding disagrees with the next.

use crate::shape::span::pair_crossings;
use std::cell::RefCell;

use bytemuck::NoUninit;
use glam::{DVec3, Mat3, Mat4, Vec3};

use super::span::{LocalRay, box_uv, quadratic_spans};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::polynomial::{MAX_DEGREE, eval, refine_root, roots_in};
use crate::math::{Aabb, Ray};

/// A blob as flat data: its threshold, bounds and its run of components in
/// `ShapeTables::blob_components`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Blob {
    pub min: Vec3,
    /// Index of the first component.
    pub first: u32,
    pub max: Vec3,
    /// Number of components.
    pub count: u32,
    /// The surface is where the summed field equals this (> 0).
    pub threshold: f32,
}

/// One field source. In its own space it is the capsule of radius 1 around the segment
/// from `(0, −h, 0)` to `(0, h, 0)`, `h` = `half_length` (0 for a sphere).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct BlobComponent {
    /// The linear part of the map from blob space to component space.
    pub component_from_blob: Mat3,
    /// Its translation: `q = M·p + offset`.
    pub offset: Vec3,
    /// `s`; negative strengths carve.
    pub strength: f32,
    pub half_length: f32,
}

impl BlobComponent {
    /// A component from its blob-from-component affine map (must be invertible).
    pub fn new(blob_from_component: Mat4, strength: f32, half_length: f32) -> Self {
        let inverse = blob_from_component.inverse();
        BlobComponent {
            component_from_blob: Mat3::from_mat4(inverse),
            offset: inverse.w_axis.truncate(),
            strength,
            half_length,
        }
    }

    fn matrix(&self) -> [DVec3; 3] {
        let m = self.component_from_blob;
        [m.x_axis.as_dvec3(), m.y_axis.as_dvec3(), m.z_axis.as_dvec3()]
    }

    /// `q = M·p + offset` in f64.
    fn local(&self, p: DVec3) -> DVec3 {
        let [c0, c1, c2] = self.matrix();
        c0 * p.x + c1 * p.y + c2 * p.z + self.offset.as_dvec3()
    }

    /// `Mᵀ·v`, which carries a component-space gradient back to blob space.
    fn gradient_in_blob(&self, v: DVec3) -> DVec3 {
        let [c0, c1, c2] = self.matrix();
        DVec3::new(c0.dot(v), c1.dot(v), c2.dot(v))
    }

    /// The segment point nearest to `q`.
    fn nearest_on_segment(&self, q: DVec3) -> DVec3 {
        let h = self.half_length as f64;
        DVec3::new(0.0, q.y.clamp(-h, h), 0.0)
    }

    /// The field `s·(1 − r²)²` at a blob-space point.
    pub fn field(&self, p: DVec3) -> f64 {
        let q = self.local(p);
        let r2 = (q - self.nearest_on_segment(q)).length_squared();
        if r2 < 1.0 { self.strength as f64 * (1.0 - r2) * (1.0 - r2) } else { 0.0 }
    }

    /// `∇(s·(1 − r²)²) = −4s·(1 − r²)·Mᵀ(q − c)`, `c` the nearest segment point.
    pub fn field_gradient(&self, p: DVec3) -> DVec3 {
        let q = self.local(p);
        let radial = q - self.nearest_on_segment(q);
        let r2 = radial.length_squared();
        if r2 >= 1.0 {
            return DVec3::ZERO;
        }
        self.gradient_in_blob(radial) * (-4.0 * self.strength as f64 * (1.0 - r2))
    }

    /// Where the field is non-zero, in blob space.
    pub fn support_bounds(&self) -> Aabb {
        let h = self.half_length;
        let local = Aabb::new(Vec3::new(-1.0, -1.0 - h, -1.0), Vec3::new(1.0, 1.0 + h, 1.0));
        let mut component_from_blob = Mat4::from_mat3(self.component_from_blob);
        component_from_blob.w_axis = self.offset.extend(1.0);
        local.transformed(&component_from_blob.inverse())
    }

    /// The pieces of the line (in the local parameter of `ray`) where this component's
    /// field is non-zero, each with its `r²` quadratic.
    fn pieces(&self, ray: &LocalRay, out: &mut Vec<Piece>) {
        let q0 = self.local(ray.origin);
        let q1 = self.local(ray.origin + ray.dir) - q0;
        let strength = self.strength as f64;
        let h = self.half_length as f64;
        // r² on a piece: distance to the point (0, y_c, 0) (a cap) or to the axis (side).
        let to_point = |yc: f64| {
            let p0 = q0 - DVec3::new(0.0, yc, 0.0);
            (q1.length_squared(), 2.0 * p0.dot(q1), p0.length_squared())
        };
        let to_axis = (q1.x * q1.x + q1.z * q1.z, 2.0 * (q0.x * q1.x + q0.z * q1.z), q0.x * q0.x + q0.z * q0.z);
        let mut push = |(a, b, c): (f64, f64, f64), lo: f64, hi: f64| {
            let (support, n) = quadratic_spans(a, b, c - 1.0, 0);
            if n == 1 {
                let lo = lo.max(support[0].enter.t as f64);
                let hi = hi.min(support[0].exit.t as f64);
                if lo < hi {
                    out.push(Piece { lo, hi, strength, a, b, c });
                }
            }
        };
        let everywhere = (f64::NEG_INFINITY, f64::INFINITY);
        if h == 0.0 {
            push(to_point(0.0), everywhere.0, everywhere.1);
        } else if q1.y == 0.0 {
            let piece = if q0.y > h {
                to_point(h)
            } else if q0.y < -h {
                to_point(-h)
            } else {
                to_axis
            };
            push(piece, everywhere.0, everywhere.1);
        } else {
            // Where the line crosses the planes y = −h and y = h.
            let (s_bottom, s_top) = ((-h - q0.y) / q1.y, (h - q0.y) / q1.y);
            let (s0, s1, first, last) = if q1.y > 0.0 { (s_bottom, s_top, -h, h) } else { (s_top, s_bottom, h, -h) };
            push(to_point(first), everywhere.0, s0);
            push(to_axis, s0, s1);
            push(to_point(last), s1, everywhere.1);
        }
    }
}

/// One component's field along a stretch of the line: `s·(1 − r²(u))²` with
/// `r²(u) = a·u² + b·u + c` for `lo ≤ u ≤ hi`, zero elsewhere.
#[derive(Clone, Copy, Debug)]
struct Piece {
    lo: f64,
    hi: f64,
    strength: f64,
    a: f64,
    b: f64,
    c: f64,
}

impl Piece {
    /// Adds this piece's field, re-expanded around `u0` (`u = u0 + v`), to the quartic
    /// coefficients `poly` (in `v`, lowest degree first).
    fn add_to(&self, u0: f64, poly: &mut [f64; 5]) {
        // w = 1 − r² = w0 + w1·v + w2·v²
        let w0 = 1.0 - ((self.a * u0 + self.b) * u0 + self.c);
        let w1 = -(2.0 * self.a * u0 + self.b);
        let w2 = -self.a;
        let s = self.strength;
        poly[0] += s * w0 * w0;
        poly[1] += s * 2.0 * w0 * w1;
        poly[2] += s * (w1 * w1 + 2.0 * w0 * w2);
        poly[3] += s * 2.0 * w1 * w2;
        poly[4] += s * w2 * w2;
    }
}

/// Per-thread buffers, so a ray allocates nothing once warm.
#[derive(Default)]
struct Scratch {
    pieces: Vec<Piece>,
    ends: Vec<f64>,
    active: Vec<Piece>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// A blob with its components, ready to intersect.
#[derive(Clone, Copy, Debug)]
pub struct BlobShape<'a> {
    pub blob: &'a Blob,
    pub components: &'a [BlobComponent],
}

impl BlobShape<'_> {
    /// The summed field minus the threshold: positive inside.
    pub fn value(&self, p: DVec3) -> f64 {
        self.components.iter().map(|c| c.field(p)).sum::<f64>() - self.blob.threshold as f64
    }

    /// The gradient of the summed field (pointing inward).
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        self.components.iter().map(|c| c.field_gradient(p)).sum()
    }

    fn centre(&self) -> Vec3 {
        0.5 * (self.blob.min + self.blob.max)
    }

    /// Calls `visit(t, entering)` for every crossing of the surface along the whole
    /// line, in order, until it returns `false`.
    fn crossings(&self, ray: &Ray, mut visit: impl FnMut(f64, bool) -> bool) {
        let local = LocalRay::new(ray, self.centre());
        SCRATCH.with_borrow_mut(|scratch| {
            let Scratch { pieces, ends, active } = scratch;
            pieces.clear();
            ends.clear();
            for c in self.components {
                c.pieces(&local, pieces);
            }
            if pieces.is_empty() {
                return;
            }
            pieces.sort_by(|p, q| p.lo.total_cmp(&q.lo));
            ends.extend(pieces.iter().flat_map(|p| [p.lo, p.hi]));
            ends.sort_by(f64::total_cmp);
            ends.dedup();
            let threshold = self.blob.threshold as f64;
            let mut next_piece = 0;
            active.clear();
            // The field minus the threshold at the start of the current segment, shared
            // with the previous segment's end. Before every support it is −threshold.
            let mut poly = [0.0; 5];
            let mut start_value = -threshold;
            for w in 0..ends.len() - 1 {
                let (u0, u1) = (ends[w], ends[w + 1]);
                active.retain(|p| p.hi > u0);
                while next_piece < pieces.len() && pieces[next_piece].lo <= u0 {
                    if pieces[next_piece].hi > u0 {
                        active.push(pieces[next_piece]);
                    }
                    next_piece += 1;
                }
                poly.fill(0.0);
                poly[0] = -threshold;
                for p in active.iter() {
                    p.add_to(u0, &mut poly);
                }
                // The value at this segment's end is the next segment's start value,
                // computed from the pieces live there.
                let end_value = if w + 2 < ends.len() {
                    let mut next = -threshold;
                    let starting = pieces[next_piece..].iter().take_while(|p| p.lo <= u1);
                    for p in active.iter().chain(starting) {
                        if p.lo <= u1 && p.hi > u1 {
                            let r2 = (p.a * u1 + p.b) * u1 + p.c;
                            next += p.strength * (1.0 - r2) * (1.0 - r2);
                        }
                    }
                    next
                } else {
                    -threshold
                };
                let len = u1 - u0;
                let mut derivative = [0.0; MAX_DEGREE];
                for i in 1..5 {
                    derivative[i - 1] = i as f64 * poly[i];
                }
                let mut critical = [0.0; MAX_DEGREE];
                let n = roots_in(&derivative, 0.0, len, &mut critical);
                let (mut a, mut fa) = (0.0, start_value);
                for (b, fb) in critical[..n].iter().map(|&v| (v, eval(&poly, v))).chain([(len, end_value)]) {
                    if (fa > 0.0) != (fb > 0.0) {
                        let v = refine_root(|v| eval(&poly, v), a, b, fa, fb);
                        if !visit(local.t0 + u0 + v, fb > 0.0) {
                            return;
                        }
                    }
                    (a, fa) = (b, fb);
                }
                start_value = end_value;
            }
        });
    }
}

impl Primitive for BlobShape<'_> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let mut hit = None;
        self.crossings(ray, |t, _| {
            let t = t as f32;
            if t >= t_max {
                return false;
            }
            if t > 0.0 {
                hit = Some(ShapeHit { t, part: 0 });
            }
            hit.is_none()
        });
        hit
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let p = ray.at(hit.t).as_dvec3();
        // One Newton step back onto the surface, then the outward normal −∇F.
        let g = self.gradient(p);
        let step = g * (self.value(p) / g.length_squared());
        let size = (self.blob.max - self.blob.min).max_element() as f64;
        let point = if step.is_finite() && step.length() < 1e-4 * size { p - step } else { p };
        let normal = -self.gradient(point).as_vec3();
        let normal = if normal.is_finite() && normal.length_squared() > 0.0 { normal } else { -ray.dir };
        let point = point.as_vec3();
        SurfacePoint { point, normal, uv: box_uv(point, self.blob.min, self.blob.max) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.blob.min, self.blob.max)
    }
}

impl Solid for BlobShape<'_> {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        self.crossings(ray, pair_crossings(out, &mut None, 0));
    }
}

#[cfg(test)]
mod tests;
