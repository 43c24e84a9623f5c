use glam::{Vec2, Vec3};

use super::span::{BOX_FACE, box_span};
use super::{Primitive, ShapeHit, Solid, Span, SurfacePoint};
use crate::math::{Aabb, Ray};

/// The cube [−1, 1]³: six planes `x = ±1`, `y = ±1`, `z = ±1` bounded by the others.
#[derive(Clone, Copy, Debug, Default)]
pub struct Cube;

impl Primitive for Cube {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        // Slab method; part = 2·axis + (1 if the +1 face).
        let inv = ray.dir.recip();
        let (mut near, mut near_part) = (f32::NEG_INFINITY, 0);
        let (mut far, mut far_part) = (f32::INFINITY, 0);
        for axis in 0..3 {
            let o = ray.origin[axis];
            if inv[axis].is_infinite() {
                if o.abs() > 1.0 {
                    return None;
                }
                continue;
            }
            let t_minus = (-1.0 - o) * inv[axis];
            let t_plus = (1.0 - o) * inv[axis];
            let (t_in, in_part, t_out, out_part) = if t_minus < t_plus {
                (t_minus, 2 * axis, t_plus, 2 * axis + 1)
            } else {
                (t_plus, 2 * axis + 1, t_minus, 2 * axis)
            };
            if t_in > near {
                (near, near_part) = (t_in, in_part);
            }
            if t_out < far {
                (far, far_part) = (t_out, out_part);
            }
        }
        if near > far {
            return None;
        }
        if near > 0.0 && near < t_max {
            return Some(ShapeHit { t: near, part: near_part as u32 });
        }
        (far > 0.0 && far < t_max).then_some(ShapeHit { t: far, part: far_part as u32 })
    }

    fn surface(&self, ray: &Ray, hit: ShapeHit) -> SurfacePoint {
        let axis = (hit.part / 2) as usize;
        let sign = if hit.part % 2 == 1 { 1.0 } else { -1.0 };
        let mut point = ray.at(hit.t).clamp(Vec3::splat(-1.0), Vec3::ONE);
        point[axis] = sign;
        let mut normal = Vec3::ZERO;
        normal[axis] = sign;
        SurfacePoint { point, normal, uv: face_uv(point, axis, sign) }
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::splat(-1.0), Vec3::ONE)
    }
}

impl Solid for Cube {
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if let Some(mut s) = box_span(ray, Vec3::splat(-1.0), Vec3::ONE) {
            // The cube numbers its faces like the box helper, without the offset.
            s.enter.part -= BOX_FACE;
            s.exit.part -= BOX_FACE;
            out.push(s);
        }
    }
}

/// Each face maps to the unit square upright and unmirrored as seen from outside
/// (the ±y faces with −z at the top of the picture for +y).
fn face_uv(p: Vec3, axis: usize, sign: f32) -> Vec2 {
    let (u, v) = match axis {
        0 => (-sign * p.z, p.y),
        1 => (p.x, -sign * p.z),
        _ => (sign * p.x, p.y),
    };
    Vec2::new(0.5 + 0.5 * u, 0.5 + 0.5 * v)
}
