//! Spectra as glint's RGB: pbrt renders spectrally, glint in linear sRGB, so every
//! colour-like parameter is turned into an RGB triple here.
//!
//! - `rgb` values are taken as they are (converted from the scene's `ColorSpace` to
//!   linear sRGB first).
//! - Emission given as a spectrum (`blackbody`, `stdillum-*`) is normalized to a
//!   luminance of 1, as pbrt-v4 normalizes light spectra (`scale /=
//!   SpectrumToPhotometric(L)`), so `"rgb L" [1 1 1]` and `"spectrum L" "stdillum-D65"`
//!   both give white of luminance 1.
//! - Black bodies and sampled spectra are integrated against Wyman, Sloan and Shirley's
//!   analytic fit of the CIE 1931 observer (JCGT 2013), then XYZ → linear sRGB. This is
//!   an approximation: the fit is within a few percent of the tables.
//! - Named metals use the RGB complex indices of refraction of [`crate::mitsuba`]'s
//!   table; named glasses their index at about 589 nm.

use glam::{Mat3, Vec3};

use super::params::SpectrumValue;

/// The RGB colour spaces pbrt-v4 names, and how their linear RGB maps to linear sRGB.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum ColorSpace {
    #[default]
    Srgb,
    Rec2020,
    Aces2065,
    DciP3,
}

impl ColorSpace {
    /// The colour space pbrt calls `name`.
    pub fn named(name: &str) -> Option<Self> {
        Some(match name {
            "srgb" => Self::Srgb,
            "rec2020" => Self::Rec2020,
            "aces2065-1" => Self::Aces2065,
            "dci-p3" => Self::DciP3,
            _ => return None,
        })
    }

    /// `rgb` (in this space) as linear sRGB: the 3×3 matrix between the two spaces'
    /// primaries (with a Bradford adaptation from ACES's D60 white to D65).
    pub fn to_srgb(self, rgb: Vec3) -> Vec3 {
        let rows = match self {
            Self::Srgb => return rgb,
            Self::Rec2020 => [[1.6605, -0.5876, -0.0728], [-0.1246, 1.1329, -0.0083], [-0.0182, -0.1006, 1.1187]],
            Self::Aces2065 => [[2.5217, -1.1341, -0.3876], [-0.2765, 1.3727, -0.0962], [-0.0154, -0.1530, 1.1684]],
            Self::DciP3 => [[1.2249, -0.2247, 0.0], [-0.0420, 1.0419, 0.0], [-0.0197, -0.0786, 1.0979]],
        };
        Mat3::from_cols_array_2d(&rows).transpose() * rgb
    }
}

/// What a spectrum stands for, which decides how a spectral value becomes RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    /// Emitted light: spectra are normalized to luminance 1.
    Illuminant,
    /// A reflectance or other unitless quantity: spectra are lit by a white (6504 K) light.
    Albedo,
}

/// The RGB of `value`, or a message saying why it could not be read (an unknown name).
pub(super) fn rgb(value: &SpectrumValue, role: Role, space: ColorSpace) -> Result<Vec3, String> {
    let c = spectrum_rgb(value, role, space)?;
    if !c.is_finite() {
        return Err(format!("the spectrum {value:?} has no finite RGB value"));
    }
    Ok(c)
}

fn spectrum_rgb(value: &SpectrumValue, role: Role, space: ColorSpace) -> Result<Vec3, String> {
    Ok(match value {
        SpectrumValue::Rgb(c) => space.to_srgb(*c),
        SpectrumValue::Constant(v) => Vec3::splat(*v),
        SpectrumValue::Blackbody(t, scale) => {
            if *t <= 0.0 {
                return Err(format!("a black body needs a positive temperature, not {t}"));
            }
            blackbody_rgb(*t) * *scale
        }
        SpectrumValue::Samples(s) => sampled_rgb(s, role)?,
        SpectrumValue::Named(name) => named_rgb(name, role)?,
    })
}

/// The RGB of a named spectrum as a light or a reflectance.
fn named_rgb(name: &str, role: Role) -> Result<Vec3, String> {
    if let Some(rest) = name.strip_prefix("metal-") {
        let (metal, part) = rest.rsplit_once('-').ok_or_else(|| format!("unknown spectrum '{name}'"))?;
        let (eta, k) = metal_ior(metal).ok_or_else(|| format!("unknown metal in spectrum '{name}'"))?;
        return match part {
            "eta" => Ok(eta),
            "k" => Ok(k),
            _ => Err(format!("unknown spectrum '{name}'")),
        };
    }
    if let Some(eta) = glass_ior(name) {
        return Ok(Vec3::splat(eta));
    }
    let kelvin = match name {
        "stdillum-D65" | "stdillum-E" => return Ok(Vec3::ONE),
        "stdillum-D50" => 5003.0,
        "stdillum-A" => 2856.0,
        "illum-acesD60" => 6000.0,
        _ => return Err(format!("unknown spectrum '{name}'")),
    };
    let c = blackbody_rgb(kelvin);
    Ok(if role == Role::Illuminant { c } else { c / c.max_element() })
}

/// The RGB `(eta, k)` of pbrt-v4's named metals (`metal-Cu-eta`, …). Brass (CuZn),
/// which Mitsuba's table lacks, uses the common RGB fit (0.444, 0.527, 1.094) /
/// (3.695, 2.765, 1.829).
pub(super) fn metal_ior(metal: &str) -> Option<(Vec3, Vec3)> {
    match metal {
        "CuZn" => Some((Vec3::new(0.444, 0.527, 1.094), Vec3::new(3.695, 2.765, 1.829))),
        "Ag" | "Al" | "Au" | "Cu" | "MgO" | "TiO2" => crate::mitsuba::tables::named_conductor(metal),
        _ => None,
    }
}

