//! `bitmap` and `checkerboard` textures, and the colour and scalar parameters that may
//! name one.
//!
//! glint's uv on a shape equals Mitsuba's, but the two renderers read an image from
//! opposite ends: Mitsuba takes row `v·height` from the top, glint puts v = 1 at the
//! top. A bitmap is therefore stored flipped vertically, and a `to_uv` scale or offset
//! is baked into the stored texels (tiling the image), which is exact when the scale is
//! a whole number and the offset a whole number of texels; anything else is refused.

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{ColorParam, ImageSampling, ScalarParam, TextureDesc, TextureWrap, Transfer};

use super::Reader;
use super::tree::Elem;
use super::values::Plugin;
use crate::error::SceneError;
use crate::texture_io::{MAX_TEXTURE_SIDE, load_texture_hdr};

/// Parameters of texture plugins that do not change the image.
const HARMLESS: [&str; 2] = ["format", "accel"];

/// Parameter `name` of `p` as a colour that may be a texture; `default` when absent.
pub(super) fn color_param<'a>(
    r: &mut Reader<'a>,
    p: &Plugin<'a>,
    name: &str,
    default: Vec3,
) -> Result<ColorParam, SceneError> {
    if let Some(e) = p.named_object(name) {
        let index = texture(r, r.resolve(e, "texture")?)?;
        return Ok(ColorParam { value: Vec3::ONE, texture: Some(index) });
    }
    Ok(ColorParam::constant(p.color(name)?.unwrap_or(default)))
}

/// Parameter `name` of `p` as a number that may be a texture (its mean channel).
pub(super) fn scalar_param<'a>(
    r: &mut Reader<'a>,
    p: &Plugin<'a>,
    name: &str,
    default: f32,
) -> Result<ScalarParam, SceneError> {
    if let Some(e) = p.named_object(name) {
        let index = texture(r, r.resolve(e, "texture")?)?;
        return Ok(ScalarParam { value: 1.0, texture: Some(index) });
    }
    Ok(ScalarParam::constant(p.float_or(name, default)?))
}

/// Parameter `name` as a plain colour: glint takes no texture there.
pub(super) fn plain_color(p: &Plugin, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
    if p.named_object(name).is_some() {
        return Err(p.param_error(name, "a texture is not supported here; give an <rgb> or <float>"));
    }
    Ok(p.color(name)?.unwrap_or(default))
}

/// The index in the scene's textures of texture element `e`, built on first use.
fn texture<'a>(r: &mut Reader<'a>, e: &'a Elem) -> Result<usize, SceneError> {
    let key: *const Elem = e;
    if let Some(&i) = r.textures.get(&key) {
        return Ok(i);
    }
    let p = Plugin::open(e)?;
    let desc = match p.ty {
        "bitmap" => bitmap(&p)?,
        "checkerboard" => checkerboard(&p)?,
        other => {
            return Err(
                p.error(format!("texture type '{other}' is not supported; glint reads bitmap and checkerboard"))
            );
        }
    };
    p.finish(&HARMLESS)?;
    r.scene.textures.push(desc);
    let index = r.scene.textures.len() - 1;
    r.textures.insert(key, index);
    Ok(index)
}

fn texture_name(p: &Plugin) -> String {
    p.elem.attr("id").map_or_else(|| format!("{}@{}", p.ty, p.elem.file.origin(p.elem.pos)), str::to_owned)
}

/// The `to_uv` transform as `uv' = scale·uv + offset`; rotations and shears are refused.
fn to_uv(p: &Plugin) -> Result<(Vec2, Vec2), SceneError> {
    let Some(t) = p.transform("to_uv")? else { return Ok((Vec2::ONE, Vec2::ZERO)) };
    let m: Mat4 = t.matrix();
    if m.x_axis.y.abs() > 1e-6 || m.y_axis.x.abs() > 1e-6 {
        return Err(p.param_error("to_uv", "only scale and translate can be expressed in glint (no rotation)"));
    }
    Ok((Vec2::new(m.x_axis.x, m.y_axis.y), Vec2::new(m.w_axis.x, m.w_axis.y)))
}

/// An image file; 8-bit files are sRGB-decoded unless `raw` is set, float files stay
/// linear.
fn bitmap(p: &Plugin) -> Result<TextureDesc, SceneError> {
    let file = p.string("filename")?.ok_or_else(|| p.error("needs a 'filename'"))?;
    let raw = p.bool_or("raw", false)?;
    let nearest = match p.string("filter_type")? {
        None | Some("bilinear") => false,
        Some("nearest") => true,
        Some(f) => return Err(p.param_error("filter_type", format!("'{f}' is not one of 'bilinear' or 'nearest'"))),
    };
    let wrap = match p.string("wrap_mode")? {
        None | Some("repeat") => TextureWrap::Repeat,
        Some("clamp") => TextureWrap::Clamp,
        Some("mirror") => TextureWrap::Mirror,
        Some(w) => return Err(p.param_error("wrap_mode", format!("'{w}' is not one of 'repeat', 'mirror' or 'clamp'"))),
    };
    let (scale, offset) = to_uv(p)?;
    let path = p.elem.resolve(file);
    let transfer = if raw { Transfer::Identity } else { Transfer::Srgb };
    let loaded = load_texture_hdr(&texture_name(p), &path, transfer).map_err(|e| p.param_error("filename", e))?;
    let TextureDesc::Image { name, width, height, texels, .. } = loaded else {
        return Err(p.error("the image loader returned no image"));
    };
    let (w, h, texels) = bake(width, height, &texels, scale, offset).map_err(|m| p.param_error("to_uv", m))?;
    // The texels are no longer the file's (flipped, maybe tiled): no source path, so a
    // writer cannot name the file in their place.
    let sampling = ImageSampling { wrap: [wrap; 2], nearest };
    Ok(TextureDesc::Image { name, path: String::new(), width: w, height: h, texels, sampling })
}

