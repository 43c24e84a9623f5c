//! Image files → [`TextureDesc::Image`] in linear RGB.
//!
//! Shading adds and scales radiance, which is only meaningful in linear light, while
//! PNG and JPEG files store sRGB-encoded values; so texels are decoded through the sRGB
//! transfer function (IEC 61966-2-1) once, here, and never again while rendering.
//! Scenes made for display-referred renderers (the course formats, which shade the
//! stored 0–255 values directly) load their textures with [`Transfer::Identity`]
//! through [`load_texture_encoded`] instead.

use std::io::Cursor;
use std::path::{Path, PathBuf};

use glam::Vec3;
use glint_core::desc::{TextureDesc, Transfer};
use image::{DynamicImage, ImageFormat, ImageReader, Limits};

use crate::input::{self, InputError, InputKind};

/// Largest texture side accepted, in pixels; bigger files are almost surely a mistake
/// and would need gigabytes once decoded to floats.
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// Why a texture file could not be used; each variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be read: missing, not a regular file, or larger than the
    /// image size limit ([`crate::input`]).
    #[error("cannot read texture file '{}': {}", .0.path.display(), .0.problem)]
    Input(InputError),
    /// The file is not an image of a format the caller accepts.
    #[error(
        "texture file '{}' is {found}; textures must be {allowed} images",
        path.display()
    )]
    UnsupportedFormat {
        /// The file.
        path: PathBuf,
        /// What it was recognised as ("an OpenEXR image", "not a recognised image").
        found: String,
        /// The formats that would have been accepted ("PNG or JPEG").
        allowed: &'static str,
    },
    /// The image is larger than [`MAX_TEXTURE_SIDE`] on a side.
    #[error(
        "texture file '{}' is {width}x{height} pixels; at most {MAX_TEXTURE_SIDE} pixels per side are allowed",
        path.display()
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its width in pixels.
        width: u32,
        /// Its height in pixels.
        height: u32,
    },
    /// The image has more pixels than the limit ([`input::InputLimits::image_pixels`]).
    #[error(
        "texture file '{}' is {width}x{height} pixels, more than the {limit} pixels allowed; \
         raise the limit with --input-limit pixels=N",
        path.display()
    )]
    TooManyPixels {
        /// The file.
        path: PathBuf,
        /// Its width in pixels.
        width: u32,
        /// Its height in pixels.
        height: u32,
        /// The most pixels allowed.
        limit: u64,
    },
    /// The decoder rejected the data (corrupt file, unsupported variant, memory limit).
    #[error("cannot decode texture file '{}': {source}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        source: image::ImageError,
    },
}

pub use glint_core::film::srgb_to_linear;

/// Loads a PNG or JPEG file (sRGB-decoded) or an OpenEXR or Radiance HDR file (linear,
/// values above 1 kept: environment maps) as a linear-RGB texture named `name`, row 0
/// at the top.
///
/// Alpha is ignored; 16-bit PNGs keep their precision.
///
/// # Errors
///
/// A [`TextureError`] naming `path` when the file cannot be read, is not one of those
/// formats, is larger than [`MAX_TEXTURE_SIDE`] on a side or than the size limits of
/// [`crate::input`], or does not decode.
pub fn load_texture(name: &str, path: &Path) -> Result<TextureDesc, TextureError> {
    load_texture_hdr(name, path, Transfer::Srgb)
}

/// Loads a PNG or JPEG file whose stored values are encoded by `transfer`: with
/// [`Transfer::Srgb`] (what [`load_texture`] does) texels are decoded to linear light;
/// with [`Transfer::Identity`] the stored values, scaled to [0, 1], are used as they are.
///
/// # Errors
///
/// As [`load_texture`].
pub fn load_texture_encoded(name: &str, path: &Path, transfer: Transfer) -> Result<TextureDesc, TextureError> {
    load_image(name, path, transfer, false)
}

/// Loads a PNG or JPEG file (decoded by `transfer`, as [`load_texture_encoded`] does) or
/// an OpenEXR or Radiance HDR (`.hdr`, RGBE) file, whose values are linear already and
/// are kept as they are, above 1 included: for environment maps and Mitsuba bitmaps.
///
/// # Errors
///
/// As [`load_texture`], with OpenEXR and Radiance HDR accepted.
pub fn load_texture_hdr(name: &str, path: &Path, transfer: Transfer) -> Result<TextureDesc, TextureError> {
    load_image(name, path, transfer, true)
}

/// The loader behind the public functions; `float_formats` admits EXR and HDR files.
fn load_image(name: &str, path: &Path, transfer: Transfer, float_formats: bool) -> Result<TextureDesc, TextureError> {
    let bytes = input::read_bytes(path, InputKind::Image).map_err(TextureError::Input)?;
    decode_image(name, path, &bytes, transfer, float_formats)
}

