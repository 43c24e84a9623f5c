//! `Shape` → scene nodes: `sphere`, `disk` and `cylinder` as glint primitives or
//! meshes, and the mesh shapes (`trianglemesh`, `bilinearmesh`, `plymesh`,
//! `loopsubdiv`) through [`super::meshes`]; `ObjectInstance` places a definition.
//!
//! pbrt's disk lies in the plane z = `height` facing +z while glint's faces +y, so it
//! gets a quarter turn about x (which maps +y onto +z). `ReverseOrientation` turns a
//! mesh inside out (winding and normals) and mirrors a disk onto itself; on a sphere
//! it cannot be expressed and is warned about when it matters (an area light).

use std::f32::consts::PI;
use std::rc::Rc;

use glam::{Mat3, Vec3};
use glint_core::desc::{BsdfDesc, MaterialDesc, NodeDesc, NodeKind, ShapeDesc, TransformOp, matrix_of};

use super::directives::is_affine;
use super::meshes;
use super::params::Params;
use super::{AreaLight, Reader, matrix_op};
use crate::error::SceneError;
use crate::source::{Pos, Source};

/// The quarter turn that lays glint's y-up flat shapes into pbrt's z = 0 plane.
const Y_TO_Z: TransformOp = TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 };

/// Reads a `Shape` directive into a node of the world or of the object being defined.
pub(super) fn shape(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    check_transform(r, p)?;
    let mut ops = Vec::new();
    let reverse = r.gs.reverse_orientation;
    let shape = match ty {
        "sphere" => {
            let radius = p.float_or("radius", 1.0)?;
            partial_warning(r, p, &[("zmin", -radius), ("zmax", radius), ("phimax", 360.0)])?;
            if reverse && r.gs.area_light.is_some() {
                r.warnings.push(p.warning("ReverseOrientation on an emitting sphere is not supported"));
            }
            ops.push(TransformOp::Scale(Vec3::splat(radius)));
            ShapeDesc::Sphere
        }
        "disk" => {
            let radius = p.float_or("radius", 1.0)?;
            let height = p.float_or("height", 0.0)?;
            partial_warning(r, p, &[("innerradius", 0.0), ("phimax", 360.0)])?;
            if reverse {
                // Mirroring the plane onto itself turns the normal.
                ops.push(TransformOp::Scale(Vec3::new(1.0, -1.0, 1.0)));
            }
            ops.extend([TransformOp::Scale(Vec3::splat(radius)), Y_TO_Z, TransformOp::Translate(Vec3::Z * height)]);
            ShapeDesc::Disk
        }
        "cylinder" | "trianglemesh" | "bilinearmesh" | "plymesh" | "loopsubdiv" => {
            let Some(mut mesh) = meshes::mesh(r, ty, p)? else { return Ok(()) };
            if reverse {
                meshes::flip(&mut mesh);
            }
            r.scene.meshes.push(mesh);
            ShapeDesc::Mesh { index: r.scene.meshes.len() - 1 }
        }
        other => {
            r.warnings.push(p.warning(format!("shape '{other}' is not supported and is skipped")));
            for param in &p.list {
                p.get(&param.name);
            }
            return Ok(());
        }
    };
    for unsupported in ["alpha", "emissionfilename"] {
        if p.has(unsupported) {
            p.get(unsupported);
            r.warnings.push(p.warning(format!("\"{unsupported}\" is not supported and is ignored")));
        }
    }
    if r.current_object.is_some() && r.gs.area_light.is_some() {
        r.warnings.push(p.warning("area lights are not supported on instanced shapes (as in pbrt); it does not emit"));
        let saved = r.gs.area_light.take();
        let material = r.shape_material();
        r.gs.area_light = saved;
        return push(r, p, ops, shape, material);
    }
    let material = material_for(r, p, shape, &ops);
    if matches!(shape, ShapeDesc::Sphere | ShapeDesc::Disk) && is_textured(&r.scene.materials[material]) {
        r.warnings.push(p.warning(format!(
            "glint's uv mapping of a {ty} differs from pbrt's, so its texture lands differently (use a mesh)"
        )));
    }
    push(r, p, ops, shape, material)
}

