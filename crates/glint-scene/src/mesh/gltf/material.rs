//! glTF materials onto glint's: the metallic-roughness model (with the transmission,
//! IOR, emissive-strength and unlit extensions) as a physically based BSDF for the path
//! tracer, and its nearest Phong material for the Whitted integrator.
//!
//! glint has no BSDF that blends a metal and a dielectric, so a material is one or the
//! other: metallic at or above one half (the factor times the mean of the texture's blue
//! channel) is a conductor whose reflectance is the base colour, below it a plastic (the
//! base colour under a coat of the material's IOR, 1.5 by default: glTF's 4 % F0). A
//! material between the two is named in a warning. Transmission at or above one half is
//! a (thick) dielectric tinted by the base colour. The normal texture is a normal map
//! in the uv frame. Occlusion textures are left out on purpose: they fake the shadowing
//! that both integrators trace.

use std::borrow::Cow;
use std::path::Path;

use glam::{Vec2, Vec3};
use glint_core::desc::{
    BsdfDesc, ColorParam, ImageSampling, MaterialDesc, NormalMapDesc, ScalarParam, TextureDesc, TextureWrap, Transfer,
};

use super::{Resource, State, resolve};
use crate::error::SceneError;
use crate::input::{self, InputKind};

/// How a texture's texels are meant: colours (sRGB-encoded) or data (stored as is).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Texels {
    Color,
    /// Values stored as they are (a normal map).
    Data,
    /// glTF's metallic-roughness texture reduced to the GGX alpha its green channel
    /// gives: `roughness²` in every channel, so a [`ScalarParam`] reads it as is.
    AlphaFromGreen,
}

/// The physically based parameters of a glTF material, read once.
struct Pbr {
    base: ColorParam,
    metallic: f32,
    /// GGX alpha: glTF's perceptual roughness squared.
    alpha: ScalarParam,
    roughness: f32,
    ior: f32,
    transmission: f32,
    emission: Vec3,
    emission_texture: Option<usize>,
}

