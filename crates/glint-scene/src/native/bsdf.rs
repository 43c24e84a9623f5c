//! `bsdf diffuse|conductor|dielectric|thin_dielectric|plastic|metallic_roughness { … }`
//! inside a material: the physically based scattering the path tracer uses, with
//! Mitsuba 3's parameters under shorter names (`reflectance` for `specular_reflectance`,
//! `ior` for `int_ior`, `roughness` for the GGX `alpha`), and glTF's metallic-roughness
//! model with its `base` colour and `metallic` share.

use glam::Vec3;
use glint_core::desc::{BsdfDesc, ColorParam, ScalarParam};

use super::args::{self, Result, Seen};
use super::builder::{Registry, Source};
use super::tree::Node;

/// The BSDF types, in the order the documentation lists them.
pub const KINDS: [&str; 6] = ["diffuse", "conductor", "dielectric", "thin_dielectric", "plastic", "metallic_roughness"];

/// Default diffuse albedo of `diffuse` and `plastic` (Mitsuba's 0.5).
const DIFFUSE_REFLECTANCE: f32 = 0.5;

/// Default index of refraction inside a dielectric or a plastic's coat (glass).
const INT_IOR: f32 = 1.5;

/// Default index of refraction outside (vacuum, close enough to air).
const EXT_IOR: f32 = 1.0;

/// Default conductor: `eta` 0, `k` 1, a perfect mirror at every angle (Mitsuba's
/// `material "none"`).
const MIRROR_ETA: Vec3 = Vec3::ZERO;
const MIRROR_K: Vec3 = Vec3::ONE;

/// The properties each kind accepts, for the "expected one of" message.
fn allowed(kind: &str) -> &'static [&'static str] {
    match kind {
        "diffuse" => &["reflectance", "texture"],
        "conductor" => &["eta", "k", "specular", "specular_texture", "roughness", "roughness_texture"],
        "dielectric" => &["ior", "ext_ior", "reflectance", "transmittance", "roughness", "roughness_texture"],
        "thin_dielectric" => &["ior", "ext_ior", "reflectance", "transmittance"],
        "metallic_roughness" => {
            &["base", "texture", "metallic", "metallic_texture", "roughness", "roughness_texture", "ior"]
        }
        _ => &["diffuse", "texture", "ior", "ext_ior", "specular", "roughness", "roughness_texture", "nonlinear"],
    }
}

