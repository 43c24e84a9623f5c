//! The compiled Whitted material: the lecture's `k·O` products, ready to shade.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::desc::MaterialDesc;

/// Marks "no texture" in [`Material::texture`].
pub const NO_TEXTURE: u32 = u32::MAX;

/// A material with its coefficients folded into the colours (`ambient = k_a·O_a`, …)
/// so that shading does no lookups beyond this record.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Material {
    /// `k_a·O_a`
    pub ambient: Vec3,
    /// `k_d·O_d` before texturing.
    pub diffuse: Vec3,
    /// `k_s·O_s`, the highlight.
    pub specular: Vec3,
    /// `k_s·O_r`, the weight of the mirror-reflected ray.
    pub reflective: Vec3,
    /// `k_t·O_t`, the weight of the transmitted ray and the shadow filter.
    pub transmissive: Vec3,
    /// `k_d`, to scale a texture colour that replaces `O_d`.
    pub kd: f32,
    /// The Phong exponent `n`.
    pub shininess: f32,
    /// Index of refraction; exactly 1 means rays pass through unbent.
    pub ior: f32,
    /// Texture weight in the diffuse colour.
    pub blend: f32,
    /// Index into the scene's textures or [`NO_TEXTURE`].
    pub texture: u32,
    /// Repeats of the texture across the uv square (the normal map's too).
    pub texture_repeat: Vec2,
    /// The normal map's texture, or [`NO_TEXTURE`].
    pub normal_texture: u32,
    /// The normal map's tangential scale.
    pub normal_scale: f32,
}

impl Material {
    /// Folds the description's coefficients into colours.
    pub fn compile(desc: &MaterialDesc, texture: Option<u32>) -> Self {
        let ambient = desc.ambient.unwrap_or(desc.diffuse);
        let reflective = desc.reflective.unwrap_or(desc.specular);
        Self {
            ambient: desc.ka * ambient,
            diffuse: desc.kd * desc.diffuse,
            specular: desc.ks * desc.specular,
            reflective: desc.ks * reflective,
            transmissive: desc.kt * desc.transmissive,
            kd: desc.kd,
            shininess: desc.shininess,
            ior: desc.ior,
            blend: if texture.is_some() { desc.blend } else { 0.0 },
            texture: texture.unwrap_or(NO_TEXTURE),
            texture_repeat: desc.texture_repeat,
            normal_texture: desc.normal_map.map_or(NO_TEXTURE, |n| n.texture as u32),
            normal_scale: desc.normal_map.map_or(1.0, |n| n.scale),
        }
    }

    /// `k_d·O_d` with the texture colour blended in: `(1 − b)·O_d + b·T`.
    #[inline]
    pub fn diffuse_with(&self, texel: Option<Vec3>) -> Vec3 {
        match texel {
            Some(t) => (1.0 - self.blend) * self.diffuse + self.blend * self.kd * t,
            None => self.diffuse,
        }
    }

    /// Whether any light passes through (shadow rays must look past it).
    pub fn is_transmissive(&self) -> bool {
        self.transmissive.max_element() > 0.0
    }
}
