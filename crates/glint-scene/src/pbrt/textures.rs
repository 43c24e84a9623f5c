//! `Texture` (imagemap, checkerboard, constant, scale; mix approximated) and the
//! colour and scalar parameters that may name one (`"texture reflectance" "wood"`).
//!
//! Image orientation: pbrt-v4 looks an image up with t flipped, so t = 0 is the bottom
//! row; glint puts v = 1 at the top row, so images are stored as they are and uvs pass
//! through unchanged. `uscale`/`vscale` of a checkerboard become its cell counts; on an
//! image (and `udelta`/`vdelta` on either) they are not supported and are warned about.

use glam::{Vec2, Vec3};
use glint_core::desc::{ColorParam, ImageSampling, ScalarParam, TextureDesc, TextureWrap, Transfer};

use super::params::Params;
use super::spectra::{self, Role};
use super::{Reader, TextureRef};
use crate::error::SceneError;
use crate::texture_io::load_texture_hdr;

/// Parameter `name` as a colour that may be a texture; `default` when absent.
pub(super) fn color_param(r: &mut Reader, p: &Params, name: &str, default: Vec3) -> Result<ColorParam, SceneError> {
    if let Some(tex) = p.texture(name) {
        return match lookup(r, p, false, tex)? {
            TextureRef::Scaled(i, factor) => Ok(ColorParam { value: factor, texture: Some(i) }),
            TextureRef::Constant(c) => Ok(ColorParam::constant(c)),
        };
    }
    match p.spectrum(name)? {
        Some(v) => spectra::rgb(&v, Role::Albedo, r.gs.color_space)
            .map(ColorParam::constant)
            .map_err(|m| p.error(format!("{name}: {m}"))),
        None => Ok(ColorParam::constant(default)),
    }
}

/// Parameter `name` as a number that may be a (float) texture.
pub(super) fn scalar_param(r: &mut Reader, p: &Params, name: &str, default: f32) -> Result<ScalarParam, SceneError> {
    if let Some(tex) = p.texture(name) {
        return match lookup(r, p, true, tex)? {
            TextureRef::Scaled(i, factor) => Ok(ScalarParam { value: factor.x, texture: Some(i) }),
            TextureRef::Constant(c) => Ok(ScalarParam::constant(c.x)),
        };
    }
    Ok(ScalarParam::constant(p.float_or(name, default)?))
}

/// The texture called `name` (float textures when `float`); pbrt-v3 scenes use
/// spectrum textures for floats and the reverse happens too, so the other kind is
/// tried second.
fn lookup(r: &Reader, p: &Params, float: bool, name: &str) -> Result<TextureRef, SceneError> {
    r.textures
        .get(&(float, name.to_owned()))
        .or_else(|| r.textures.get(&(!float, name.to_owned())))
        .copied()
        .ok_or_else(|| p.error(format!("no texture is named \"{name}\" (Texture must come first)")))
}

/// Reads a `Texture "name" "spectrum"|"float" "class"` directive.
pub(super) fn texture(r: &mut Reader, name: &str, kind: &str, class: &str, p: &Params) -> Result<(), SceneError> {
    let float = match kind {
        "float" => true,
        "spectrum" | "color" | "rgb" => false,
        other => return Err(p.error(format!("texture kind '{other}' is neither \"float\" nor \"spectrum\""))),
    };
    let made = match class {
        "imagemap" => TextureRef::Scaled(image(r, name, p)?, Vec3::ONE),
        "checkerboard" => checkerboard(r, name, float, p)?,
        "constant" => TextureRef::Constant(constant(r, p, float, "value", 1.0)?),
        "scale" => scale(r, p, float)?,
        "mix" | "directionmix" => {
            let first = "tex1";
            r.warnings.push(p.warning(format!("approximated by its \"{first}\" alone")));
            for param in &p.list {
                if param.name != first {
                    p.get(&param.name);
                }
            }
            match p.texture(first) {
                Some(t) => lookup(r, p, float, t)?,
                None => TextureRef::Constant(constant(r, p, float, first, 1.0)?),
            }
        }
        other => {
            r.warnings.push(p.warning(format!("texture class '{other}' is not supported; using a constant grey")));
            for param in &p.list {
                p.get(&param.name);
            }
            TextureRef::Constant(Vec3::splat(0.5))
        }
    };
    r.textures.insert((float, name.to_owned()), made);
    Ok(())
}

/// pbrt's `scale` texture, `tex · scale`: exact when `scale` is a number (glint's
/// parameters are a value times a texture); a textured `scale` is dropped with a
/// warning.
fn scale(r: &mut Reader, p: &Params, float: bool) -> Result<TextureRef, SceneError> {
    let base = match p.texture("tex") {
        Some(t) => lookup(r, p, float, t)?,
        None => TextureRef::Constant(constant(r, p, float, "tex", 1.0)?),
    };
    let factor = if p.texture("scale").is_some() {
        r.warnings.push(p.warning("a textured \"scale\" is not supported; the texture is used unscaled"));
        Vec3::ONE
    } else {
        constant(r, p, float, "scale", 1.0)?
    };
    Ok(match base {
        TextureRef::Scaled(i, f) => TextureRef::Scaled(i, f * factor),
        TextureRef::Constant(c) => TextureRef::Constant(c * factor),
    })
}