/// Every property a BSDF block can set; each kind reads the ones it accepts.
#[derive(Default)]
struct Props {
    /// `reflectance`, `specular`, `transmittance`, `diffuse`, `base`.
    colors: Vec<(&'static str, Vec3)>,
    /// `texture`, `specular_texture`, `roughness_texture`, `metallic_texture`: texture
    /// indices.
    textures: Vec<(&'static str, usize)>,
    metallic: Option<f32>,
    eta: Option<Vec3>,
    k: Option<Vec3>,
    roughness: Option<f32>,
    ior: Option<f32>,
    ext_ior: Option<f32>,
    nonlinear: bool,
}

impl Props {
    fn color(&self, name: &str) -> Option<Vec3> {
        self.colors.iter().find(|(n, _)| *n == name).map(|(_, c)| *c)
    }

    fn texture(&self, name: &str) -> Option<usize> {
        self.textures.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
    }

    /// A colour that may come from `texture`: the written value, else 1 (the texture
    /// alone) when there is a texture, else `default`.
    fn color_param(&self, name: &str, texture: &str, default: f32) -> ColorParam {
        let texture = self.texture(texture);
        let fallback = Vec3::splat(if texture.is_some() { 1.0 } else { default });
        ColorParam { value: self.color(name).unwrap_or(fallback), texture }
    }

    /// `roughness` and `roughness_texture`, as [`Self::color_param`] does it (default 0:
    /// smooth).
    fn roughness(&self) -> ScalarParam {
        let texture = self.texture("roughness_texture");
        let fallback = if texture.is_some() { 1.0 } else { 0.0 };
        ScalarParam { value: self.roughness.unwrap_or(fallback), texture }
    }

    /// `metallic` and `metallic_texture`, as [`Self::roughness`] does it (default 0:
    /// plastic).
    fn metallic(&self) -> ScalarParam {
        let texture = self.texture("metallic_texture");
        let fallback = if texture.is_some() { 1.0 } else { 0.0 };
        ScalarParam { value: self.metallic.unwrap_or(fallback), texture }
    }

    fn iors(&self) -> (f32, f32) {
        (self.ior.unwrap_or(INT_IOR), self.ext_ior.unwrap_or(EXT_IOR))
    }
}

/// Builds a BSDF from its kind node (`conductor { … }`), which [`KINDS`] has already
/// checked; textures are looked up by name in `textures`.
pub fn bsdf(src: &Source, kind: &Node, textures: &Registry) -> Result<BsdfDesc> {
    let allowed = allowed(&kind.name);
    let place = format!("bsdf {}", kind.name);
    let mut props = Props::default();
    let mut seen = Seen::default();
    for prop in kind.children() {
        let Some(name) = allowed.iter().copied().find(|n| *n == prop.name) else {
            return Err(args::unknown(src, prop, "property", &format!("in '{place}'"), allowed));
        };
        seen.once(src, prop, &place)?;
        match name {
            "reflectance" | "specular" | "transmittance" | "diffuse" | "base" => {
                props.colors.push((name, args::color(src, prop)?))
            }
            "texture" | "specular_texture" | "roughness_texture" | "metallic_texture" => {
                args::no_block(src, prop)?;
                let (texture, pos) = args::string(src, prop, "a texture name")?;
                props.textures.push((name, textures.lookup(src, pos, "texture", &texture)?));
            }
            "eta" => props.eta = Some(non_negative(src, prop)?),
            "k" => props.k = Some(non_negative(src, prop)?),
            "roughness" => {
                props.roughness = Some(args::number_where(src, prop, "0 or more (0 is smooth)", |x| x >= 0.0)?);
            }
            "metallic" => {
                props.metallic =
                    Some(args::number_where(src, prop, "from 0 (plastic) to 1 (metal)", |x| (0.0..=1.0).contains(&x))?);
            }
            "ior" => props.ior = Some(args::number_where(src, prop, "greater than 0", |x| x > 0.0)?),
            "ext_ior" => props.ext_ior = Some(args::number_where(src, prop, "greater than 0", |x| x > 0.0)?),
            _ => props.nonlinear = args::boolean(src, prop)?,
        }
    }
    let (int_ior, ext_ior) = props.iors();
    let one = |name| props.color(name).unwrap_or(Vec3::ONE);
    Ok(match kind.name.as_str() {
        "diffuse" => {
            BsdfDesc::Diffuse { reflectance: props.color_param("reflectance", "texture", DIFFUSE_REFLECTANCE) }
        }
        "conductor" => BsdfDesc::Conductor {
            eta: props.eta.unwrap_or(MIRROR_ETA),
            k: props.k.unwrap_or(MIRROR_K),
            specular: props.color_param("specular", "specular_texture", 1.0),
            alpha: props.roughness(),
        },
        "dielectric" => BsdfDesc::Dielectric {
            int_ior,
            ext_ior,
            reflectance: one("reflectance"),
            transmittance: one("transmittance"),
            alpha: props.roughness(),
        },
        "thin_dielectric" => BsdfDesc::ThinDielectric {
            int_ior,
            ext_ior,
            reflectance: one("reflectance"),
            transmittance: one("transmittance"),
        },
        "metallic_roughness" => BsdfDesc::MetallicRoughness {
            base: props.color_param("base", "texture", DIFFUSE_REFLECTANCE),
            metallic: props.metallic(),
            alpha: props.roughness(),
            ior: int_ior,
        },
        _ => BsdfDesc::Plastic {
            diffuse: props.color_param("diffuse", "texture", DIFFUSE_REFLECTANCE),
            int_ior,
            ext_ior,
            specular: one("specular"),
            alpha: props.roughness(),
            nonlinear: props.nonlinear,
        },
    })
}

/// `[x y z]` or one number, none negative (`eta`, `k`).
fn non_negative(src: &Source, prop: &Node) -> Result<Vec3> {
    let v = args::vec3_broadcast(src, prop)?;
    if v.min_element() >= 0.0 {
        Ok(v)
    } else {
        Err(src.invalid(
            args::value_pos(prop),
            format!("'{}' must not be negative, found {v}; each component is 0 or more", prop.name),
        ))
    }
}
