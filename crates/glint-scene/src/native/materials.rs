//! `material "name" { … }` and `texture "name" checker|image { … }`.

use glam::{Vec2, Vec3};
use glint_core::desc::{Highlight, ImageSampling, MaterialDesc, NormalMapDesc, TextureDesc, TextureWrap, Transfer};

use super::args::{self, Result, Seen};
use super::bsdf;
use super::builder::{Builder, Registry, Source};
use super::tree::Node;
use crate::error::SceneErrorKind;
use crate::texture_io;

/// The texture types, in the order the documentation lists them.
pub const TEXTURE_KINDS: [&str; 2] = ["checker", "image"];

const MATERIAL_PROPERTIES: [&str; 24] = [
    "diffuse",
    "specular",
    "shininess",
    "reflective",
    "transmissive",
    "ior",
    "ambient",
    "ka",
    "kd",
    "ks",
    "kt",
    "texture",
    "blend",
    "repeat",
    "bsdf",
    "emission",
    "two_sided",
    "microfacet",
    "casts_shadows",
    "normal_map",
    "normal_scale",
    "emission_texture",
    "highlight",
    "textured_ambient",
];

/// Builds a material; unset properties keep [`MaterialDesc::default`].
pub fn material(src: &Source, node: &Node, name: &str, textures: &Registry) -> Result<MaterialDesc> {
    let mut m = MaterialDesc { name: name.to_owned(), ..MaterialDesc::default() };
    let mut seen = Seen::default();
    let mut normal_scale = None;
    let mut rest = node.children().iter();
    while let Some(prop) = rest.next() {
        seen.once(src, prop, "material")?;
        let coefficient = |prop| args::number_where(src, prop, "0 or more", |x| x >= 0.0);
        match prop.name.as_str() {
            "diffuse" => m.diffuse = args::color(src, prop)?,
            "specular" => m.specular = args::color(src, prop)?,
            "reflective" => m.reflective = Some(args::color(src, prop)?),
            "transmissive" => m.transmissive = args::color(src, prop)?,
            "ambient" => m.ambient = Some(args::color(src, prop)?),
            "shininess" => m.shininess = coefficient(prop)?,
            "ior" => m.ior = args::number_where(src, prop, "greater than 0", |x| x > 0.0)?,
            "ka" => m.ka = coefficient(prop)?,
            "kd" => m.kd = coefficient(prop)?,
            "ks" => m.ks = coefficient(prop)?,
            "kt" => m.kt = coefficient(prop)?,
            "blend" => {
                m.blend = args::number_where(src, prop, "from 0 to 1", |x| (0.0..=1.0).contains(&x))?;
            }
            "repeat" => m.texture_repeat = args::vec2_positive(src, prop)?,
            "bsdf" => {
                args::no_values(src, prop)?;
                let kind = Builder::kind_node(src, prop, rest.next(), &bsdf::KINDS)?;
                m.bsdf = Some(bsdf::bsdf(src, kind, textures)?);
            }
            "emission" => m.emission = args::color(src, prop)?,
            "two_sided" => m.two_sided = args::boolean(src, prop)?,
            "casts_shadows" => m.casts_shadows = args::boolean(src, prop)?,
            "textured_ambient" => m.textured_ambient = args::boolean(src, prop)?,
            "highlight" => m.highlight = highlight(src, prop)?,
            "microfacet" => m.microfacet = microfacet(src, prop)?,
            "texture" => {
                args::no_block(src, prop)?;
                let (texture, pos) = args::string(src, prop, "a texture name")?;
                m.texture = Some(textures.lookup(src, pos, "texture", &texture)?);
            }
            "normal_map" => {
                args::no_block(src, prop)?;
                let (texture, pos) = args::string(src, prop, "a texture name")?;
                let scale = m.normal_map.map_or(1.0, |n| n.scale);
                m.normal_map = Some(NormalMapDesc { texture: textures.lookup(src, pos, "texture", &texture)?, scale });
            }
            "normal_scale" => normal_scale = Some((args::number(src, prop)?, prop)),
            "emission_texture" => {
                args::no_block(src, prop)?;
                let (texture, pos) = args::string(src, prop, "a texture name")?;
                m.emission_texture = Some(textures.lookup(src, pos, "texture", &texture)?);
            }
            _ => {
                return Err(args::unknown(src, prop, "property", "in 'material'", &MATERIAL_PROPERTIES));
            }
        }
    }
    if let Some((scale, prop)) = normal_scale {
        match &mut m.normal_map {
            Some(map) => map.scale = scale,
            None => return Err(src.invalid(prop.pos(), "'normal_scale' needs a 'normal_map' in the same material")),
        }
    }
    Ok(m)
}

