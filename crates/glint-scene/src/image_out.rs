//! Writing rendered images: PNG (8/16-bit sRGB), EXR (linear float) and PPM.
//!
//! Files are written to a temporary sibling and renamed into place, so an error or an
//! interrupted process never leaves a half-written image under the requested name.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::atomic_file::write_atomically;
use glint_core::film::{Image, Transfer};
use image::{ImageBuffer, ImageFormat, Rgb};

/// The encodings glint writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputFormat {
    /// 8 bits per channel, sRGB.
    Png8,
    /// 16 bits per channel, sRGB.
    Png16,
    /// 32-bit float per channel, linear: keeps values above 1 for compositing.
    Exr,
    /// Binary PPM (P6), 8-bit sRGB: trivially readable by any tool.
    Ppm,
}

impl OutputFormat {
    /// The format a file name asks for, by extension.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(Self::Png8),
            "exr" => Some(Self::Exr),
            "ppm" => Some(Self::Ppm),
            _ => None,
        }
    }
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("cannot write {path}: {source}")]
    Io { path: PathBuf, source: std::io::Error },
    #[error("cannot encode {path}: {source}")]
    Encode { path: PathBuf, source: image::ImageError },
}

/// Encodes `image` as `format` and atomically places it at `path`. `transfer` encodes
/// the 8/16-bit formats; EXR always stores the computed values as they are.
pub fn write_image(image: &Image, path: &Path, format: OutputFormat, transfer: Transfer) -> Result<(), WriteError> {
    write_atomically(
        path,
        |tmp| encode(image, tmp, format, transfer),
        |source| WriteError::Io { path: path.to_owned(), source },
    )
}

/// Writes a multi-layer OpenEXR file (32-bit float): the first image as the plain
/// `R`, `G`, `B` channels every viewer shows, the others as named layers (`albedo.R`,
/// `normal.X`, `depth.Z`, …): each layer names the channels it keeps, its image's first
/// channels in order. Atomic like [`write_image`].
pub fn write_exr_layers(path: &Path, beauty: &Image, layers: &[(&str, &[&str], &Image)]) -> Result<(), WriteError> {
    use exr::prelude::{AnyChannel, AnyChannels, FlatSamples, WritableImage};
    let channel = |name: String, image: &Image, k: usize| {
        AnyChannel::new(name.as_str(), FlatSamples::F32(image.pixels.iter().map(|p| p[k]).collect()))
    };
    let mut channels = exr::prelude::SmallVec::new();
    for (k, name) in ["R", "G", "B"].into_iter().enumerate() {
        channels.push(channel(name.to_string(), beauty, k));
    }
    for (layer, names, image) in layers {
        for (k, name) in names.iter().enumerate() {
            channels.push(channel(format!("{layer}.{name}"), image, k));
        }
    }
    let size = (beauty.width as usize, beauty.height as usize);
    let image = exr::prelude::Image::from_channels(size, AnyChannels::sort(channels));
    write_atomically(
        path,
        |tmp| {
            image
                .write()
                .to_file(tmp)
                .map_err(|e| WriteError::Io { path: tmp.to_owned(), source: std::io::Error::other(e.to_string()) })
        },
        |source| WriteError::Io { path: path.to_owned(), source },
    )
}

fn encode(image: &Image, tmp: &Path, format: OutputFormat, transfer: Transfer) -> Result<(), WriteError> {
    let io_err = |source| WriteError::Io { path: tmp.to_owned(), source };
    let enc_err = |source| WriteError::Encode { path: tmp.to_owned(), source };
    let (w, h) = (image.width, image.height);
    match format {
        OutputFormat::Png8 => {
            let buf: ImageBuffer<Rgb<u8>, _> =
                ImageBuffer::from_raw(w, h, image.encode8(transfer)).expect("buffer size matches");
            buf.save_with_format(tmp, ImageFormat::Png).map_err(enc_err)
        }
        OutputFormat::Png16 => {
            let buf: ImageBuffer<Rgb<u16>, _> =
                ImageBuffer::from_raw(w, h, image.encode16(transfer)).expect("buffer size matches");
            buf.save_with_format(tmp, ImageFormat::Png).map_err(enc_err)
        }
        OutputFormat::Exr => {
            let data: Vec<f32> = image.pixels.iter().flat_map(|p| p.to_array()).collect();
            let buf: ImageBuffer<Rgb<f32>, _> = ImageBuffer::from_raw(w, h, data).expect("buffer size matches");
            buf.save_with_format(tmp, ImageFormat::OpenExr).map_err(enc_err)
        }
        OutputFormat::Ppm => {
            let file = fs::File::create(tmp).map_err(io_err)?;
            let mut out = BufWriter::new(file);
            write!(out, "P6\n{w} {h}\n255\n").map_err(io_err)?;
            out.write_all(&image.encode8(transfer)).map_err(io_err)?;
            // Flushed, not synced: like the other formats, an image is replaced whole by
            // the rename, and a crash at worst loses it (checkpoints are what is synced).
            out.flush().map_err(io_err)
        }
    }
}