/// A constant texture value (a float becomes a grey).
fn constant(r: &Reader, p: &Params, float: bool, name: &str, default: f32) -> Result<Vec3, SceneError> {
    if float {
        return Ok(Vec3::splat(p.float_or(name, default)?));
    }
    match p.spectrum(name)? {
        Some(v) => spectra::rgb(&v, Role::Albedo, r.gs.color_space).map_err(|m| p.error(format!("{name}: {m}"))),
        None => Ok(Vec3::splat(default)),
    }
}

/// Warns about a uv mapping glint cannot follow.
fn check_mapping(r: &mut Reader, p: &Params, scales_supported: bool) -> Result<Vec2, SceneError> {
    if let Some(m) = p.string("mapping")?.filter(|m| *m != "uv") {
        r.warnings.push(p.warning(format!("mapping \"{m}\" is not supported; using the shape's uv")));
    }
    let scale = Vec2::new(p.float_or("uscale", 1.0)?, p.float_or("vscale", 1.0)?);
    let delta = Vec2::new(p.float_or("udelta", 0.0)?, p.float_or("vdelta", 0.0)?);
    if (!scales_supported && scale != Vec2::ONE) || delta != Vec2::ZERO {
        r.warnings.push(p.warning("uscale/vscale/udelta/vdelta are not supported here and are ignored"));
    }
    Ok(scale)
}

/// An `imagemap`: the file relative to the scene file; 8-bit images are sRGB-decoded
/// unless `encoding` is `linear`, float images stay linear.
fn image(r: &mut Reader, name: &str, p: &Params) -> Result<usize, SceneError> {
    check_mapping(r, p, false)?;
    let file = p.string("filename")?.ok_or_else(|| p.error("needs a \"string filename\""))?;
    let transfer = match p.string("encoding")? {
        None | Some("sRGB" | "srgb") => Transfer::Srgb,
        Some("linear") => Transfer::Identity,
        Some(other) => {
            r.warnings.push(p.warning(format!("encoding \"{other}\" is approximated by sRGB")));
            Transfer::Srgb
        }
    };
    let sampling = sampling(r, p)?;
    p.get("maxanisotropy");
    let scale = p.float_or("scale", 1.0)?;
    let invert = p.bool_or("invert", false)?;
    let path = p.src.dir.join(file);
    let loaded = load_texture_hdr(name, &path, transfer).map_err(|e| p.error(e.to_string()))?;
    let TextureDesc::Image { name, path, width, height, mut texels, .. } = loaded else {
        return Err(p.error("the image loader returned no image"));
    };
    let changed = scale != 1.0 || invert;
    if changed {
        for t in &mut texels {
            *t *= scale;
            if invert {
                *t = Vec3::ONE - *t;
            }
        }
    }
    // Changed texels are no longer the file's: no path, so a writer cannot name it.
    let path = if changed { String::new() } else { path };
    r.scene.textures.push(TextureDesc::Image { name, path, width, height, texels, sampling });
    Ok(r.scene.textures.len() - 1)
}

/// An imagemap's `wrap` and `filter`: repeat and clamp as they are, `black` as clamp
/// (glint has no border colour); `point` is the nearest texel, the other filters
/// (bilinear, trilinear, EWA) are bilinear, glint having no mip-maps.
fn sampling(r: &mut Reader, p: &Params) -> Result<ImageSampling, SceneError> {
    let wrap = match p.string("wrap")? {
        None | Some("repeat") => TextureWrap::Repeat,
        Some("clamp") => TextureWrap::Clamp,
        Some(other) => {
            r.warnings.push(p.warning(format!("wrap \"{other}\" is approximated by \"clamp\"")));
            TextureWrap::Clamp
        }
    };
    let nearest = p.string("filter")? == Some("point");
    Ok(ImageSampling { wrap: [wrap; 2], nearest })
}

/// pbrt's 2-D checkerboard: `tex1` where ⌊s⌋ + ⌊t⌋ is even (s = u·uscale,
/// t = v·vscale), `tex2` elsewhere.
fn checkerboard(r: &mut Reader, name: &str, float: bool, p: &Params) -> Result<TextureRef, SceneError> {
    if p.int("dimension")?.unwrap_or(2) != 2 {
        r.warnings.push(p.warning("3-D checkerboards are not supported; using the 2-D one"));
    }
    let scale = check_mapping(r, p, true)?;
    let mut color = |which: &str, default: f32| -> Result<Vec3, SceneError> {
        if let Some(t) = p.texture(which) {
            r.warnings.push(p.warning(format!("a texture as \"{which}\" is approximated by a grey")));
            let _ = t;
            return Ok(Vec3::splat(default));
        }
        constant(r, p, float, which, default)
    };
    let even = color("tex1", 1.0)?;
    let odd = color("tex2", 0.0)?;
    r.scene.textures.push(TextureDesc::Checker { name: name.to_owned(), even, odd, cells: scale, filtered: false });
    Ok(TextureRef::Scaled(r.scene.textures.len() - 1, Vec3::ONE))
}
