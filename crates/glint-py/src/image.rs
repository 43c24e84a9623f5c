//! numpy arrays → glint images: writing files and encoding PNGs for notebooks.

use std::path::PathBuf;

use glint_core::film::{Image, Transfer};
use glint_core::math::Vec3;
use glint_scene::image_out::{OutputFormat, write_image};
use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// Writes an (height, width, 3) float32 array of linear RGB to `path`, atomically:
/// PNG (8-bit, or 16-bit with `format="png16"`), EXR (32-bit float, linear) or PPM,
/// chosen by `format` or else by the extension. `transfer` encodes the 8/16-bit ones.
#[pyfunction]
#[pyo3(signature = (path, image, transfer="srgb", format=None))]
pub fn write(
    py: Python<'_>,
    path: PathBuf,
    image: PyReadonlyArray3<'_, f32>,
    transfer: &str,
    format: Option<&str>,
) -> PyResult<()> {
    let format = output_format(&path, format)?;
    let transfer = parse_transfer(transfer)?;
    let image = from_array(&image)?;
    py.detach(|| write_image(&image, &path, format, transfer)).map_err(|e| PyOSError::new_err(e.to_string()))
}

/// Reads a PNG, PPM or EXR file as linear RGB, a float32 array (height, width, 3).
#[pyfunction]
pub fn read<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let image = py
        .detach(|| glint_scene::image_out::read_image(&path))
        .map_err(|e| PyOSError::new_err(format!("cannot read {}: {e}", path.display())))?;
    crate::render::to_array(py, &image)
}

/// The array as 8-bit PNG bytes, for Jupyter's `_repr_png_`.
#[pyfunction]
#[pyo3(signature = (image, transfer="srgb"))]
pub fn encode_png<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<'_, f32>,
    transfer: &str,
) -> PyResult<Bound<'py, PyBytes>> {
    use image::ImageEncoder;
    let transfer = parse_transfer(transfer)?;
    let image = from_array(&image)?;
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(&image.encode8(transfer), image.width, image.height, image::ExtendedColorType::Rgb8)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(PyBytes::new(py, &png))
}

/// The format `format` names, or else the one `path`'s extension asks for.
fn output_format(path: &std::path::Path, format: Option<&str>) -> PyResult<OutputFormat> {
    match format {
        Some("png") => Ok(OutputFormat::Png8),
        Some("png16") => Ok(OutputFormat::Png16),
        Some("exr") => Ok(OutputFormat::Exr),
        Some("ppm") => Ok(OutputFormat::Ppm),
        Some(other) => {
            Err(PyValueError::new_err(format!("format='{other}' is not one of 'png', 'png16', 'exr', 'ppm'")))
        }
        None => OutputFormat::from_path(path).ok_or_else(|| {
            PyValueError::new_err(format!(
                "cannot tell the image format of '{}': use .png, .exr or .ppm, or pass format=",
                path.display()
            ))
        }),
    }
}

fn parse_transfer(transfer: &str) -> PyResult<Transfer> {
    match transfer {
        "srgb" => Ok(Transfer::Srgb),
        "identity" => Ok(Transfer::Identity),
        other => Err(PyValueError::new_err(format!("transfer='{other}' is not one of 'srgb', 'identity'"))),
    }
}

/// An (height, width, 3) array as a glint image.
fn from_array(array: &PyReadonlyArray3<'_, f32>) -> PyResult<Image> {
    let [height, width, channels] = array.shape() else { unreachable!("a 3-D array") };
    if *channels != 3 || *height == 0 || *width == 0 {
        return Err(PyValueError::new_err(format!(
            "expected an image of shape (height, width, 3), found {:?}",
            array.shape()
        )));
    }
    let side = |n: usize| u32::try_from(n).map_err(|_| PyValueError::new_err("the image is too large"));
    let view = array.as_array();
    let pixels = (0..*height)
        .flat_map(|y| (0..*width).map(move |x| (y, x)))
        .map(|(y, x)| Vec3::new(view[[y, x, 0]], view[[y, x, 1]], view[[y, x, 2]]))
        .collect();
    Ok(Image { width: side(*width)?, height: side(*height)?, pixels })
}