/// Builds a texture from its kind node (`checker { … }` or `image { … }`).
pub fn texture(src: &Source, name: &str, kind: &Node) -> Result<TextureDesc> {
    let mut seen = Seen::default();
    if kind.name == "checker" {
        let mut even = Vec3::splat(0.9);
        let mut odd = Vec3::splat(0.1);
        let mut cells = Vec2::splat(8.0);
        let mut filtered = false;
        for prop in kind.children() {
            seen.once(src, prop, "checker")?;
            match prop.name.as_str() {
                "even" => even = args::color(src, prop)?,
                "odd" => odd = args::color(src, prop)?,
                "cells" => cells = args::vec2_positive(src, prop)?,
                "filtered" => filtered = args::boolean(src, prop)?,
                _ => {
                    return Err(args::unknown(
                        src,
                        prop,
                        "property",
                        "in 'texture checker'",
                        &["even", "odd", "cells", "filtered"],
                    ));
                }
            }
        }
        return Ok(TextureDesc::Checker { name: name.to_owned(), even, odd, cells, filtered });
    }
    let mut file = None;
    let mut sampling = ImageSampling::default();
    let mut transfer = Transfer::Srgb;
    for prop in kind.children() {
        seen.once(src, prop, "image")?;
        match prop.name.as_str() {
            "file" => {
                args::no_block(src, prop)?;
                file = Some((args::string(src, prop, "a file name")?.0, prop));
            }
            "wrap" => sampling.wrap = [wrap(src, prop)?; 2],
            "wrap_u" => sampling.wrap[0] = wrap(src, prop)?,
            "wrap_v" => sampling.wrap[1] = wrap(src, prop)?,
            "filter" => sampling.nearest = args::choice(src, prop, &[("bilinear", false), ("nearest", true)])?,
            "encoding" => {
                transfer = args::choice(src, prop, &[("srgb", Transfer::Srgb), ("linear", Transfer::Identity)])?;
            }
            _ => {
                let allowed = ["file", "wrap", "wrap_u", "wrap_v", "filter", "encoding"];
                return Err(args::unknown(src, prop, "property", "in 'texture image'", &allowed));
            }
        }
    }
    let Some((file, prop)) = file else {
        return Err(src.invalid(kind.pos(), "an image texture needs its file, as in `image { file \"wood.png\" }`"));
    };
    let path = src.dir.join(&file);
    let mut texture = texture_io::load_texture_hdr(name, &path, transfer)
        .map_err(|e| src.error(SceneErrorKind::Io, prop.pos(), e.to_string()))?;
    if let TextureDesc::Image { sampling: s, .. } = &mut texture {
        *s = sampling;
    }
    Ok(texture)
}

/// `wrap "repeat"|"clamp"|"mirror"`: what an image shows beyond its edges.
fn wrap(src: &Source, prop: &Node) -> Result<TextureWrap> {
    args::choice(
        src,
        prop,
        &[("repeat", TextureWrap::Repeat), ("clamp", TextureWrap::Clamp), ("mirror", TextureWrap::Mirror)],
    )
}

/// `microfacet "ggx"|"beckmann"`: the distribution of the BSDF's rough lobes.
fn microfacet(src: &Source, prop: &Node) -> Result<glint_core::desc::MicrofacetKind> {
    use glint_core::desc::MicrofacetKind;
    args::choice(src, prop, &[("ggx", MicrofacetKind::Ggx), ("beckmann", MicrofacetKind::Beckmann)])
}

fn highlight(src: &Source, prop: &Node) -> Result<Highlight> {
    args::choice(src, prop, &[("phong", Highlight::Phong), ("blinn", Highlight::Blinn)])
}