/// Reads a PNG/PPM/EXR back as linear RGB (the inverse of [`write_image`]), for image
/// comparisons in tests and benchmarks; the file is read within the image size limit
/// of [`crate::input`].
pub fn read_image(path: &Path) -> Result<Image, image::ImageError> {
    let bytes = crate::input::read_bytes(path, crate::input::InputKind::Image)
        .map_err(|e| image::ImageError::IoError(std::io::Error::other(e)))?;
    let format = image::ImageFormat::from_path(path)?;
    let decoded = image::load_from_memory_with_format(&bytes, format)?;
    let is_float = matches!(decoded.color(), image::ColorType::Rgb32F | image::ColorType::Rgba32F);
    let rgb = decoded.to_rgb32f();
    let mut out = Image::new(rgb.width(), rgb.height());
    for (dst, px) in out.pixels.iter_mut().zip(rgb.pixels()) {
        let [r, g, b] = px.0;
        *dst = if is_float {
            glam::Vec3::new(r, g, b)
        } else {
            glam::Vec3::new(r, g, b).map(glint_core::film::srgb_to_linear)
        };
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn sample_image() -> Image {
        let mut img = Image::new(4, 3);
        for (i, p) in img.pixels.iter_mut().enumerate() {
            *p = Vec3::new(i as f32 / 12.0, 0.5, 1.0 - i as f32 / 12.0);
        }
        img
    }

    #[test]
    fn every_format_round_trips() {
        let dir = std::env::temp_dir().join(format!("glint-image-out-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let img = sample_image();
        for (name, format, tolerance) in [
            ("a.png", OutputFormat::Png8, 4e-3),
            ("b.png", OutputFormat::Png16, 1e-4),
            ("c.exr", OutputFormat::Exr, 1e-6),
            ("d.ppm", OutputFormat::Ppm, 4e-3),
        ] {
            let path = dir.join(name);
            write_image(&img, &path, format, Transfer::Srgb).unwrap();
            let back = read_image(&path).unwrap();
            assert!(img.mean_abs_diff(&back) < tolerance, "{name}: {}", img.mean_abs_diff(&back));
        }
        // No temporary files are left behind.
        let leftovers = fs::read_dir(&dir)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().ends_with(".tmp"))
            .count();
        assert_eq!(leftovers, 0);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn layered_exr_keeps_every_channel() {
        use exr::prelude::{ReadChannels, ReadLayers};
        let path = std::env::temp_dir().join(format!("glint-layers-{}.exr", std::process::id()));
        let beauty = sample_image();
        let mut depth = Image::new(4, 3);
        depth.pixels.iter_mut().enumerate().for_each(|(i, p)| *p = Vec3::splat(i as f32 * 10.0));
        write_exr_layers(&path, &beauty, &[("albedo", &["R", "G", "B"], &depth), ("depth", &["Z"], &depth)]).unwrap();
        // The plain colour reads back as the image, the layer by its channel names.
        assert!(read_image(&path).unwrap().mean_abs_diff(&beauty) < 1e-6);
        let read = exr::prelude::read().no_deep_data().largest_resolution_level().all_channels().first_valid_layer();
        let layers = read.all_attributes().from_file(&path).unwrap();
        let names: Vec<String> = layers.layer_data.channel_data.list.iter().map(|c| c.name.to_string()).collect();
        assert_eq!(names, ["B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "depth.Z"]);
        let albedo_r = &layers.layer_data.channel_data.list[5].sample_data;
        assert_eq!(albedo_r.value_by_flat_index(7).to_f32(), 70.0);
        fs::remove_file(&path).unwrap();
    }

    #[test]
    fn failed_write_leaves_nothing() {
        let path = std::env::temp_dir().join("glint-no-such-dir-xyz").join("out.png");
        assert!(write_image(&sample_image(), &path, OutputFormat::Png8, Transfer::Srgb).is_err());
        assert!(!path.exists());
    }
}