/// The shape's material; under an area light given by `power`, an emitting material
/// of its own whose radiance makes this shape emit that power.
fn material_for(r: &mut Reader, p: &Params, shape: ShapeDesc, ops: &[TransformOp]) -> usize {
    let Some(light) = r.gs.area_light.clone().filter(|l| l.power.is_some()) else { return r.shape_material() };
    let area = world_area(r, shape, ops);
    let sides = if light.two_sided { 2.0 } else { 1.0 };
    let phi = light.power.unwrap_or(0.0);
    if !(area.is_finite() && area > 0.0) {
        r.warnings.push(p.warning("the shape has no area, so \"power\" cannot set its radiance"));
        return r.shape_material();
    }
    r.area_light_count += 1;
    let radiance = light.radiance * phi / (PI * area * sides);
    r.gs.area_light = Some(AreaLight { radiance, id: r.area_light_count, ..light.clone() });
    let material = r.shape_material();
    r.gs.area_light = Some(light);
    material
}

/// The shape's surface area in the world (an ellipsoid's is approximated by the sphere
/// of the same volume).
fn world_area(r: &Reader, shape: ShapeDesc, ops: &[TransformOp]) -> f32 {
    let m = r.gs.ctm * matrix_of(ops);
    match shape {
        ShapeDesc::Sphere => 4.0 * PI * Mat3::from_mat4(m).determinant().abs().powf(2.0 / 3.0),
        ShapeDesc::Disk => PI * m.transform_vector3(Vec3::X).cross(m.transform_vector3(Vec3::Z)).length(),
        ShapeDesc::Mesh { index } => {
            let mesh = &r.scene.meshes[index];
            let world: Vec<Vec3> = mesh.positions.iter().map(|&v| m.transform_point3(v)).collect();
            mesh.indices
                .chunks_exact(3)
                .map(|t| {
                    let [a, b, c] = [t[0], t[1], t[2]].map(|i| world[i as usize]);
                    0.5 * (b - a).cross(c - a).length()
                })
                .sum()
        }
        _ => 0.0,
    }
}

/// Whether any colour or roughness of the material comes from a texture.
fn is_textured(m: &MaterialDesc) -> bool {
    match m.bsdf {
        Some(BsdfDesc::Diffuse { reflectance }) => reflectance.texture.is_some(),
        Some(BsdfDesc::Conductor { specular, alpha, .. }) => specular.texture.is_some() || alpha.texture.is_some(),
        Some(BsdfDesc::Dielectric { alpha, .. }) => alpha.texture.is_some(),
        Some(BsdfDesc::Plastic { diffuse, alpha, .. }) => diffuse.texture.is_some() || alpha.texture.is_some(),
        _ => m.texture.is_some(),
    }
}

fn push(
    r: &mut Reader,
    p: &Params,
    mut ops: Vec<TransformOp>,
    shape: ShapeDesc,
    material: usize,
) -> Result<(), SceneError> {
    ops.extend(matrix_op(r.gs.ctm));
    r.push_node(NodeDesc { transform: ops, kind: NodeKind::Shape { shape, material }, origin: p.origin() });
    Ok(())
}

/// Refuses a current transform glint cannot apply: projective or singular.
fn check_transform(r: &Reader, p: &Params) -> Result<(), SceneError> {
    let m = r.gs.ctm;
    if !is_affine(m) {
        return Err(p.error("the current transform is projective; glint places shapes by affine transforms only"));
    }
    if Mat3::from_mat4(m).determinant().abs() <= f32::MIN_POSITIVE {
        return Err(p.error("the current transform is singular (it flattens the shape)"));
    }
    Ok(())
}

/// Warns when a parameter that cuts a shape short differs from its default.
fn partial_warning(r: &mut Reader, p: &Params, params: &[(&str, f32)]) -> Result<(), SceneError> {
    for &(name, full) in params {
        if p.float(name)?.is_some_and(|v| v != full) {
            r.warnings
                .push(p.warning(format!("\"{name}\" (a partial shape) is not supported; the whole shape is drawn")));
        }
    }
    Ok(())
}

/// `ObjectInstance "name"`: the definition's shapes, placed by the current transform.
pub(super) fn instance(r: &mut Reader, src: &Rc<Source>, pos: Pos, name: &str) -> Result<(), SceneError> {
    let children = r.objects.get(name).cloned().ok_or_else(|| {
        src.invalid(pos, format!("ObjectInstance: no object is named \"{name}\" (ObjectBegin first)"))
    })?;
    if !is_affine(r.gs.ctm) || Mat3::from_mat4(r.gs.ctm).determinant().abs() <= f32::MIN_POSITIVE {
        return Err(src.invalid(pos, "ObjectInstance: the current transform is projective or singular"));
    }
    if r.current_object.is_some() {
        return Err(src.invalid(pos, "ObjectInstance cannot be used inside ObjectBegin"));
    }
    r.push_node(NodeDesc { transform: matrix_op(r.gs.ctm), kind: NodeKind::Group(children), origin: src.origin(pos) });
    Ok(())
}