/// Decodes the bytes of an image file (`path` names it in errors and in the texture)
/// within the size limits: PNG or JPEG, and with `float_formats` OpenEXR or Radiance HDR.
/// Public for images already in memory (glTF's embedded ones) and for fuzzing the decoder.
///
/// # Errors
///
/// As [`load_texture`], less the errors of reading the file.
pub fn decode_image(
    name: &str,
    path: &Path,
    bytes: &[u8],
    transfer: Transfer,
    float_formats: bool,
) -> Result<TextureDesc, TextureError> {
    let decode_error = |source| TextureError::Decode { path: path.to_path_buf(), source };
    // Reading from memory cannot fail; the format is guessed from the first bytes.
    let open = || ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| decode_error(e.into()));
    let reader = open()?;
    let float_image = match reader.format() {
        Some(ImageFormat::Png | ImageFormat::Jpeg) => false,
        Some(ImageFormat::OpenExr | ImageFormat::Hdr) if float_formats => true,
        other => {
            return Err(TextureError::UnsupportedFormat {
                path: path.to_path_buf(),
                found: other.map_or_else(|| "not a recognised image".to_owned(), |f| format!("a {f:?} image")),
                allowed: if float_formats { "PNG, JPEG, OpenEXR or Radiance HDR" } else { "PNG or JPEG" },
            });
        }
    };
    // Read the header first so an absurd size is reported as such, before any decoding.
    let (width, height) = reader.into_dimensions().map_err(decode_error)?;
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(TextureError::TooLarge { path: path.to_path_buf(), width, height });
    }
    let max_pixels = input::limits().image_pixels;
    if u64::from(width) * u64::from(height) > max_pixels {
        return Err(TextureError::TooManyPixels { path: path.to_path_buf(), width, height, limit: max_pixels });
    }
    let mut reader = open()?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    // The widest decoded form is RGBA in 32-bit floats: 16 bytes a pixel.
    limits.max_alloc = Some(max_pixels.saturating_mul(16));
    reader.limits(limits);
    let image = reader.decode().map_err(decode_error)?;
    Ok(TextureDesc::Image {
        name: name.to_owned(),
        path: path.display().to_string(),
        width: image.width(),
        height: image.height(),
        texels: if float_image { linear_texels(&image) } else { decoded_texels(&image, transfer) },
        sampling: Default::default(),
    })
}

/// The pixels of a floating-point image as they are stored (linear, unclamped).
fn linear_texels(image: &DynamicImage) -> Vec<Vec3> {
    image.to_rgb32f().pixels().map(|p| Vec3::new(p[0], p[1], p[2])).collect()
}

/// Decodes every pixel through the inverse of `transfer`, rows top to bottom as the
/// file stores them.
fn decoded_texels(image: &DynamicImage, transfer: Transfer) -> Vec<Vec3> {
    let decode_unit: fn(f32) -> f32 = match transfer {
        Transfer::Srgb => srgb_to_linear,
        Transfer::Identity => |c| c,
    };
    let sixteen_bit = matches!(
        image,
        DynamicImage::ImageLuma16(_)
            | DynamicImage::ImageLumaA16(_)
            | DynamicImage::ImageRgb16(_)
            | DynamicImage::ImageRgba16(_)
    );
    if sixteen_bit {
        let scale = 1.0 / f32::from(u16::MAX);
        let decode = |c: u16| decode_unit(f32::from(c) * scale);
        image.to_rgb16().pixels().map(|p| Vec3::new(decode(p[0]), decode(p[1]), decode(p[2]))).collect()
    } else {
        // 256 possible values: decode each once.
        let table: Vec<f32> = (0..=255u8).map(|c| decode_unit(f32::from(c) / 255.0)).collect();
        image
            .to_rgb8()
            .pixels()
            .map(|p| Vec3::new(table[usize::from(p[0])], table[usize::from(p[1])], table[usize::from(p[2])]))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_transfer_function_endpoints_and_midpoint() {
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert!((srgb_to_linear(1.0) - 1.0).abs() < 1e-6);
        // 0.5 encoded is about 21.4 % linear light.
        assert!((srgb_to_linear(0.5) - 0.214_041).abs() < 1e-5);
        // The linear toe and the power segment meet continuously.
        let below = srgb_to_linear(0.04045);
        let above = srgb_to_linear(0.040_451);
        assert!((below - above).abs() < 1e-6);
    }

    #[test]
    fn identity_transfer_keeps_the_stored_values() {
        let dir = std::env::temp_dir().join(format!("glint-texture-io-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("two.png");
        image::RgbImage::from_raw(2, 1, vec![128, 0, 255, 64, 32, 16]).unwrap().save(&path).unwrap();
        let texels = |transfer| match load_texture_encoded("t", &path, transfer).unwrap() {
            TextureDesc::Image { texels, width: 2, height: 1, .. } => texels,
            other => panic!("{other:?}"),
        };
        let stored = texels(Transfer::Identity);
        assert_eq!(stored[0], Vec3::new(128.0 / 255.0, 0.0, 1.0));
        assert_eq!(stored[1], Vec3::new(64.0, 32.0, 16.0) / 255.0);
        let linear = texels(Transfer::Srgb);
        assert!((linear[0].x - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6);
        assert!(linear[1].x < stored[1].x);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
