//! BSDF plugins → [`BsdfDesc`] inside a [`MaterialDesc`]: `diffuse`, `conductor`,
//! `roughconductor`, `dielectric`, `roughdielectric`, `thindielectric`, `plastic`,
//! `roughplastic`, `principled` (as glint's metallic-roughness BSDF), and `twosided`
//! around one of them. Rough ones take Mitsuba's `distribution`: `beckmann` (its
//! default) or `ggx`.

use glam::Vec3;
use glint_core::desc::{BsdfDesc, ColorParam, MaterialDesc, MicrofacetKind, NormalMapDesc, ScalarParam};

use super::Reader;
use super::tables::{conductor_names, ior_names, named_conductor, named_ior};
use super::textures::{color_param, plain_color, scalar_param};
use super::tree::Elem;
use super::values::{Plugin, Value};
use crate::error::SceneError;

/// Parameters that only change how a BSDF is sampled, never what it computes.
const HARMLESS: [&str; 5] = [
    "sample_visible",
    "main_specular_sampling_rate",
    "clearcoat_sampling_rate",
    "diffuse_reflectance_sampling_rate",
    "spec_trans_sampling_rate",
];

/// `principled` lobes glint's metallic-roughness BSDF does not have, with the value
/// that turns each off (Mitsuba's default).
const PRINCIPLED_EXTRAS: [(&str, f32); 7] = [
    ("anisotropic", 0.0),
    ("sheen", 0.0),
    ("sheen_tint", 0.0),
    ("clearcoat", 0.0),
    ("spec_trans", 0.0),
    ("spec_tint", 0.0),
    ("flatness", 0.0),
];

/// Mitsuba's default roughness of the rough BSDFs.
const DEFAULT_ALPHA: f32 = 0.1;

/// A BSDF read from the file, before it becomes a material.
pub(super) struct Surface {
    pub bsdf: BsdfDesc,
    pub two_sided: bool,
    /// The colour the Whitted integrator shows as the diffuse colour.
    pub base: ColorParam,
    /// The microfacet distribution of a rough plugin.
    pub microfacet: MicrofacetKind,
    /// A `normalmap` wrapper's texture.
    pub normal_map: Option<NormalMapDesc>,
}

/// Mitsuba's BSDF for shapes that name none: diffuse, reflectance 0.5, one-sided.
pub(super) fn default_surface() -> Surface {
    let base = ColorParam::constant(Vec3::splat(0.5));
    Surface {
        bsdf: BsdfDesc::Diffuse { reflectance: base },
        two_sided: false,
        base,
        microfacet: MicrofacetKind::Ggx,
        normal_map: None,
    }
}

/// The material index of BSDF element `e` (or a `<ref>` to one; `None`: the default
/// BSDF), built once however many shapes use it.
pub(super) fn material<'a>(r: &mut Reader<'a>, e: Option<&'a Elem>) -> Result<usize, SceneError> {
    let target = e.map(|e| r.resolve(e, "bsdf")).transpose()?;
    let key: *const Elem = target.map_or(std::ptr::null(), |t| t);
    if let Some(&i) = r.materials.get(&key) {
        return Ok(i);
    }
    let (name, surface) = match target {
        Some(t) => (t.attr("id").unwrap_or("").to_owned(), surface(r, t)?),
        None => ("mitsuba default".to_owned(), default_surface()),
    };
    let index = r.add_material(material_desc(name, &surface));
    r.materials.insert(key, index);
    Ok(index)
}

/// A material scattering like `s`, Phong fields left at their defaults except the
/// diffuse colour (and texture), so the Whitted integrator shows something like it.
pub(super) fn material_desc(name: String, s: &Surface) -> MaterialDesc {
    MaterialDesc {
        name,
        diffuse: s.base.value,
        texture: s.base.texture,
        bsdf: Some(s.bsdf),
        two_sided: s.two_sided,
        microfacet: s.microfacet,
        normal_map: s.normal_map,
        ..MaterialDesc::default()
    }
}

/// Reads one BSDF element.
fn surface<'a>(r: &mut Reader<'a>, e: &'a Elem) -> Result<Surface, SceneError> {
    let p = Plugin::open(e)?;
    let mut s = match p.ty {
        "twosided" => two_sided(r, &p)?,
        "normalmap" => normal_mapped(r, &p)?,
        "diffuse" => {
            let reflectance = color_param(r, &p, "reflectance", Vec3::splat(0.5))?;
            Surface {
                bsdf: BsdfDesc::Diffuse { reflectance },
                two_sided: false,
                base: reflectance,
                microfacet: MicrofacetKind::Ggx,
                normal_map: None,
            }
        }
        "conductor" | "roughconductor" => conductor(r, &p)?,
        "dielectric" | "roughdielectric" | "thindielectric" => dielectric(r, &p)?,
        "plastic" | "roughplastic" => plastic(r, &p)?,
        "principled" => principled(r, &p)?,
        other => {
            return Err(p.error(format!(
                "BSDF type '{other}' is not supported; glint reads diffuse, conductor, roughconductor, dielectric, \
                 roughdielectric, thindielectric, plastic, roughplastic, principled, twosided and normalmap"
            )));
        }
    };
    if p.ty.starts_with("rough") {
        s.microfacet = microfacet(&p)?;
    }
    p.finish(&HARMLESS)?;
    Ok(s)
}

