//! The compiled Whitted material: the lecture's `k·O` products, ready to shade.

use bytemuck::{Pod, Zeroable};
use glam::{Vec2, Vec3};

use crate::desc::{Highlight, MaterialDesc};

/// Marks "no texture" in [`Material::texture`].
pub const NO_TEXTURE: u32 = u32::MAX;

/// [`Material::highlight`] for the lecture's `(r·v)^n`.
pub const PHONG_HIGHLIGHT: u32 = 0;
/// [`Material::highlight`] for Blinn's `(n·h)^n`.
pub const BLINN_HIGHLIGHT: u32 = 1;

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
    /// `k_a`, to scale a texture colour that replaces `O_a`.
    pub ka: f32,
    /// Texture weight in the ambient colour: [`Material::blend`] where the ambient
    /// follows the texture, else 0.
    pub ambient_blend: f32,
    /// [`PHONG_HIGHLIGHT`] or [`BLINN_HIGHLIGHT`]: a word, so the GPU reads it as is.
    pub highlight: u32,
}

impl Material {
    /// Folds the description's coefficients into colours.
    pub fn compile(desc: &MaterialDesc, texture: Option<u32>) -> Self {
        let ambient = desc.ambient.unwrap_or(desc.diffuse);
        let reflective = desc.reflective.unwrap_or(desc.specular);
        let blend = if texture.is_some() { desc.blend } else { 0.0 };
        Self {
            ambient: desc.ka * ambient,
            diffuse: desc.kd * desc.diffuse,
            specular: desc.ks * desc.specular,
            reflective: desc.ks * reflective,
            transmissive: desc.kt * desc.transmissive,
            kd: desc.kd,
            shininess: desc.shininess,
            ior: desc.ior,
            blend,
            texture: texture.unwrap_or(NO_TEXTURE),
            texture_repeat: desc.texture_repeat,
            normal_texture: desc.normal_map.map_or(NO_TEXTURE, |n| n.texture as u32),
            normal_scale: desc.normal_map.map_or(1.0, |n| n.scale),
            ka: desc.ka,
            ambient_blend: if desc.textured_ambient { blend } else { 0.0 },
            highlight: match desc.highlight {
                Highlight::Phong => PHONG_HIGHLIGHT,
                Highlight::Blinn => BLINN_HIGHLIGHT,
            },
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

    /// `k_a·O_a` with the texture colour blended in where the ambient follows the
    /// texture: `(1 − b)·O_a + b·T`, as [`Material::diffuse_with`].
    #[inline]
    pub fn ambient_with(&self, texel: Option<Vec3>) -> Vec3 {
        match texel {
            Some(t) => (1.0 - self.ambient_blend) * self.ambient + self.ambient_blend * self.ka * t,
            None => self.ambient,
        }
    }

    /// The highlight factor for unit normal `n`, unit direction to the light `l` and
    /// unit direction to the viewer `v`, both on `n`'s side: `(r·v)^n` or `(n·h)^n`.
    #[inline]
    pub fn highlight(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        let cosine = if self.highlight == BLINN_HIGHLIGHT {
            crate::math::unit_or_zero(l + v).dot(n)
        } else {
            (2.0 * l.dot(n) * n - l).dot(v)
        };
        cosine.max(0.0).powf(self.shininess)
    }

    /// The specular term as the explained ray tree names it.
    pub fn specular_formula(&self) -> &'static str {
        if self.highlight == BLINN_HIGHLIGHT { "k_s·O_s·(n·h)^n" } else { "k_s·O_s·(r·v)^n" }
    }

    /// The ambient term as the explained ray tree names it, where the texture gave
    /// `texel` (or nothing).
    pub fn ambient_formula(&self, texel: Option<Vec3>) -> &'static str {
        if self.ambient_blend > 0.0 && texel.is_some() {
            "ambient L_a·k_a·((1−b)·O_a + b·T)"
        } else {
            "ambient L_a·k_a·O_a"
        }
    }

