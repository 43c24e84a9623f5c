//! Shape plugins → scene nodes: `sphere`, `cube`, `rectangle`, `disk`, `cylinder`,
//! `obj` and `ply`, each with its BSDF (nested, referenced or Mitsuba's default) and an
//! optional nested `area` emitter.
//!
//! Mitsuba's flat shapes lie in z = 0 facing +z while glint's face +y, so they get a
//! quarter turn about x first (which maps +y onto +z and keeps Mitsuba's uv). Mitsuba's
//! cylinder is an open tube, which glint has no primitive for: it becomes a mesh of
//! [`CYLINDER_SEGMENTS`] quads with smooth normals.

use std::f32::consts::TAU;

use glam::{Vec2, Vec3};
use glint_core::desc::{BsdfDesc, MeshDesc, NodeDesc, NodeKind, ShapeDesc, TransformOp};

use super::Reader;
use super::bsdfs::material;
use super::emitters::area_radiance;
use super::tree::Elem;
use super::values::Plugin;
use crate::error::SceneError;

/// Quads around a `cylinder` mesh: the silhouette deviates from the true circle by
/// 1 − cos(π/256) ≈ 0.008 % of the radius.
pub const CYLINDER_SEGMENTS: u32 = 256;

/// The quarter turn that lays glint's y-up flat shapes into Mitsuba's z = 0 plane.
const Y_TO_Z: TransformOp = TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 };

/// Reads a `<shape>` into a node (and a mesh, for mesh shapes).
pub(super) fn shape<'a>(r: &mut Reader<'a>, e: &'a Elem) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    let material = shape_material(r, &p)?;
    let flip = p.bool_or("flip_normals", false)?;
    let mut ops = Vec::new();
    let shape = match p.ty {
        "sphere" => {
            let radius = p.float_or("radius", 1.0)?;
            let center = p.point("center")?.unwrap_or(Vec3::ZERO);
            ops.extend([TransformOp::Scale(Vec3::splat(radius)), TransformOp::Translate(center)]);
            ShapeDesc::Sphere
        }
        "cube" => ShapeDesc::Cube,
        "rectangle" | "disk" => {
            if flip {
                // Mirroring the plane onto itself turns the normal and keeps the uv.
                ops.push(TransformOp::Scale(Vec3::new(1.0, -1.0, 1.0)));
            }
            ops.push(Y_TO_Z);
            if p.ty == "rectangle" { ShapeDesc::Rectangle } else { ShapeDesc::Disk }
        }
        "cylinder" => mesh_shape(r, cylinder(&p, flip)?),
        "obj" | "ply" => mesh_shape(r, mesh_file(&p, flip)?),
        other => {
            return Err(p.error(format!(
                "shape type '{other}' is not supported; glint reads sphere, cube, rectangle, disk, cylinder, obj and ply"
            )));
        }
    };
    if flip && matches!(shape, ShapeDesc::Sphere | ShapeDesc::Cube) {
        return Err(p.param_error("flip_normals", format!("is not supported on a {}", p.ty)));
    }
    check_uv(r, &p, shape, material)?;
    ops.extend(p.transform("to_world")?.unwrap_or_default().ops);
    p.finish(&[])?;
    r.scene.objects.push(NodeDesc {
        transform: ops,
        kind: NodeKind::Shape { shape, material },
        origin: e.file.origin(e.pos),
    });
    Ok(())
}

fn mesh_shape(r: &mut Reader, mesh: MeshDesc) -> ShapeDesc {
    r.scene.meshes.push(mesh);
    ShapeDesc::Mesh { index: r.scene.meshes.len() - 1 }
}

/// The shape's material: its BSDF's, or a copy that emits when an area emitter is
/// nested in the shape.
fn shape_material<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<usize, SceneError> {
    let bsdf = match p.objects("bsdf").as_slice() {
        [] => None,
        [b] => Some(*b),
        [_, extra, ..] => return Err(extra.error(format!("{}: a shape takes one BSDF", p.label()))),
    };
    let index = material(r, bsdf)?;
    let radiance = match p.objects("emitter").as_slice() {
        [] => return Ok(index),
        [em] => area_radiance(em)?,
        [_, extra, ..] => return Err(extra.error(format!("{}: a shape takes one emitter", p.label()))),
    };
    let mut emitting = r.scene.materials[index].clone();
    emitting.name = format!("{} (emitting)", emitting.name);
    emitting.emission = radiance;
    Ok(r.add_material(emitting))
}

