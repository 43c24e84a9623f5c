//! glTF materials onto glint's: the metallic-roughness model (with the transmission,
//! IOR, emissive-strength and unlit extensions) as a physically based BSDF for the path
//! tracer, and its nearest Phong material for the Whitted integrator.
//!
//! The path tracer reads the model as glTF defines it, with glint's metallic-roughness
//! BSDF: per point, `metallic` (the factor times the texture's blue channel) blends a
//! metal whose reflectance at normal incidence is the base colour (Schlick's Fresnel)
//! and a plastic (the base colour under a coat of the material's IOR, 1.5 by default:
//! glTF's 4 % F0), with the roughness of the texture's green channel. Transmission at or
//! above one half is a (thick) dielectric tinted by the base colour. The normal texture
//! is a normal map in the uv frame. Occlusion textures are left out on purpose: they
//! fake the shadowing that both integrators trace.

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
    /// The same texture's blue channel (metallic) in every channel.
    MetallicFromBlue,
}

/// The physically based parameters of a glTF material, read once.
struct Pbr {
    base: ColorParam,
    metallic: ScalarParam,
    /// The metallic share over the whole surface (the factor times the texture's mean),
    /// for the Whitted integrator's single Phong material.
    mean_metallic: f32,
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
        let pbr = self.pbr(material)?;
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

    fn pbr(&mut self, material: &gltf::Material) -> Result<Pbr, SceneError> {
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, _] = pbr.base_color_factor();
        let base_texture = match pbr.base_color_texture() {
            Some(info) => self.texture(&info.texture(), Texels::Color)?,
            None => None,
        };
        let roughness = pbr.roughness_factor().clamp(0.0, 1.0);
        let mut metallic = ScalarParam::constant(pbr.metallic_factor().clamp(0.0, 1.0));
        let mut mean_metallic = metallic.value;
        let mut alpha = ScalarParam::constant(roughness * roughness);
        if let Some(info) = pbr.metallic_roughness_texture() {
            alpha.texture = self.texture(&info.texture(), Texels::AlphaFromGreen)?;
            // A zero factor makes the texture's metallic channel irrelevant.
            if metallic.value > 0.0 {
                metallic.texture = self.texture(&info.texture(), Texels::MetallicFromBlue)?;
                if let Some(t) = metallic.texture {
                    mean_metallic *= self.channel_means.get(&t).copied().unwrap_or(1.0);
                }
            }
            self.metallic_roughness_image = None;
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
            mean_metallic,
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
            match texels {
                Texels::AlphaFromGreen => {
                    spread_channel(&mut desc, |t| t.y * t.y);
                }
                Texels::MetallicFromBlue => {
                    let mean = spread_channel(&mut desc, |t| t.z);
                    self.channel_means.insert(self.import.textures.len(), mean);
                }
                Texels::Color | Texels::Data => {}
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
        if texels == Texels::MetallicFromBlue
            && let Some((_, decoded)) = self.metallic_roughness_image.take_if(|(i, _)| *i == index)
        {
            return Ok(decoded);
        }
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
            Texels::AlphaFromGreen | Texels::MetallicFromBlue | Texels::Data => Transfer::Identity,
        };
        match crate::texture_io::decode_image(&format!("image{index}"), &file, &bytes, transfer, false) {
            Ok(desc) => {
                if texels == Texels::AlphaFromGreen {
                    self.metallic_roughness_image = Some((index, Some(desc.clone())));
                }
                Ok(Some(desc))
            }
            Err(e @ crate::texture_io::TextureError::UnsupportedFormat { .. }) => {
                self.warn(format!("image {index} is left out: {e}"));
                if texels == Texels::AlphaFromGreen {
                    self.metallic_roughness_image = Some((index, None));
                }
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

/// Replaces every texel of a decoded image by `value(texel)` in all three channels (so a
/// [`ScalarParam`] reads it as is) and returns the mean of the new values. The texels
/// are no longer the file's, so the texture keeps no path (as the pbrt reader does with
/// scaled ones): a writer such as `glint convert` then cannot name the file for them.
fn spread_channel(desc: &mut TextureDesc, value: impl Fn(Vec3) -> f32) -> f32 {
    let TextureDesc::Image { texels, path, .. } = desc else { return 1.0 };
    path.clear();
    let mut sum = 0.0f64;
    for t in texels.iter_mut() {
        let v = value(*t);
        sum += f64::from(v);
        *t = Vec3::splat(v);
    }
    (sum / texels.len().max(1) as f64) as f32
}

/// The path tracer's BSDF: glass when the material transmits, else the
/// metallic-roughness blend.
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
    BsdfDesc::MetallicRoughness {
        base: pbr.base,
        metallic: pbr.metallic,
        alpha: pbr.alpha,
        ior: pbr.ior.max(1.0 + 1e-3),
    }
}

/// The nearest Phong material for the Whitted integrator, blended by the surface's mean
/// metallic share as the BSDF is: the base colour as diffuse (metals show it in their
/// highlights and reflection instead), a highlight as sharp as the roughness, a mirror
/// term for smooth metals, refraction for transmission.
fn phong_of(pbr: &Pbr, name: String) -> MaterialDesc {
    let base = pbr.base.value;
    let metal = pbr.mean_metallic;
    let alpha = (pbr.roughness * pbr.roughness).max(1e-3);
    let mut desc = MaterialDesc {
        name,
        diffuse: base * (1.0 - 0.9 * metal),
        specular: Vec3::splat(0.04).lerp(base, metal),
        shininess: (2.0 / (alpha * alpha) - 2.0).clamp(1.0, 2000.0),
        reflective: Some(base * (metal * (1.0 - pbr.roughness))),
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
