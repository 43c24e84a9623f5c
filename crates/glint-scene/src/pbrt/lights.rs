//! `LightSource` (point, spot, distant, infinite) and `AreaLightSource "diffuse"`.
//!
//! pbrt-v4 normalizes a light's spectrum to luminance 1 before `scale` and `power`
//! apply, and an RGB value stands for itself ([`super::spectra`]); point and spot lights
//! fall off with the inverse square as glint's do with attenuation (0, 0, 1).
//!
//! Environment maps: pbrt-v4's `infinite` light reads a square image in the equal-area
//! octahedral parameterization (Clarberg 2008), and glint's environment is an
//! equirectangular image; the map is therefore resampled (bilinearly) into an
//! equirectangular image with the light's transform (and glint's mirror) baked in. A
//! non-square image is taken to be pbrt-v3's equirectangular map (z up), with a warning.

use std::f32::consts::{PI, TAU};

use glam::{Mat3, Vec2, Vec3};
use glint_core::desc::{EnvironmentDesc, LightDesc, SpotFalloff, TextureDesc, Transfer};

use super::params::{Params, SpectrumValue};
use super::spectra::{self, Role};
use super::{AreaLight, Reader};
use crate::error::SceneError;
use crate::texture_io::load_texture_hdr;

/// Inverse-square falloff, as glint's `1/(c1 + c2·d + c3·d²)` reads it.
const INVERSE_SQUARE: Vec3 = Vec3::new(0.0, 0.0, 1.0);

/// The tallest equirectangular image an environment map is resampled into.
const MAX_ENV_HEIGHT: u32 = 1024;

/// Reads a `LightSource` directive.
pub(super) fn light_source(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    if !r.in_world {
        return Err(p.error("must come after WorldBegin"));
    }
    let light = match ty {
        "point" => point(r, p)?,
        "spot" => spot(r, p)?,
        "distant" => distant(r, p)?,
        "infinite" => infinite(r, p)?,
        other => {
            r.warnings.push(p.warning(format!("light type '{other}' is not supported; the light is skipped")));
            for param in &p.list {
                p.get(&param.name);
            }
            return Ok(());
        }
    };
    if r.current_object.is_some() {
        r.warnings.push(p.warning("lights inside an object definition are not instanced; placed once"));
    }
    r.scene.lights.push(light);
    Ok(())
}

/// A light's spectrum parameter `name` as RGB (white when absent), times `scale`.
fn emitted(r: &Reader, p: &Params, name: &str) -> Result<Vec3, SceneError> {
    let value = p.spectrum(name)?.unwrap_or(SpectrumValue::Rgb(Vec3::ONE));
    let rgb = spectra::rgb(&value, Role::Illuminant, r.gs.color_space).map_err(|m| p.error(format!("{name}: {m}")))?;
    let scale = p.float_or("scale", 1.0)?;
    let c = rgb * scale;
    if !c.is_finite() || c.min_element() < 0.0 {
        return Err(p.error(format!("the emitted {name} must be finite and non-negative")));
    }
    Ok(c)
}

/// `power` (in pbrt's photometric sense) as a factor, given the solid-angle measure `k_e`.
fn power_factor(p: &Params, k_e: f32) -> Result<f32, SceneError> {
    let phi = p.float_or("power", -1.0)?;
    Ok(if phi > 0.0 { phi / k_e } else { 1.0 })
}

/// The light-space point `from` (default origin) in glint's world.
fn world_point(r: &Reader, local: Vec3) -> Vec3 {
    r.world_point(r.gs.ctm.transform_point3(local))
}

/// A light-space direction in glint's world.
fn world_vector(r: &Reader, local: Vec3) -> Vec3 {
    r.world_point(r.gs.ctm.transform_vector3(local))
}

fn point(r: &Reader, p: &Params) -> Result<LightDesc, SceneError> {
    let from = p.vec3("from", &["point3"])?.unwrap_or(Vec3::ZERO);
    let color = emitted(r, p, "I")? * power_factor(p, 4.0 * PI)?;
    Ok(LightDesc::Point { position: world_point(r, from), color, attenuation: INVERSE_SQUARE })
}