/// The index of refraction at about 589 nm of pbrt-v4's named glasses (Schott data).
fn glass_ior(name: &str) -> Option<f32> {
    Some(match name {
        "glass-BK7" => 1.5168,
        "glass-BAF10" => 1.6700,
        "glass-FK51A" => 1.4866,
        "glass-LASF9" => 1.8503,
        "glass-F5" => 1.6034,
        "glass-F10" => 1.7283,
        "glass-F11" => 1.7847,
        _ => return None,
    })
}

/// One lobe of the CIE fit: a Gaussian with different widths left and right of `mu`.
fn lobe(lambda: f32, mu: f32, left: f32, right: f32) -> f32 {
    let s = if lambda < mu { left } else { right };
    (-0.5 * ((lambda - mu) / s).powi(2)).exp()
}

/// The CIE 1931 colour-matching functions at `lambda` nm (Wyman et al. 2013, eq. 2–4).
fn cie_xyz(lambda: f32) -> Vec3 {
    let x = 1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
        - 0.065 * lobe(lambda, 501.1, 20.4, 26.2);
    let y = 0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1);
    let z = 1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8);
    Vec3::new(x, y, z)
}

/// CIE XYZ → linear sRGB (D65).
fn xyz_to_srgb(xyz: Vec3) -> Vec3 {
    let rows = [[3.2406, -1.5372, -0.4986], [-0.9689, 1.8758, 0.0415], [0.0557, -0.2040, 1.0570]];
    Mat3::from_cols_array_2d(&rows).transpose() * xyz
}

/// Planck's law (relative: constant factors cancel in the normalization).
fn planck(lambda_nm: f32, kelvin: f32) -> f32 {
    let l = f64::from(lambda_nm) * 1e-9;
    let c2 = 1.4387769e-2;
    (1.0 / (l.powi(5) * ((c2 / (l * f64::from(kelvin))).exp() - 1.0))) as f32
}

/// XYZ of a spectrum `s(λ)` sampled every 5 nm over 360–830 nm.
fn integrate(s: impl Fn(f32) -> f32) -> Vec3 {
    (0..=94).map(|i| 360.0 + 5.0 * i as f32).map(|l| s(l) * cie_xyz(l)).sum()
}

/// The linear sRGB of a black body at `kelvin`, at luminance (Y) 1.
pub(super) fn blackbody_rgb(kelvin: f32) -> Vec3 {
    let xyz = integrate(|l| planck(l, kelvin));
    xyz_to_srgb(xyz / xyz.y).max(Vec3::ZERO)
}

/// A spectrum given as `(wavelength, value)` pairs, linearly interpolated (constant
/// beyond its ends).
fn sampled_rgb(samples: &[(f32, f32)], role: Role) -> Result<Vec3, String> {
    if samples.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err("the wavelengths of a sampled spectrum must increase".to_owned());
    }
    let at = |l: f32| -> f32 {
        let i = samples.partition_point(|s| s.0 < l);
        match (i.checked_sub(1).map(|j| samples[j]), samples.get(i)) {
            (Some(a), Some(b)) => a.1 + (b.1 - a.1) * (l - a.0) / (b.0 - a.0),
            (None, Some(b)) => b.1,
            (Some(a), None) => a.1,
            (None, None) => 0.0,
        }
    };
    Ok(match role {
        Role::Illuminant => {
            let xyz = integrate(at);
            if xyz.y <= 0.0 {
                return Ok(Vec3::ZERO);
            }
            xyz_to_srgb(xyz / xyz.y).max(Vec3::ZERO)
        }
        Role::Albedo => {
            let white = integrate(|l| planck(l, 6504.0));
            xyz_to_srgb(integrate(|l| at(l) * planck(l, 6504.0)) / white.y).max(Vec3::ZERO)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blackbodies_are_warm_or_cool_with_unit_luminance() {
        let warm = blackbody_rgb(2700.0);
        let cool = blackbody_rgb(10000.0);
        assert!(warm.x > warm.z && cool.z > cool.x, "{warm} {cool}");
        let d65ish = blackbody_rgb(6504.0);
        assert!((d65ish / d65ish.max_element()).min_element() > 0.8, "{d65ish}");
        let y = Vec3::new(0.2126, 0.7152, 0.0722).dot(warm);
        assert!((y - 1.0).abs() < 0.05, "{y}");
    }

    #[test]
    fn a_flat_reflectance_spectrum_is_grey() {
        let grey = sampled_rgb(&[(400.0, 0.5), (700.0, 0.5)], Role::Albedo).unwrap();
        assert!((grey - Vec3::splat(0.5)).abs().max_element() < 0.05, "{grey}");
    }

    #[test]
    fn colour_spaces_keep_white() {
        for s in [ColorSpace::Rec2020, ColorSpace::DciP3] {
            assert!((s.to_srgb(Vec3::ONE) - Vec3::ONE).abs().max_element() < 0.01);
        }
        assert!((ColorSpace::Aces2065.to_srgb(Vec3::ONE) - Vec3::ONE).abs().max_element() < 0.01);
        assert_eq!(
            rgb(&SpectrumValue::Named("metal-Cu-k".into()), Role::Albedo, ColorSpace::Srgb).map(|v| v.x > 3.0),
            Ok(true)
        );
        assert!(rgb(&SpectrumValue::Named("nope".into()), Role::Albedo, ColorSpace::Srgb).is_err());
    }
}
