//! `Material` and `MakeNamedMaterial` → a [`MaterialDesc`] with a [`BsdfDesc`].
//!
//! | pbrt-v4        | glint                                                       |
//! |----------------|-------------------------------------------------------------|
//! | diffuse        | Diffuse                                                     |
//! | conductor      | Conductor (`eta`/`k` spectra → RGB; `reflectance` → k)     |
//! | dielectric     | Dielectric                                                  |
//! | thindielectric | ThinDielectric                                              |
//! | coateddiffuse  | Plastic (the coat's thickness and albedo are not modelled)  |
//! | coatedconductor| Conductor of the base (warning)                             |
//! | mix            | the first material (warning)                                |
//! | interface      | a thin dielectric of index 1, which light passes (warning)  |
//! | v3 matte, plastic, metal, mirror, glass | their v4 counterparts (warning) |
//! | others         | Diffuse of their `reflectance` (warning)                    |
//!
//! Roughness: with `remaproughness` (pbrt's default) pbrt's `RoughnessToAlpha` is
//! `alpha = sqrt(roughness)`; otherwise the roughness is alpha. glint's microfacet
//! lobes are isotropic, so different `uroughness` and `vroughness` are averaged.

use glam::Vec3;
use glint_core::desc::{BsdfDesc, ColorParam, MaterialDesc, MicrofacetKind, NormalMapDesc, ScalarParam, Transfer};

use super::Reader;
use super::params::{Params, SpectrumValue};
use super::spectra::{self, Role};
use super::textures::{color_param, scalar_param};
use crate::error::SceneError;

/// pbrt-v4's material for shapes when none was set: diffuse, reflectance 0.5.
pub(super) fn default_material() -> MaterialDesc {
    let reflectance = ColorParam::constant(Vec3::splat(0.5));
    desc("pbrt default".to_owned(), BsdfDesc::Diffuse { reflectance }, reflectance)
}

/// A material scattering like `bsdf`, the Phong fields showing `base` as its colour.
fn desc(name: String, bsdf: BsdfDesc, base: ColorParam) -> MaterialDesc {
    MaterialDesc {
        name,
        diffuse: base.value,
        texture: base.texture,
        bsdf: Some(bsdf),
        two_sided: true,
        microfacet: MicrofacetKind::Ggx,
        ..MaterialDesc::default()
    }
}

/// Reads a material of type `ty` and returns its index in the scene.
pub(super) fn material(r: &mut Reader, ty: &str, p: &Params, name: Option<&str>) -> Result<usize, SceneError> {
    let label = name.map_or_else(|| format!("{ty}@{}", p.origin()), str::to_owned);
    let (bsdf, base) = bsdf(r, ty, p)?;
    if p.has("displacement") {
        p.get("displacement");
        r.warnings.push(p.warning("\"displacement\" is not supported and is ignored"));
    }
    let mut material = desc(label, bsdf, base);
    material.normal_map = normal_map(r, p)?;
    Ok(r.add_material(material))
}

/// `"string normalmap"`: an image read linearly, as pbrt-v4 reads it, whose texels
/// are normals in the frame of ∂p/∂u and the shading normal.
fn normal_map(r: &mut Reader, p: &Params) -> Result<Option<NormalMapDesc>, SceneError> {
    let Some(file) = p.string("normalmap")? else { return Ok(None) };
    let path = p.src.dir.join(file);
    let texture = crate::texture_io::load_texture_encoded(&format!("normalmap {file}"), &path, Transfer::Identity)
        .map_err(|e| p.error(e.to_string()))?;
    r.scene.textures.push(texture);
    Ok(Some(NormalMapDesc { texture: r.scene.textures.len() - 1, scale: 1.0 }))
}