/// Mitsuba's `distribution` of a rough plugin; Beckmann when not given, as in Mitsuba.
fn microfacet(p: &Plugin) -> Result<MicrofacetKind, SceneError> {
    match p.string("distribution")?.unwrap_or("beckmann") {
        "ggx" => Ok(MicrofacetKind::Ggx),
        "beckmann" => Ok(MicrofacetKind::Beckmann),
        other => {
            Err(p.param_error("distribution", format!("'{other}' is not a microfacet distribution (ggx, beckmann)")))
        }
    }
}

/// `twosided` around exactly one BSDF: the same scattering on both sides.
fn two_sided<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    match p.objects("bsdf").as_slice() {
        [inner] => {
            let inner = r.resolve(inner, "bsdf")?;
            Ok(Surface { two_sided: true, ..surface(r, inner)? })
        }
        [] => Err(p.error("needs one nested <bsdf>")),
        _ => Err(p.error("different BSDFs on the two sides are not supported; give one nested <bsdf>")),
    }
}

/// `normalmap` around one BSDF: its nested texture `normalmap` (give the bitmap
/// `raw="true"`, as Mitsuba wants) bends the shading normal in the uv frame.
fn normal_mapped<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    if p.named_object("normalmap").is_none() {
        return Err(p.error("needs a nested <texture name=\"normalmap\">"));
    }
    let texture = color_param(r, p, "normalmap", Vec3::ZERO)?.texture;
    let inner = match p.objects("bsdf").as_slice() {
        [inner] => r.resolve(inner, "bsdf")?,
        _ => return Err(p.error("needs exactly one nested <bsdf>")),
    };
    let inner = surface(r, inner)?;
    Ok(Surface { normal_map: texture.map(|texture| NormalMapDesc { texture, scale: 1.0 }), ..inner })
}

/// Roughness `alpha` of a rough plugin (0, a delta lobe, for the smooth ones).
fn roughness<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<ScalarParam, SceneError> {
    if !p.ty.starts_with("rough") {
        return Ok(ScalarParam::constant(0.0));
    }
    if p.has("alpha_u") || p.has("alpha_v") {
        let u = p.float("alpha_u")?.ok_or_else(|| p.error("'alpha_v' needs 'alpha_u' as well"))?;
        let v = p.float("alpha_v")?.ok_or_else(|| p.error("'alpha_u' needs 'alpha_v' as well"))?;
        if (u - v).abs() > 1e-6 || p.has("alpha") {
            return Err(p.param_error("alpha_u", "anisotropic roughness (alpha_u ≠ alpha_v) is not supported"));
        }
        return Ok(ScalarParam::constant(u));
    }
    scalar_param(r, p, "alpha", DEFAULT_ALPHA)
}

/// A metal by `material` name or by `eta` and `k`.
fn conductor<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    let (eta, k) = if p.has("eta") || p.has("k") {
        if p.has("material") {
            return Err(p.param_error("material", "give either 'material' or 'eta' and 'k', not both"));
        }
        let eta = plain_color(p, "eta", Vec3::ZERO)?;
        if !p.has("k") {
            return Err(p.error("'eta' needs 'k' as well"));
        }
        (eta, plain_color(p, "k", Vec3::ZERO)?)
    } else {
        let name = p.string("material")?.unwrap_or("none");
        named_conductor(name).ok_or_else(|| {
            p.param_error("material", format!("unknown conductor '{name}'; known: {}", conductor_names()))
        })?
    };
    let specular = color_param(r, p, "specular_reflectance", Vec3::ONE)?;
    let alpha = roughness(r, p)?;
    // Normal-incidence Fresnel reflectance, the metal's colour for the Whitted preview.
    let f0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
    let base = ColorParam { value: specular.value * f0, texture: specular.texture };
    Ok(Surface {
        bsdf: BsdfDesc::Conductor { eta, k, specular, alpha },
        two_sided: false,
        base,
        microfacet: MicrofacetKind::Ggx,
        normal_map: None,
    })
}

