//! Emitter plugins: `point`, `spot`, `directional`, `constant` and `envmap` at the top
//! level, and `area` nested in a shape (which makes the shape's material emissive).
//!
//! Point and spot lights fall off with the physical inverse square (attenuation
//! (0, 0, 1)). glint's spot light fades from full to zero between `beam_width` and
//! `cutoff_angle` along a smooth cubic where Mitsuba's fade is linear in angle, so the
//! edge of a spot's pool of light differs slightly.

use glam::{Mat3, Vec3};
use glint_core::desc::{EnvironmentDesc, LightDesc, TextureDesc, Transfer};

use super::Reader;
use super::textures::plain_color;
use super::transform::Transform;
use super::tree::Elem;
use super::values::Plugin;
use crate::error::SceneError;
use crate::texture_io::load_texture_hdr;

/// Parameters that do not change the image (sampling weights, ids).
const HARMLESS: [&str; 2] = ["mis_compensation", "sampling_weight"];

/// Inverse-square falloff, as glint's `1/(c1 + c2·d + c3·d²)` reads it.
const INVERSE_SQUARE: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// Reads a top-level `<emitter>` into a light.
pub(super) fn emitter(r: &mut Reader, e: &Elem) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    let light = match p.ty {
        "point" => point(&p)?,
        "spot" => spot(&p)?,
        "directional" => directional(&p)?,
        "constant" | "envmap" => environment(r, &p)?,
        "area" => return Err(p.error("an area emitter must be nested inside the <shape> that emits")),
        other => {
            return Err(p.error(format!(
                "emitter type '{other}' is not supported; glint reads point, spot, directional, constant, envmap \
                 and area (inside a shape)"
            )));
        }
    };
    p.finish(&HARMLESS)?;
    r.scene.lights.push(light);
    Ok(())
}

/// The radiance of an `<emitter type="area">` nested in a shape.
pub(super) fn area_radiance(e: &Elem) -> Result<Vec3, SceneError> {
    let p = Plugin::open(e)?;
    if p.ty != "area" {
        return Err(p.error("only an 'area' emitter can be attached to a shape"));
    }
    let radiance = plain_color(&p, "radiance", Vec3::ONE)?;
    p.finish(&HARMLESS)?;
    Ok(radiance)
}

/// `to_world` of an emitter (identity when absent).
fn to_world(p: &Plugin) -> Result<Transform, SceneError> {
    Ok(p.transform("to_world")?.unwrap_or_default())
}

fn point(p: &Plugin) -> Result<LightDesc, SceneError> {
    let position = match (p.point("position")?, p.has("to_world")) {
        (Some(_), true) => return Err(p.param_error("position", "give either 'position' or 'to_world', not both")),
        (Some(v), false) => v,
        (None, _) => to_world(p)?.matrix().transform_point3(Vec3::ZERO),
    };
    let color = plain_color(p, "intensity", Vec3::ONE)?;
    Ok(LightDesc::Point { position, color, attenuation: INVERSE_SQUARE })
}

/// A spot light shining along its local +z.
fn spot(p: &Plugin) -> Result<LightDesc, SceneError> {
    let m = to_world(p)?.matrix();
    let color = plain_color(p, "intensity", Vec3::ONE)?;
    let cutoff = p.float_or("cutoff_angle", 20.0)?;
    let beam = p.float_or("beam_width", cutoff * 0.75)?;
    if !(cutoff > 0.0 && cutoff <= 90.0 && (0.0..=cutoff).contains(&beam)) {
        return Err(p.error(format!("needs 0 < beam_width ≤ cutoff_angle ≤ 90, not {beam} and {cutoff}")));
    }
    Ok(LightDesc::Spot {
        position: m.transform_point3(Vec3::ZERO),
        direction: m.transform_vector3(Vec3::Z).normalize_or(Vec3::Z),
        color,
        attenuation: INVERSE_SQUARE,
        angle_degrees: cutoff,
        penumbra_degrees: cutoff - beam,
        falloff: glint_core::desc::SpotFalloff::Linear,
    })
}

/// Parallel light travelling along `direction` (or `to_world`'s +z).
fn directional(p: &Plugin) -> Result<LightDesc, SceneError> {
    let direction = match (p.point("direction")?, p.has("to_world")) {
        (Some(_), true) => return Err(p.param_error("direction", "give either 'direction' or 'to_world', not both")),
        (Some(v), false) => v,
        (None, _) => to_world(p)?.matrix().transform_vector3(Vec3::Z),
    };
    if direction.length_squared() == 0.0 || !direction.is_finite() {
        return Err(p.error("the direction must be a non-zero vector"));
    }
    let color = plain_color(p, "irradiance", Vec3::ONE)?;
    Ok(LightDesc::Directional { direction: direction.normalize(), color })
}

/// `constant` (uniform radiance) or `envmap` (an equirectangular image, kept linear).
fn environment(r: &mut Reader, p: &Plugin) -> Result<LightDesc, SceneError> {
    if r.scene.lights.iter().any(|l| matches!(l, LightDesc::Environment(_))) {
        return Err(p.error("the scene already has an environment emitter; glint takes one"));
    }
    if p.ty == "constant" {
        let radiance = plain_color(p, "radiance", Vec3::ONE)?;
        return Ok(LightDesc::Environment(EnvironmentDesc { radiance, texture: None, transform: Vec::new() }));
    }
    let file = p.string("filename")?.ok_or_else(|| p.error("needs a 'filename'"))?;
    let scale = p.float_or("scale", 1.0)?;
    let transform = to_world(p)?;
    check_rotation(p, &transform)?;
    let path = p.elem.resolve(file);
    let image = load_texture_hdr("envmap", &path, Transfer::Srgb).map_err(|e| p.param_error("filename", e))?;
    debug_assert!(matches!(image, TextureDesc::Image { .. }));
    r.scene.textures.push(image);
    Ok(LightDesc::Environment(EnvironmentDesc {
        radiance: Vec3::splat(scale),
        texture: Some(r.scene.textures.len() - 1),
        transform: transform.ops,
    }))
}

/// An environment can only be turned: its `to_world` must be a rotation (a translation
/// is allowed and has no effect).
fn check_rotation(p: &Plugin, t: &Transform) -> Result<(), SceneError> {
    let m = Mat3::from_mat4(t.matrix());
    let orthonormal = (m.transpose() * m).abs_diff_eq(Mat3::IDENTITY, 1e-4);
    if !orthonormal || m.determinant() < 0.0 {
        return Err(p.param_error("to_world", "an environment map can only be rotated (no scale, shear or mirror)"));
    }
    Ok(())
}