/// The BSDF of a material type and the colour the Whitted integrator shows for it.
fn bsdf(r: &mut Reader, ty: &str, p: &Params) -> Result<(BsdfDesc, ColorParam), SceneError> {
    let grey = |v: f32| ColorParam::constant(Vec3::splat(v));
    Ok(match ty {
        "diffuse" => {
            let reflectance = color_param(r, p, "reflectance", Vec3::splat(0.5))?;
            (BsdfDesc::Diffuse { reflectance }, reflectance)
        }
        "conductor" => conductor(r, p)?,
        "dielectric" => {
            let eta = eta(r, p)?;
            let alpha = alpha(r, p)?;
            (
                BsdfDesc::Dielectric {
                    int_ior: eta,
                    ext_ior: 1.0,
                    reflectance: Vec3::ONE,
                    transmittance: Vec3::ONE,
                    alpha,
                },
                grey(0.0),
            )
        }
        "thindielectric" => {
            let eta = eta(r, p)?;
            let bsdf = BsdfDesc::ThinDielectric {
                int_ior: eta,
                ext_ior: 1.0,
                reflectance: Vec3::ONE,
                transmittance: Vec3::ONE,
            };
            (bsdf, grey(0.0))
        }
        "coateddiffuse" => {
            let diffuse = color_param(r, p, "reflectance", Vec3::splat(0.5))?;
            let eta = eta(r, p)?;
            let alpha = alpha(r, p)?;
            approximate_coat(r, p);
            (
                BsdfDesc::Plastic { diffuse, int_ior: eta, ext_ior: 1.0, specular: Vec3::ONE, alpha, nonlinear: false },
                diffuse,
            )
        }
        "coatedconductor" => {
            r.warnings.push(p.warning("approximated by its conductor base without the dielectric coat"));
            for coat in ["interface.roughness", "interface.uroughness", "interface.vroughness", "interface.eta"] {
                p.get(coat);
            }
            approximate_coat(r, p);
            conductor_prefixed(r, p, "conductor.")?
        }
        "mix" => {
            let first = p.strings("materials")?.and_then(|m| m.first().cloned());
            p.get("amount");
            r.warnings.push(p.warning("a mix of materials is approximated by its first material"));
            match first.and_then(|m| r.named_materials.get(&m).copied()) {
                Some(m) => {
                    let mat = &r.scene.materials[m];
                    let base = ColorParam { value: mat.diffuse, texture: mat.texture };
                    (mat.bsdf.unwrap_or(BsdfDesc::Diffuse { reflectance: base }), base)
                }
                None => return Err(p.error("\"string materials\" must name two materials defined before")),
            }
        }
        "interface" | "" | "none" => {
            r.warnings.push(p.warning(
                "an interface (invisible) material is approximated by a thin sheet of index 1, which light passes",
            ));
            let bsdf = BsdfDesc::ThinDielectric {
                int_ior: 1.0,
                ext_ior: 1.0,
                reflectance: Vec3::ONE,
                transmittance: Vec3::ONE,
            };
            (bsdf, grey(0.0))
        }
        "matte" | "plastic" | "metal" | "mirror" | "glass" => v3_material(r, ty, p)?,
        other => {
            r.warnings.push(p.warning(format!("material '{other}' is approximated by a diffuse one")));
            let reflectance = color_param(r, p, "reflectance", Vec3::splat(0.5))?;
            for param in &p.list {
                p.get(&param.name);
            }
            (BsdfDesc::Diffuse { reflectance }, reflectance)
        }
    })
}

/// pbrt-v3's materials, mapped onto the nearest pbrt-v4 ones with a warning (v3's
/// roughness remapping differs from v4's square root, which is used).
fn v3_material(r: &mut Reader, ty: &str, p: &Params) -> Result<(BsdfDesc, ColorParam), SceneError> {
    r.warnings.push(p.warning(format!("pbrt-v3 material '{ty}' is approximated by its pbrt-v4 counterpart")));
    let grey = |v: f32| ColorParam::constant(Vec3::splat(v));
    Ok(match ty {
        "matte" => {
            let reflectance = color_param(r, p, "Kd", Vec3::splat(0.5))?;
            (BsdfDesc::Diffuse { reflectance }, reflectance)
        }
        "plastic" => {
            let diffuse = color_param(r, p, "Kd", Vec3::splat(0.25))?;
            let specular = color_param(r, p, "Ks", Vec3::splat(0.25))?.value;
            let alpha = alpha_named(r, p, "roughness", "roughness", "roughness")?;
            (BsdfDesc::Plastic { diffuse, int_ior: 1.5, ext_ior: 1.0, specular, alpha, nonlinear: false }, diffuse)
        }
        "metal" => conductor(r, p)?,
        "mirror" => {
            let specular = color_param(r, p, "Kr", Vec3::splat(0.9))?;
            let alpha = ScalarParam::constant(0.0);
            (BsdfDesc::Conductor { eta: Vec3::ZERO, k: Vec3::ONE, specular, alpha }, grey(0.8))
        }
        _ => {
            let eta = p.float_or("index", 1.5)?;
            let reflectance = color_param(r, p, "Kr", Vec3::ONE)?.value;
            let transmittance = color_param(r, p, "Kt", Vec3::ONE)?.value;
            let alpha = ScalarParam::constant(0.0);
            (BsdfDesc::Dielectric { int_ior: eta, ext_ior: 1.0, reflectance, transmittance, alpha }, grey(0.0))
        }
    })
}