/// Refuses textures on shapes whose uv parameterisation differs from Mitsuba's (the
/// sphere, disk and cube primitives), where they would land differently.
fn check_uv(r: &Reader, p: &Plugin, shape: ShapeDesc, material: usize) -> Result<(), SceneError> {
    if !matches!(shape, ShapeDesc::Sphere | ShapeDesc::Disk | ShapeDesc::Cube) {
        return Ok(());
    }
    let m = &r.scene.materials[material];
    let textured = m.texture.is_some()
        || match m.bsdf {
            Some(BsdfDesc::Diffuse { reflectance }) => reflectance.texture.is_some(),
            Some(BsdfDesc::Conductor { specular, alpha, .. }) => specular.texture.is_some() || alpha.texture.is_some(),
            Some(BsdfDesc::Dielectric { alpha, .. }) => alpha.texture.is_some(),
            Some(BsdfDesc::Plastic { diffuse, alpha, .. }) => diffuse.texture.is_some() || alpha.texture.is_some(),
            Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, .. }) => {
                base.texture.is_some() || metallic.texture.is_some() || alpha.texture.is_some()
            }
            _ => false,
        };
    if textured {
        return Err(p.error(format!(
            "textures on a {} are not supported: glint's uv mapping of it differs from Mitsuba's (use a mesh)",
            p.ty
        )));
    }
    Ok(())
}

/// Mitsuba's open cylinder from `p0` to `p1` with `radius`, as a mesh: u = φ/2π around
/// the axis, v from 0 at `p0` to 1 at `p1`.
fn cylinder(p: &Plugin, flip: bool) -> Result<MeshDesc, SceneError> {
    let p0 = p.point("p0")?.unwrap_or(Vec3::ZERO);
    let p1 = p.point("p1")?.unwrap_or(Vec3::Z);
    let radius = p.float_or("radius", 1.0)?;
    let axis = p1 - p0;
    if axis.length_squared() == 0.0 || radius <= 0.0 {
        return Err(p.error("needs p0 ≠ p1 and a positive radius"));
    }
    let dir = axis.normalize();
    let (s, t) = dir.any_orthonormal_pair();
    let mut mesh = MeshDesc { name: format!("cylinder@{}", p.elem.file.origin(p.elem.pos)), ..MeshDesc::default() };
    for i in 0..=CYLINDER_SEGMENTS {
        let u = i as f32 / CYLINDER_SEGMENTS as f32;
        let (sin, cos) = (u * TAU).sin_cos();
        let n = cos * s + sin * t;
        for v in [0.0, 1.0] {
            mesh.positions.push(p0 + v * axis + radius * n);
            mesh.normals.push(n);
            mesh.uvs.push(Vec2::new(u, v));
        }
    }
    for i in 0..CYLINDER_SEGMENTS {
        let [a, d, b, c] = [2 * i, 2 * i + 1, 2 * i + 2, 2 * i + 3];
        mesh.indices.extend([a, b, c, a, c, d]);
    }
    if flip {
        flip_mesh(&mut mesh);
    }
    Ok(mesh)
}

/// Turns a mesh inside out: reversed winding, negated normals.
fn flip_mesh(mesh: &mut MeshDesc) {
    for tri in mesh.indices.chunks_exact_mut(3) {
        tri.swap(1, 2);
    }
    for n in &mut mesh.normals {
        *n = -*n;
    }
}

/// An `obj` or `ply` file through glint's mesh loaders, all of its parts merged (MTL
/// materials are ignored, as Mitsuba ignores them).
fn mesh_file(p: &Plugin, flip: bool) -> Result<MeshDesc, SceneError> {
    let file = p.string("filename")?.ok_or_else(|| p.error("needs a 'filename'"))?;
    let path = p.elem.resolve(file);
    let wrong_ext = crate::mesh::MeshFormat::from_path(&path).is_none_or(|f| {
        !matches!((p.ty, f), ("obj", crate::mesh::MeshFormat::Obj) | ("ply", crate::mesh::MeshFormat::Ply))
    });
    if wrong_ext {
        return Err(p.param_error("filename", format!("'{file}' does not end in .{}", p.ty)));
    }
    let import = crate::mesh::load_mesh(&path).map_err(|e| p.param_error("filename", e))?;
    let mut mesh = crate::mesh::merged(&import, file, &path.display().to_string());
    let face_normals = p.bool_or("face_normals", false)?;
    let flip_uv = p.bool_or("flip_tex_coords", true)? && !mesh.uvs.is_empty();
    if face_normals {
        mesh.normals.clear();
    }
    // Mitsuba flips v on load unless told not to; glint's uv must equal Mitsuba's.
    if flip_uv {
        for uv in &mut mesh.uvs {
            uv.y = 1.0 - uv.y;
        }
    }
    if flip {
        flip_mesh(&mut mesh);
    }
    if face_normals || flip_uv || flip {
        // No longer the file's data: a writer must not name the file in its place.
        mesh.path.clear();
    }
    Ok(mesh)
}