/// A whole number close to `x`, if there is one.
fn whole(x: f32) -> Option<i64> {
    let r = x.round();
    ((x - r).abs() < 1e-3 && r.is_finite()).then_some(r as i64)
}

/// The texels glint must store (rows from the top) so that its lookup at uv gives
/// Mitsuba's lookup at `scale·uv + offset` in the `w`×`h` image `src`: the image
/// tiled `scale` times, flipped vertically and shifted by `offset`.
fn bake(w: u32, h: u32, src: &[glam::Vec3], scale: Vec2, offset: Vec2) -> Result<(u32, u32, Vec<Vec3>), String> {
    let (Some(sx), Some(sy)) = (whole(scale.x), whole(scale.y)) else {
        return Err(format!(
            "a scale of {} × {} repeats; only whole, positive repeat counts can be baked",
            scale.x, scale.y
        ));
    };
    let (Some(ox), Some(oy)) = (whole(offset.x * w as f32), whole(offset.y * h as f32)) else {
        return Err(format!("an offset of ({}, {}) is not a whole number of texels", offset.x, offset.y));
    };
    if sx < 1 || sy < 1 {
        return Err(format!("a scale of {sx} × {sy} mirrors or collapses the texture"));
    }
    let (big_w, big_h) = (i64::from(w) * sx, i64::from(h) * sy);
    if big_w > i64::from(MAX_TEXTURE_SIDE) || big_h > i64::from(MAX_TEXTURE_SIDE) {
        return Err(format!(
            "repeating the {w}x{h} image {sx} × {sy} times exceeds {MAX_TEXTURE_SIDE} texels per side"
        ));
    }
    let max_pixels = crate::input::limits().image_pixels;
    if (big_w * big_h) as u64 > max_pixels {
        return Err(format!(
            "repeating the {w}x{h} image {sx} × {sy} times makes more than the {max_pixels} texels allowed; \
             raise the limit with --input-limit pixels=N"
        ));
    }
    let (wi, hi) = (i64::from(w), i64::from(h));
    let mut out = Vec::with_capacity((big_w * big_h) as usize);
    for j in 0..big_h {
        let y = (big_h - 1 - j + oy).rem_euclid(hi);
        for i in 0..big_w {
            let x = (i + ox).rem_euclid(wi);
            out.push(src[(y * wi + x) as usize]);
        }
    }
    Ok((big_w as u32, big_h as u32, out))
}

/// Mitsuba's checkerboard: `color0` where the fractional parts of u and v are both
/// below or both above one half, `color1` elsewhere; 2×2 squares per unit of uv.
fn checkerboard(p: &Plugin) -> Result<TextureDesc, SceneError> {
    let color0 = plain_color(p, "color0", Vec3::splat(0.4))?;
    let color1 = plain_color(p, "color1", Vec3::splat(0.2))?;
    let (scale, offset) = to_uv(p)?;
    if scale.x <= 0.0 || scale.y <= 0.0 {
        return Err(p.param_error("to_uv", "a negative or zero scale of a checkerboard is not supported"));
    }
    // An offset of whole half-cells shifts the pattern by whole squares: it swaps the
    // colours when the total shift is odd.
    let (Some(dx), Some(dy)) = (whole(2.0 * offset.x), whole(2.0 * offset.y)) else {
        return Err(p.param_error("to_uv", "the offset must be a multiple of 0.5 (whole squares)"));
    };
    let (even, odd) = if (dx + dy).rem_euclid(2) == 0 { (color0, color1) } else { (color1, color0) };
    Ok(TextureDesc::Checker { name: texture_name(p), even, odd, cells: 2.0 * scale, filtered: false })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bake_flips_rows_and_tiles() {
        let src = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::ONE]; // 2×2: top row X Y, bottom Z 1
        let (w, h, t) = bake(2, 2, &src, Vec2::ONE, Vec2::ZERO).unwrap();
        assert_eq!((w, h), (2, 2));
        assert_eq!(t, vec![Vec3::Z, Vec3::ONE, Vec3::X, Vec3::Y]);
        let (w, h, t) = bake(2, 2, &src, Vec2::new(2.0, 1.0), Vec2::new(0.5, 0.0)).unwrap();
        assert_eq!((w, h), (4, 2));
        assert_eq!(&t[..4], &[Vec3::ONE, Vec3::Z, Vec3::ONE, Vec3::Z]);
        assert!(bake(2, 2, &src, Vec2::splat(1.5), Vec2::ZERO).is_err());
        assert!(bake(2, 2, &src, Vec2::ONE, Vec2::splat(0.25)).is_err());
    }
}