/// Warns about the coat parameters glint's plastic does not model.
fn approximate_coat(r: &mut Reader, p: &Params) {
    for unmodelled in ["thickness", "albedo", "g", "maxdepth", "nsamples"] {
        if p.has(unmodelled) {
            p.get(unmodelled);
            r.warnings.push(p.warning(format!("the coat's \"{unmodelled}\" is not modelled and is ignored")));
        }
    }
}

fn conductor(r: &mut Reader, p: &Params) -> Result<(BsdfDesc, ColorParam), SceneError> {
    conductor_prefixed(r, p, "")
}

/// A conductor whose parameters are named with `prefix` (`conductor.` in a coated one).
fn conductor_prefixed(r: &mut Reader, p: &Params, prefix: &str) -> Result<(BsdfDesc, ColorParam), SceneError> {
    let name = |n: &str| format!("{prefix}{n}");
    let alpha = alpha_named(r, p, &name("roughness"), &name("uroughness"), &name("vroughness"))?;
    let (eta, k) = if let Some(refl) = p.spectrum(&name("reflectance"))? {
        // pbrt-v4: a reflectance r means eta = 1, k = 2·sqrt(r)/sqrt(1 − r).
        let r = albedo(p, &name("reflectance"), &refl, r)?.clamp(Vec3::ZERO, Vec3::splat(0.9999));
        (Vec3::ONE, 2.0 * r.powf(0.5) / (Vec3::ONE - r).powf(0.5))
    } else {
        let eta = p.spectrum(&name("eta"))?.unwrap_or(SpectrumValue::Named("metal-Cu-eta".into()));
        let k = p.spectrum(&name("k"))?.unwrap_or(SpectrumValue::Named("metal-Cu-k".into()));
        (albedo(p, &name("eta"), &eta, r)?, albedo(p, &name("k"), &k, r)?)
    };
    let specular = ColorParam::constant(Vec3::ONE);
    Ok((BsdfDesc::Conductor { eta, k, specular, alpha }, ColorParam::constant(Vec3::splat(0.8))))
}

/// A spectrum parameter as RGB, with an unknown name reported at the parameter.
fn albedo(p: &Params, name: &str, value: &SpectrumValue, r: &Reader) -> Result<Vec3, SceneError> {
    spectra::rgb(value, Role::Albedo, r.gs.color_space).map_err(|m| p.error(format!("{name}: {m}")))
}

/// The index of refraction: a float, or a named glass spectrum; default 1.5.
fn eta(r: &mut Reader, p: &Params) -> Result<f32, SceneError> {
    let eta = match p.spectrum("eta")? {
        None => 1.5,
        Some(SpectrumValue::Constant(v)) => v,
        Some(value) => {
            let rgb = albedo(p, "eta", &value, r)?;
            if rgb.max_element() - rgb.min_element() > 1e-3 {
                r.warnings.push(p.warning("a wavelength-dependent eta is approximated by its mean"));
            }
            rgb.element_sum() / 3.0
        }
    };
    if eta <= 0.0 || !eta.is_finite() {
        return Err(p.error(format!("eta {eta} must be positive")));
    }
    Ok(eta)
}

/// The GGX alpha from `roughness` or `uroughness`/`vroughness`.
fn alpha(r: &mut Reader, p: &Params) -> Result<ScalarParam, SceneError> {
    alpha_named(r, p, "roughness", "uroughness", "vroughness")
}

fn alpha_named(r: &mut Reader, p: &Params, both: &str, u: &str, v: &str) -> Result<ScalarParam, SceneError> {
    let remap = p.bool_or("remaproughness", true)?;
    let rough = scalar_param(r, p, both, 0.0)?;
    let ru = if p.has(u) || p.texture(u).is_some() { scalar_param(r, p, u, 0.0)? } else { rough };
    let rv = if p.has(v) || p.texture(v).is_some() { scalar_param(r, p, v, 0.0)? } else { ru };
    let mut roughness = ru;
    if ru != rv {
        if ru.texture.is_some() || rv.texture.is_some() {
            r.warnings.push(p.warning("anisotropic textured roughness is approximated by its u roughness"));
        } else {
            r.warnings.push(p.warning("anisotropic roughness is approximated by the mean of u and v"));
            roughness.value = 0.5 * (ru.value + rv.value);
        }
    }
    if roughness.value < 0.0 {
        return Err(p.error(format!("roughness {} must not be negative", roughness.value)));
    }
    if remap && roughness.texture.is_some() {
        r.warnings.push(p.warning("a roughness texture is used as alpha without pbrt's square-root remapping"));
    } else if remap {
        roughness.value = roughness.value.sqrt();
    }
    Ok(roughness)
}