/// A spot light from `from` towards `to`: full intensity inside `coneangle − conedelta`,
/// fading to zero at `coneangle` (pbrt's smoothstep in cos θ; glint's smooth cubic).
fn spot(r: &Reader, p: &Params) -> Result<LightDesc, SceneError> {
    let from = p.vec3("from", &["point3"])?.unwrap_or(Vec3::ZERO);
    let to = p.vec3("to", &["point3"])?.unwrap_or(Vec3::Z);
    let angle = p.float_or("coneangle", 30.0)?;
    if !(angle > 0.0 && angle <= 180.0) {
        return Err(p.error(format!("coneangle {angle} must lie in (0, 180]")));
    }
    // Checked first: clamping to a negative or NaN angle would be meaningless.
    let delta = p.float_or("conedelta", 5.0)?.max(0.0).min(angle);
    let direction = world_vector(r, to - from);
    if direction.length_squared() == 0.0 || !direction.is_finite() {
        return Err(p.error("from and to must differ"));
    }
    let (cos_end, cos_start) = (angle.to_radians().cos(), (angle - delta).to_radians().cos());
    let k_e = TAU * ((1.0 - cos_start) + 0.5 * (cos_start - cos_end));
    let color = emitted(r, p, "I")? * power_factor(p, k_e)?;
    Ok(LightDesc::Spot {
        position: world_point(r, from),
        direction: direction.normalize(),
        color,
        attenuation: INVERSE_SQUARE,
        angle_degrees: angle.min(90.0),
        penumbra_degrees: delta.min(angle.min(90.0)),
        falloff: SpotFalloff::Smooth,
    })
}

/// Parallel light travelling from `from` towards `to`, of radiance `L` (glint's
/// irradiance on a surface facing it).
fn distant(r: &mut Reader, p: &Params) -> Result<LightDesc, SceneError> {
    let from = p.vec3("from", &["point3"])?.unwrap_or(Vec3::ZERO);
    let to = p.vec3("to", &["point3"])?.unwrap_or(Vec3::Z);
    let direction = world_vector(r, to - from);
    if direction.length_squared() == 0.0 || !direction.is_finite() {
        return Err(p.error("from and to must differ"));
    }
    if p.has("illuminance") || p.has("power") {
        p.get("illuminance");
        p.get("power");
        r.warnings.push(p.warning("\"illuminance\" is not supported; L and scale are used"));
    }
    Ok(LightDesc::Directional { direction: direction.normalize(), color: emitted(r, p, "L")? })
}

/// `infinite`: a constant `L`, or an image map resampled to glint's equirectangular
/// layout.
fn infinite(r: &mut Reader, p: &Params) -> Result<LightDesc, SceneError> {
    if r.scene.lights.iter().any(|l| matches!(l, LightDesc::Environment(_))) {
        return Err(p.error("the scene already has an infinite light; glint takes one"));
    }
    for unsupported in ["illuminance", "portal"] {
        if p.has(unsupported) {
            p.get(unsupported);
            r.warnings.push(p.warning(format!("\"{unsupported}\" is not supported and is ignored")));
        }
    }
    let Some(file) = p.string("filename")? else {
        let radiance = emitted(r, p, "L")?;
        return Ok(LightDesc::Environment(EnvironmentDesc { radiance, texture: None, transform: Vec::new() }));
    };
    if p.has("L") {
        return Err(p.error("give either \"L\" or \"filename\", not both"));
    }
    let scale = p.float_or("scale", 1.0)?;
    let path = p.src.dir.join(file);
    let image = load_texture_hdr("environment", &path, Transfer::Srgb).map_err(|e| p.error(e.to_string()))?;
    let TextureDesc::Image { width, height, texels, .. } = image else {
        return Err(p.error("the image loader returned no image"));
    };
    let square = width == height;
    if !square {
        r.warnings.push(p.warning(
            "the image is not square, so it is not pbrt-v4's equal-area map; read as pbrt-v3's equirectangular map",
        ));
    }
    let source = Image { width, height, texels: &texels };
    let light_from_world = Mat3::from_mat4(r.gs.ctm).inverse();
    let mirror = r.mirror;
    let env_height = height.min(MAX_ENV_HEIGHT);
    let texels = equirect(env_height, |d| {
        let d_pbrt = if mirror { Vec3::new(-d.x, d.y, d.z) } else { d };
        let local = (light_from_world * d_pbrt).normalize_or(Vec3::Z);
        let uv = if square { equal_area_sphere_to_square(local) } else { lat_long_v3(local) };
        source.bilerp(uv)
    });
    r.scene.textures.push(TextureDesc::Image {
        name: format!("environment {file}"),
        path: String::new(),
        width: 2 * env_height,
        height: env_height,
        texels,
        sampling: Default::default(),
    });
    let texture = Some(r.scene.textures.len() - 1);
    Ok(LightDesc::Environment(EnvironmentDesc { radiance: Vec3::splat(scale), texture, transform: Vec::new() }))
}

