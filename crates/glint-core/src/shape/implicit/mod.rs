//! General implicit surfaces `f(x, y, z) = 0` written as expressions, inside a box.
//!
//! The solid is `{f < 0} ∩ box` (like POV-Ray's `isosurface` with its container), so
//! where the function is still negative at the box the box's face closes the solid.
//! Rays are solved with interval arithmetic over the compiled bytecode ([`solve`]), which
//! cannot step over a root; normals are exact gradients from forward-mode dual numbers.

pub mod bytecode;
pub mod interval;
pub mod parse;
pub mod solve;

use crate::shape::span::pair_crossings;
use bytemuck::NoUninit;
use glam::{DVec3, Vec3};

pub use bytecode::{ImplicitOp, OpCode};
pub use parse::{ExprError, compile_expression};

use self::bytecode::{enclose_along, gradient, value};
use self::interval::{DualInterval, Interval};
use self::solve::{RayFunction, crossings, inside};
use super::span::{BOX_FACE, box_face, box_span, box_uv};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::{Aabb, Ray};

/// Part number of the implicit surface itself; box faces follow [`BOX_FACE`].
const SURFACE: u32 = 0;

/// An implicit surface as flat data: its box and where its program lives in
/// `ShapeTables::implicit_code`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Implicit {
    pub min: Vec3,
    /// Index of the first instruction.
    pub first: u32,
    pub max: Vec3,
    /// Number of instructions.
    pub len: u32,
    /// A bound on `|∇f|` inside the box, or 0 when none was given.
    pub lipschitz: f32,
}

/// An implicit surface with its program, ready to intersect.
#[derive(Clone, Copy, Debug)]
pub struct ImplicitShape<'a> {
    pub record: &'a Implicit,
    pub code: &'a [ImplicitOp],
}

/// `f` along one ray.
struct AlongRay<'a> {
    code: &'a [ImplicitOp],
    o: DVec3,
    d: DVec3,
    /// `L·|d|`, the bound on `|df/dt|` a Lipschitz constant gives; 0 when none.
    slope_bound: f64,
}

impl RayFunction for AlongRay<'_> {
    fn value(&self, t: f64) -> f64 {
        value(self.code, self.o + t * self.d)
    }

    fn enclose(&self, t: Interval) -> DualInterval {
        let mut e = enclose_along(self.code, self.o, self.d, t);
        if self.slope_bound > 0.0 {
            // Mean-value form: |f(t) − f(m)| ≤ L·|d|·|t − m| tightens the enclosure
            // where interval arithmetic overestimates.
            let m = 0.5 * (t.lo + t.hi);
            let reach = self.slope_bound * 0.5 * (t.hi - t.lo);
            let fm = self.value(m);
            if fm.is_finite() {
                let lipschitz = Interval::new(fm - reach, fm + reach);
                let meet = e.v.meet(lipschitz);
                // Keep the plain enclosure if rounding made them disjoint.
                if meet.lo <= meet.hi {
                    e.v = meet;
                }
            }
        }
        e
    }
}

impl<'a> ImplicitShape<'a> {
    fn along(&self, ray: &Ray) -> AlongRay<'a> {
        let d = ray.dir.as_dvec3();
        AlongRay {
            code: self.code,
            o: ray.origin.as_dvec3(),
            d,
            slope_bound: self.record.lipschitz as f64 * d.length(),
        }
    }
}

impl Primitive for ImplicitShape<'_> {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let (min, max) = (self.record.min, self.record.max);
        let b = box_span(ray, min, max)?;
        let f = self.along(ray);
        let in_range = |t: f32| t > 0.0 && t < t_max;
        // Entering the box where the function is negative: the box face is the surface.
        if in_range(b.enter.t) && inside(f.value(b.enter.t as f64)) {
            return Some(b.enter);
        }
        let lo = b.enter.t.max(0.0) as f64;
        let hi = b.exit.t.min(t_max) as f64;
        let mut hit = None;
        crossings(&f, lo, hi, |t, _| {
            let t = t as f32;
            if in_range(t) {
                hit = Some(ShapeHit { t, part: SURFACE });
            }
            hit.is_none()
        });
        if hit.is_some() {
            return hit;
        }
        // Started inside and found no surface before the box: leave through its face.
        (in_range(b.exit.t) && inside(f.value(b.exit.t as f64))).then_some(b.exit)
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let (min, max) = (self.record.min, self.record.max);
        let p = ray.at(hit.t);
        if hit.part >= BOX_FACE {
            let (point, normal) = box_face(hit.part, p, min, max);
            return SurfacePoint { point, normal, uv: box_uv(point, min, max) };
        }
        let (point, normal) = refine_onto_surface(self.code, p, (max - min).max_element());
        let normal = if normal.is_finite() && normal.length_squared() > 0.0 { normal } else { -ray.dir };
        SurfacePoint { point, normal, uv: box_uv(point, min, max) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.record.min, self.record.max)
    }
}

impl Solid for ImplicitShape<'_> {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let Some(b) = box_span(ray, self.record.min, self.record.max) else { return };
        let f = self.along(ray);
        let (t0, t1) = (b.enter.t as f64, b.exit.t as f64);
        let mut enter = inside(f.value(t0)).then_some(b.enter);
        crossings(&f, t0, t1, pair_crossings(out, &mut enter, SURFACE));
        if let Some(e) = enter.filter(|e| e.t < b.exit.t) {
            out.push(Span { enter: e, exit: b.exit });
        }
    }
}

/// One Newton step `p − f·∇f/|∇f|²` onto the surface (removing the error of the f32 `t`)
/// and the gradient there, the outward normal. The step is refused if it is not small
/// compared with the object (`size`), as near a singular point.
fn refine_onto_surface(code: &[ImplicitOp], p: Vec3, size: f32) -> (Vec3, Vec3) {
    let p64 = p.as_dvec3();
    let g = gradient(code, p64);
    let len2 = g.g.length_squared();
    let step = g.g * (g.v / len2);
    let refined = if step.is_finite() && step.length() < 1e-4 * size as f64 { p64 - step } else { p64 };
    let normal = gradient(code, refined).g;
    let normal = if normal.is_finite() && normal.length_squared() > 0.0 { normal } else { g.g };
    (refined.as_vec3(), normal.as_vec3())
}

/// The largest `|∇f|` found on a grid of `n³` points in the box and where, for checking
/// a user's Lipschitz bound (a bound below it would let the solver skip roots).
pub fn sampled_gradient_max(code: &[ImplicitOp], min: Vec3, max: Vec3, n: u32) -> (f64, DVec3) {
    let mut worst = (0.0, min.as_dvec3());
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let s = |c: u32| c as f64 / (n - 1).max(1) as f64;
                let p = min.as_dvec3() + (max - min).as_dvec3() * DVec3::new(s(i), s(j), s(k));
                let g = gradient(code, p).g.length();
                if g.is_finite() && g > worst.0 {
                    worst = (g, p);
                }
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests;