    /// Whether any light passes through (shadow rays must look past it).
    pub fn is_transmissive(&self) -> bool {
        self.transmissive.max_element() > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit vector in the xy plane, `degrees` from the normal +y towards +x.
    fn at(degrees: f32) -> Vec3 {
        let a = degrees.to_radians();
        Vec3::new(a.sin(), a.cos(), 0.0)
    }

    fn shiny(highlight: Highlight) -> Material {
        let desc = MaterialDesc { specular: Vec3::ONE, shininess: 10.0, highlight, ..MaterialDesc::default() };
        Material::compile(&desc, None)
    }

    #[test]
    fn phong_and_blinn_peak_in_the_mirror_direction() {
        for highlight in [Highlight::Phong, Highlight::Blinn] {
            let m = shiny(highlight);
            assert!((m.highlight(Vec3::Y, at(35.0), at(-35.0)) - 1.0).abs() < 1e-5, "{highlight:?}");
        }
    }

    #[test]
    fn phong_measures_the_mirror_angle_and_blinn_the_half_angle() {
        // Light and viewer both 30° off the normal on the same side: the mirror direction
        // is 60° from the viewer, the half vector 30° from the normal.
        let (n, l, v) = (Vec3::Y, at(30.0), at(30.0));
        let phong = shiny(Highlight::Phong).highlight(n, l, v);
        let blinn = shiny(Highlight::Blinn).highlight(n, l, v);
        assert_eq!(shiny(Highlight::Phong).specular_formula(), "k_s·O_s·(r·v)^n");
        assert_eq!(shiny(Highlight::Blinn).specular_formula(), "k_s·O_s·(n·h)^n");
        assert!((phong - 0.5f32.powf(10.0)).abs() < 1e-6, "{phong}");
        assert!((blinn - 30f32.to_radians().cos().powf(10.0)).abs() < 1e-5, "{blinn}");
        // Light and viewer 10° apart on either side of the normal: the half vector is
        // 5° off it, the mirror direction 10° off the viewer.
        let (l, v) = (at(-2.0), at(12.0));
        let blinn = shiny(Highlight::Blinn).highlight(n, l, v);
        assert!((blinn - 5f32.to_radians().cos().powf(10.0)).abs() < 1e-5, "{blinn}");
        let phong = shiny(Highlight::Phong).highlight(n, l, v);
        assert!((phong - 10f32.to_radians().cos().powf(10.0)).abs() < 1e-5, "{phong}");
    }

    #[test]
    fn a_grazing_view_opposite_the_light_has_no_blinn_highlight() {
        let m = shiny(Highlight::Blinn);
        assert_eq!(m.highlight(Vec3::Y, Vec3::X, -Vec3::X), 0.0, "l + v = 0 has no half vector");
    }

    #[test]
    fn the_ambient_follows_the_texture_only_when_asked() {
        let desc = MaterialDesc {
            ka: 0.5,
            kd: 0.8,
            diffuse: Vec3::new(1.0, 0.5, 0.25),
            blend: 0.75,
            ..MaterialDesc::default()
        };
        let texel = Vec3::new(0.2, 0.4, 0.8);
        let lecture = Material::compile(&desc, Some(0));
        assert_eq!(lecture.ambient_with(Some(texel)), 0.5 * desc.diffuse, "O_a stays the untextured O_d");
        let pov = Material::compile(&MaterialDesc { textured_ambient: true, ..desc.clone() }, Some(0));
        let expected = 0.5 * (0.25 * desc.diffuse + 0.75 * texel);
        assert!((pov.ambient_with(Some(texel)) - expected).abs().max_element() < 1e-6);
        assert!(
            (pov.diffuse_with(Some(texel)) - 0.8 * (0.25 * desc.diffuse + 0.75 * texel)).abs().max_element() < 1e-6
        );
        // The explained ray tree names the term that was computed.
        assert_eq!(lecture.ambient_formula(Some(texel)), "ambient L_a·k_a·O_a");
        assert_eq!(pov.ambient_formula(Some(texel)), "ambient L_a·k_a·((1−b)·O_a + b·T)");
        // Without a texture there is nothing to follow.
        let untextured = Material::compile(&MaterialDesc { textured_ambient: true, ..desc }, None);
        assert_eq!(untextured.ambient_with(None), untextured.ambient);
        assert_eq!(untextured.ambient_formula(None), "ambient L_a·k_a·O_a");
        assert_eq!(untextured.ambient_blend, 0.0);
    }
}
