//! Area emitters from emissive instances: their surfaces placed in world space.

use glam::{Mat4, Vec3};
use std::f32::consts::PI;

use super::{Emitter, EmitterKind, NO_EMITTER};
use crate::bsdf::{Bsdf, EMITS_BOTH_SIDES};
use crate::material::NO_TEXTURE;
use crate::mesh::Mesh;
use crate::scene::{Instance, NO_MOTION};
use crate::shape::ShapeKind;

/// The sampled area emitters of `instances` and, per instance, the index of its first
/// emitter ([`NO_EMITTER`] when it has none). A hit on instance `i`, part `k` is on
/// emitter `first[i] + k` for meshes (k = triangle) and cubes (k = face), `first[i]`
/// for the others.
pub fn emitters_of_instances(instances: &[Instance], meshes: &[Mesh], bsdfs: &[Bsdf]) -> (Vec<Emitter>, Vec<u32>) {
    let mut emitters = Vec::new();
    let mut first = Vec::with_capacity(instances.len());
    for inst in instances {
        let bsdf = &bsdfs[inst.material as usize];
        let start = emitters.len() as u32;
        // Moving and textured emitters are left to BSDF sampling.
        let placed = bsdf.is_emissive() && inst.motion == NO_MOTION && bsdf.emission_texture == NO_TEXTURE && {
            let before = emitters.len();
            push_instance(inst, meshes, bsdf.emission, &mut emitters);
            let two_sided = (bsdf.flags & EMITS_BOTH_SIDES != 0) as u32;
            emitters[before..].iter_mut().for_each(|e| e.two_sided = two_sided);
            emitters.len() > before
        };
        first.push(if placed { start } else { NO_EMITTER });
    }
    (emitters, first)
}

fn push_instance(inst: &Instance, meshes: &[Mesh], radiance: Vec3, out: &mut Vec<Emitter>) {
    let xf = &inst.transform;
    let m = xf.world_from_object;
    let planar = |kind, p: Vec3, e1: Vec3, e2: Vec3, normal_object: Vec3, area: f32| Emitter {
        kind,
        p,
        e1,
        e2,
        normal: xf.normal_to_world(normal_object).normalize_or_zero(),
        radiance,
        size: area,
        ..Emitter::empty(kind)
    };
    let vector = |v: Vec3| m.transform_vector3(v);
    match inst.shape.kind {
        ShapeKind::Mesh => {
            let mesh = &meshes[inst.shape.mesh_index() as usize];
            for tri in &mesh.triangles {
                let [a, b, c] = tri.map(|i| mesh.positions[i as usize]);
                let mut normal = (b - a).cross(c - a);
                if !mesh.normals.is_empty() {
                    let shading: Vec3 = tri.iter().map(|&i| mesh.normals[i as usize]).sum();
                    if shading.dot(normal) < 0.0 {
                        normal = -normal;
                    }
                }
                let (wa, wb, wc) = (m.transform_point3(a), m.transform_point3(b), m.transform_point3(c));
                let area = 0.5 * (wb - wa).cross(wc - wa).length();
                out.push(planar(EmitterKind::Triangle, wa, wb - wa, wc - wa, normal, area));
            }
        }
        ShapeKind::Rectangle => {
            let (e1, e2) = (vector(Vec3::new(2.0, 0.0, 0.0)), vector(Vec3::new(0.0, 0.0, 2.0)));
            let corner = m.transform_point3(Vec3::new(-1.0, 0.0, -1.0));
            out.push(planar(EmitterKind::Parallelogram, corner, e1, e2, Vec3::Y, e1.cross(e2).length()));
        }
        ShapeKind::Disk => {
            let (e1, e2) = (vector(Vec3::X), vector(Vec3::Z));
            let centre = m.transform_point3(Vec3::ZERO);
            out.push(planar(EmitterKind::Disk, centre, e1, e2, Vec3::Y, PI * e1.cross(e2).length()));
        }
        ShapeKind::Cube => {
            // Face `part` = 2·axis + (1 for the +1 face), as the cube's hits number them.
            for part in 0..6 {
                let axis = part / 2;
                let sign = if part % 2 == 1 { 1.0 } else { -1.0 };
                let (u_axis, v_axis) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut corner = Vec3::splat(-1.0);
                corner[axis] = sign;
                let (mut du, mut dv, mut n) = (Vec3::ZERO, Vec3::ZERO, Vec3::ZERO);
                du[u_axis] = 2.0;
                dv[v_axis] = 2.0;
                n[axis] = sign;
                let (e1, e2) = (vector(du), vector(dv));
                let p = m.transform_point3(corner);
                out.push(planar(EmitterKind::Parallelogram, p, e1, e2, n, e1.cross(e2).length()));
            }
        }
        ShapeKind::Sphere => {
            if let Some(radius) = uniform_scale(&m) {
                let centre = m.transform_point3(Vec3::ZERO);
                out.push(Emitter { p: centre, radiance, size: radius, ..Emitter::empty(EmitterKind::Sphere) });
            }
        }
        _ => {}
    }
}

/// The scale of a similarity transform (rotation, uniform scale, translation); `None`
/// for shear or non-uniform scale, under which a sphere is no longer a sphere.
fn uniform_scale(m: &Mat4) -> Option<f32> {
    let (x, y, z) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
    let s = x.length();
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * s;
    let square = |a: f32| a.abs() <= 1e-4 * s * s;
    let similar = close(y.length(), s) && close(z.length(), s);
    (similar && square(x.dot(y)) && square(y.dot(z)) && square(x.dot(z))).then_some(s)
}