impl State<'_> {
    /// The index in the import of glTF material `index`, mapped the first time a
    /// primitive uses it.
    pub(super) fn material(&mut self, material: &gltf::Material, index: usize) -> Result<usize, SceneError> {
        if let Some(&i) = self.materials.get(&index) {
            return Ok(i);
        }
        let name = material.name().map_or_else(|| format!("material{index}"), str::to_owned);
        let pbr = self.pbr(material, &name)?;
        let mut desc = phong_of(&pbr, name);
        desc.bsdf = Some(if material.unlit() {
            BsdfDesc::Diffuse { reflectance: ColorParam::constant(Vec3::ZERO) }
        } else {
            bsdf_of(&pbr)
        });
        (desc.emission, desc.emission_texture) =
            if material.unlit() { (pbr.base.value, pbr.base.texture) } else { (pbr.emission, pbr.emission_texture) };
        desc.two_sided = material.double_sided();
        if let Some(normal) = material.normal_texture()
            && let Some(texture) = self.texture(&normal.texture(), Texels::Data)?
        {
            desc.normal_map = Some(NormalMapDesc { texture, scale: normal.scale() });
        }
        self.import.materials.push(desc);
        self.materials.insert(index, self.import.materials.len() - 1);
        Ok(self.import.materials.len() - 1)
    }

    fn pbr(&mut self, material: &gltf::Material, name: &str) -> Result<Pbr, SceneError> {
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let base_texture = match pbr.base_color_texture() {
            Some(info) => self.texture(&info.texture(), Texels::Color)?,
            None => None,
        };
        let roughness = pbr.roughness_factor().clamp(0.0, 1.0);
        let mut metallic = pbr.metallic_factor().clamp(0.0, 1.0);
        let mut alpha = ScalarParam::constant(roughness * roughness);
        if let Some(info) = pbr.metallic_roughness_texture()
            && let Some(t) = self.texture(&info.texture(), Texels::AlphaFromGreen)?
        {
            alpha.texture = Some(t);
            metallic *= self.blue_means.get(&t).copied().unwrap_or(1.0);
        }
        if metallic > 0.1 && metallic < 0.9 {
            let nearest = if metallic >= 0.5 { "a metal" } else { "a plastic" };
            self.warn(format!(
                "material '{name}': metallic {metallic:.2} is rendered as {nearest} (glint has no blend of the two)"
            ));
        }
        let strength = material.emissive_strength().unwrap_or(1.0);
        let emission = Vec3::from(material.emissive_factor()) * strength;
        let emission_texture = match material.emissive_texture() {
            Some(info) => self.texture(&info.texture(), Texels::Color)?,
            None => None,
        };
        Ok(Pbr {
            base: ColorParam { value: Vec3::new(r, g, b), texture: base_texture },
            metallic,
            alpha,
            roughness,
            ior: material.ior().unwrap_or(1.5),
            transmission: material.transmission().map_or(0.0, |t| t.transmission_factor()),
            emission,
            emission_texture,
        })
    }

    /// The texture of `texture`'s image as `texels` means it, decoded the first time;
    /// `None`, with a warning, for an image glint cannot decode (KTX2, WebP, a texture
    /// with no image): the material then renders with its factors alone.
    pub(super) fn texture(&mut self, texture: &gltf::Texture, texels: Texels) -> Result<Option<usize>, SceneError> {
        let Some(image) = texture.source() else {
            self.warn(format!("texture {} has no image glint can read (KTX2?); it is left out", texture.index()));
            return Ok(None);
        };
        let sampling = sampling_of(&texture.sampler());
        let key = (image.index(), texels, sampling);
        if let Some(&t) = self.textures.get(&key) {
            return Ok(t);
        }
        let decoded = self.decode(&image, texels)?;
        let index = decoded.map(|mut desc| {
            if let TextureDesc::Image { sampling: s, .. } = &mut desc {
                *s = sampling;
            }
            if texels == Texels::AlphaFromGreen {
                let blue_mean = alpha_from_green(&mut desc);
                self.blue_means.insert(self.import.textures.len(), blue_mean);
            }
            self.import.textures.push(desc);
            self.import.textures.len() - 1
        });
        self.textures.insert(key, index);
        Ok(index)
    }

    /// Decodes `image`: PNG or JPEG from a buffer view, a `data:` URI or a file (read
    /// within the image size limit). A missing file is an error naming the path looked
    /// for; a format glint does not decode is a warning.
    fn decode(&mut self, image: &gltf::Image, texels: Texels) -> Result<Option<TextureDesc>, SceneError> {
        let index = image.index();
        let fail = |message: String| super::mesh_error(self.path, 0, format!("image {index}: {message}"));
        let (bytes, file): (Cow<[u8]>, Cow<Path>) = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self.buffers.get(view.buffer().index()).map_or(&[][..], |b| &b.0[..]);
                let range = view.offset()..view.offset().saturating_add(view.length());
                let bytes = buffer.get(range).ok_or_else(|| fail("its buffer view lies outside its buffer".into()))?;
                (Cow::Borrowed(bytes), Cow::Borrowed(self.path))
            }
            gltf::image::Source::Uri { uri, .. } => {
                match resolve(self.path.parent().unwrap_or(Path::new("")), uri).map_err(fail)? {
                    Resource::Bytes(bytes) => (Cow::Owned(bytes), Cow::Borrowed(self.path)),
                    Resource::File(file) => {
                        let bytes = input::read_bytes(&file, InputKind::Image).map_err(|e| fail(e.to_string()))?;
                        super::super::check_lfs_pointer(&file, &bytes).map_err(|e| fail(e.message))?;
                        (Cow::Owned(bytes), Cow::Owned(file))
                    }
                }
            }
        };
        let transfer = match texels {
            Texels::Color => Transfer::Srgb,
            Texels::AlphaFromGreen | Texels::Data => Transfer::Identity,
        };
        match crate::texture_io::decode_image(&format!("image{index}"), &file, &bytes, transfer, false) {
            Ok(desc) => Ok(Some(desc)),
            Err(e @ crate::texture_io::TextureError::UnsupportedFormat { .. }) => {
                self.warn(format!("image {index} is left out: {e}"));
                Ok(None)
            }
            Err(e) => Err(fail(e.to_string())),
        }
    }

    pub(super) fn warn(&mut self, message: String) {
        self.import.warnings.push(format!("{}: {message}", self.path.display()));
    }
}