/// An equirectangular image `2h × h` in glint's layout, each texel `radiance(d)` for
/// its direction: u = atan2(x, −z)/2π across, v = acos(y)/π down from the top.
fn equirect(h: u32, radiance: impl Fn(Vec3) -> Vec3) -> Vec<Vec3> {
    let w = 2 * h;
    let mut out = Vec::with_capacity((w * h) as usize);
    for j in 0..h {
        let theta = (j as f32 + 0.5) / h as f32 * PI;
        for i in 0..w {
            let phi = (i as f32 + 0.5) / w as f32 * TAU;
            let d = Vec3::new(theta.sin() * phi.sin(), theta.cos(), -theta.sin() * phi.cos());
            out.push(radiance(d));
        }
    }
    out
}

/// pbrt-v4's `EqualAreaSphereToSquare` (Clarberg 2008): a unit direction → [0, 1]².
pub(super) fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let (a, b) = (x.max(y), x.min(y));
    let b = if a == 0.0 { 0.0 } else { b / a };
    let mut phi = b.atan() * 2.0 / PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    let u = u.copysign(d.x);
    let v = v.copysign(d.y);
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

/// pbrt-v3's equirectangular lookup: s = φ/2π with φ = atan2(y, x), t = θ/π from +z.
fn lat_long_v3(d: Vec3) -> Vec2 {
    let phi = d.y.atan2(d.x).rem_euclid(TAU);
    Vec2::new(phi / TAU, d.z.clamp(-1.0, 1.0).acos() / PI)
}

/// A decoded image, looked up like pbrt's `Image::Bilerp` (texel centres at half
/// integers, row 0 at t = 0, clamped at the edges).
struct Image<'a> {
    width: u32,
    height: u32,
    texels: &'a [Vec3],
}

impl Image<'_> {
    fn texel(&self, x: i64, y: i64) -> Vec3 {
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let y = y.clamp(0, i64::from(self.height) - 1) as usize;
        self.texels[y * self.width as usize + x]
    }

    fn bilerp(&self, uv: Vec2) -> Vec3 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self.texel(x0, y0).lerp(self.texel(x0 + 1, y0), fx);
        let bottom = self.texel(x0, y0 + 1).lerp(self.texel(x0 + 1, y0 + 1), fx);
        top.lerp(bottom, fy)
    }
}

/// `AreaLightSource "diffuse"`: the shapes that follow in this block emit `L · scale`
/// from their front side.
pub(super) fn area_light(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    if ty != "diffuse" {
        r.warnings.push(p.warning(format!("area light type '{ty}' is not supported; the shapes will not emit")));
        r.gs.area_light = None;
        return Ok(());
    }
    let radiance = emitted(r, p, "L")?;
    let two_sided = p.bool_or("twosided", false)?;
    let power = p.float("power")?.filter(|&phi| phi > 0.0);
    for unsupported in ["filename"] {
        if p.has(unsupported) {
            p.get(unsupported);
            r.warnings.push(p.warning(format!("\"{unsupported}\" is not supported and is ignored")));
        }
    }
    r.area_light_count += 1;
    r.gs.area_light = Some(AreaLight { radiance, power, two_sided, id: r.area_light_count });
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_area_map_centres_and_corners() {
        let c = equal_area_sphere_to_square(Vec3::Z);
        assert!((c - Vec2::splat(0.5)).length() < 1e-6, "{c}");
        let s = equal_area_sphere_to_square(Vec3::NEG_Z);
        assert!((s.x - 0.5).abs() > 0.49 && (s.y - 0.5).abs() > 0.49, "{s}");
        let e = equal_area_sphere_to_square(Vec3::X);
        assert!((e - Vec2::new(1.0, 0.5)).length() < 1e-6, "{e}");
    }
}