/// Mitsuba's Disney-style `principled` BSDF (what Blender's exporter writes for its
/// Principled BSDF) read as glint's metallic-roughness BSDF: base colour, metallic and
/// roughness (each may be a texture; `alpha = roughness²`), and the coat's index from
/// `eta`, else from `specular` (F0 = 0.08·specular, as Mitsuba has it). The lobes glint
/// does not have are left out, named in one warning when they are set.
fn principled<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    let base = color_param(r, p, "base_color", Vec3::splat(0.5))?;
    let metallic = scalar_param(r, p, "metallic", 0.0)?;
    let roughness = scalar_param(r, p, "roughness", 0.5)?;
    let alpha = ScalarParam {
        value: roughness.value * roughness.value,
        texture: roughness.texture.map(|t| r.squared_texture(t)),
    };
    let ior = match p.float("eta")? {
        Some(eta) if eta > 0.0 && eta != 1.0 => eta,
        Some(eta) => return Err(p.param_error("eta", format!("{eta} is not an index of refraction above 0 and not 1"))),
        None => {
            let f0 = (0.08 * p.float_or("specular", 0.5)?).clamp(0.0, 0.99).sqrt();
            ((1.0 + f0) / (1.0 - f0)).max(1.0 + 1e-3)
        }
    };
    let mut left_out = Vec::new();
    for (name, off) in PRINCIPLED_EXTRAS {
        if p.named_object(name).is_some() {
            left_out.push(format!("{name} (a texture)"));
        } else if let Some(v) = p.float(name)?.filter(|&v| v != off) {
            left_out.push(format!("{name} {v}"));
        }
    }
    // Only the clearcoat (left out above) reads its gloss.
    if p.named_object("clearcoat_gloss").is_none() {
        p.float("clearcoat_gloss")?;
    }
    if !left_out.is_empty() {
        r.warn_at(
            p.elem,
            format!(
                "{}: {} left out: glint's metallic-roughness BSDF has no such lobes",
                p.label(),
                left_out.join(", ")
            ),
        );
    }
    Ok(Surface {
        bsdf: BsdfDesc::MetallicRoughness { base, metallic, alpha, ior },
        two_sided: false,
        base,
        microfacet: MicrofacetKind::Ggx,
        normal_map: None,
    })
}

/// An index of refraction given as a number or as a name from Mitsuba's table.
fn ior(p: &Plugin, name: &str, default: &str) -> Result<f32, SceneError> {
    let unknown = |n: &str| p.param_error(name, format!("unknown material '{n}'; known: {}", ior_names()));
    match p.value(name).cloned() {
        None => named_ior(default).ok_or_else(|| unknown(default)),
        Some(Value::Float(v)) => Ok(v),
        Some(Value::Integer(v)) => Ok(v as f32),
        Some(Value::Str(s)) => named_ior(&s).ok_or_else(|| unknown(&s)),
        Some(_) => Err(p.param_error(name, "must be a <float> or a <string> naming a material")),
    }
}

/// Glass (smooth, rough or thin); dielectrics are two-sided.
fn dielectric<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    let int_ior = ior(p, "int_ior", "bk7")?;
    let ext_ior = ior(p, "ext_ior", "air")?;
    let reflectance = plain_color(p, "specular_reflectance", Vec3::ONE)?;
    let transmittance = plain_color(p, "specular_transmittance", Vec3::ONE)?;
    let bsdf = if p.ty == "thindielectric" {
        BsdfDesc::ThinDielectric { int_ior, ext_ior, reflectance, transmittance }
    } else {
        let alpha = roughness(r, p)?;
        BsdfDesc::Dielectric { int_ior, ext_ior, reflectance, transmittance, alpha }
    };
    Ok(Surface {
        bsdf,
        two_sided: true,
        base: ColorParam::constant(transmittance),
        microfacet: MicrofacetKind::Ggx,
        normal_map: None,
    })
}

/// A diffuse base under a dielectric coat.
fn plastic<'a>(r: &mut Reader<'a>, p: &Plugin<'a>) -> Result<Surface, SceneError> {
    let diffuse = color_param(r, p, "diffuse_reflectance", Vec3::splat(0.5))?;
    let int_ior = ior(p, "int_ior", "polypropylene")?;
    let ext_ior = ior(p, "ext_ior", "air")?;
    let specular = plain_color(p, "specular_reflectance", Vec3::ONE)?;
    let nonlinear = p.bool_or("nonlinear", false)?;
    let alpha = roughness(r, p)?;
    let bsdf = BsdfDesc::Plastic { diffuse, int_ior, ext_ior, specular, alpha, nonlinear };
    Ok(Surface { bsdf, two_sided: false, base: diffuse, microfacet: MicrofacetKind::Ggx, normal_map: None })
}