/// A glTF sampler's wrap modes and magnification filter (glint does not mip-map, so
/// the minification filter has nothing to choose).
fn sampling_of(sampler: &gltf::texture::Sampler) -> ImageSampling {
    use gltf::texture::{MagFilter, WrappingMode};
    let wrap = |mode: WrappingMode| match mode {
        WrappingMode::ClampToEdge => TextureWrap::Clamp,
        WrappingMode::MirroredRepeat => TextureWrap::Mirror,
        WrappingMode::Repeat => TextureWrap::Repeat,
    };
    ImageSampling {
        wrap: [wrap(sampler.wrap_s()), wrap(sampler.wrap_t())],
        nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
    }
}

/// Turns a decoded metallic-roughness image into its GGX alpha (green squared, in every
/// channel) and returns the mean of its blue (metallic) channel.
fn alpha_from_green(desc: &mut TextureDesc) -> f32 {
    let TextureDesc::Image { texels, .. } = desc else { return 1.0 };
    let mut blue = 0.0f64;
    for t in texels.iter_mut() {
        blue += f64::from(t.z);
        *t = Vec3::splat(t.y * t.y);
    }
    (blue / texels.len().max(1) as f64) as f32
}

/// The path tracer's BSDF: glass, metal or plastic, whichever the material is nearest.
fn bsdf_of(pbr: &Pbr) -> BsdfDesc {
    if pbr.transmission >= 0.5 {
        return BsdfDesc::Dielectric {
            int_ior: pbr.ior,
            ext_ior: 1.0,
            reflectance: Vec3::ONE,
            transmittance: pbr.base.value * pbr.transmission,
            alpha: pbr.alpha,
        };
    }
    if pbr.metallic >= 0.5 {
        // η = 0, k = 1 reflects everything at every angle (Mitsuba's conductor "none"),
        // so the reflectance is the base colour, as glTF's metal is at normal incidence.
        return BsdfDesc::Conductor { eta: Vec3::ZERO, k: Vec3::ONE, specular: pbr.base, alpha: pbr.alpha };
    }
    BsdfDesc::Plastic {
        diffuse: pbr.base,
        int_ior: pbr.ior.max(1.0 + 1e-3),
        ext_ior: 1.0,
        specular: Vec3::ONE,
        alpha: pbr.alpha,
        nonlinear: false,
    }
}

/// The nearest Phong material for the Whitted integrator: the base colour as diffuse
/// (metals show it in their highlights and reflection instead), a highlight as sharp as
/// the roughness, a mirror term for smooth metals, refraction for transmission.
fn phong_of(pbr: &Pbr, name: String) -> MaterialDesc {
    let base = pbr.base.value;
    let metal = pbr.metallic >= 0.5;
    let alpha = (pbr.roughness * pbr.roughness).max(1e-3);
    let mut desc = MaterialDesc {
        name,
        diffuse: if metal { base * 0.1 } else { base },
        specular: if metal { base } else { Vec3::splat(0.04) },
        shininess: (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 2000.0),
        reflective: Some(if metal { base * (1.0 - pbr.roughness) } else { Vec3::ZERO }),
        ..Default::default()
    };
    if let Some(texture) = pbr.base.texture {
        desc.texture = Some(texture);
        desc.blend = 1.0;
        desc.texture_repeat = Vec2::ONE;
    }
    if pbr.transmission >= 0.5 {
        desc.transmissive = base * pbr.transmission;
        desc.ior = pbr.ior;
        desc.diffuse = Vec3::ZERO;
        desc.reflective = Some(Vec3::splat(0.04));
    }
    desc
}
