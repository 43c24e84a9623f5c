//! The physically based side of a scene description: which integrator renders it,
//! BSDFs, emission and environment lighting. Plain serde data like the rest of
//! [`crate::desc`]; the path tracer reads its compiled form.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::TransformOp;

/// Which light-transport algorithm renders the image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum IntegratorDesc {
    /// The lecture's recursive model: ambient, direct Phong lighting with shadow rays,
    /// mirror reflection and refraction.
    #[default]
    Whitted,
    /// Unidirectional path tracing with next-event estimation and multiple importance
    /// sampling: global illumination, solving the rendering equation.
    Path(PathDesc),
}

/// Path-tracing limits, counted as Mitsuba 3 counts them so that its scene files mean
/// the same here: `max_depth` 1 shows only emitters seen directly, 2 adds direct
/// lighting, each further step one more bounce; `u32::MAX` is unlimited (Mitsuba's −1).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathDesc {
    pub max_depth: u32,
    /// Path depth from which Russian roulette may end a path.
    pub rr_depth: u32,
    /// Which sequence draws the path's random numbers.
    pub sampler: SamplerKind,
}

impl Default for PathDesc {
    /// Mitsuba's defaults: unlimited depth, roulette from depth 5; Sobol samples.
    fn default() -> Self {
        Self { max_depth: u32::MAX, rr_depth: 5, sampler: SamplerKind::Sobol }
    }
}

/// The sequence that supplies every dimension of a path (pixel position, lens, time,
/// light choice, BSDF lobe and direction, roulette).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum SamplerKind {
    /// Owen-scrambled Sobol points, padded: each pair of dimensions is its own
    /// scrambled 2-D Sobol sequence, shuffled per pixel (Burley 2020).
    #[default]
    Sobol,
    /// Independent uniform numbers hashed from (pixel, sample, dimension, seed).
    Independent,
}

/// A colour that may come from a texture: `value` times the texture's colour, or
/// `value` alone when there is none.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ColorParam {
    pub value: Vec3,
    /// Index into [`super::SceneDesc::textures`].
    pub texture: Option<usize>,
}

impl ColorParam {
    /// A plain colour.
    pub fn constant(value: Vec3) -> Self {
        Self { value, texture: None }
    }
}

/// A scalar that may come from a texture (its mean channel), scaled by `value`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ScalarParam {
    pub value: f32,
    pub texture: Option<usize>,
}

impl ScalarParam {
    /// A plain number.
    pub fn constant(value: f32) -> Self {
        Self { value, texture: None }
    }
}

/// A physically based scattering function. Roughness is the GGX `alpha` (0 = smooth,
/// a delta lobe); indices of refraction are the inside (`int_ior`) over the outside
/// (`ext_ior`), as Mitsuba names them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum BsdfDesc {
    /// Lambertian reflection.
    Diffuse { reflectance: ColorParam },
    /// A metal: Fresnel reflection with complex index `eta + i·k` (per RGB channel),
    /// scaled by `specular`.
    Conductor { eta: Vec3, k: Vec3, specular: ColorParam, alpha: ScalarParam },
    /// Glass: Fresnel-weighted reflection and refraction.
    Dielectric { int_ior: f32, ext_ior: f32, reflectance: Vec3, transmittance: Vec3, alpha: ScalarParam },
    /// A thin sheet of glass (a window pane): reflection and straight-through
    /// transmission with the inter-reflections of both faces summed.
    ThinDielectric { int_ior: f32, ext_ior: f32, reflectance: Vec3, transmittance: Vec3 },
    /// A diffuse base under a dielectric coat (plastic, varnish).
    Plastic { diffuse: ColorParam, int_ior: f32, ext_ior: f32, specular: Vec3, alpha: ScalarParam, nonlinear: bool },
    /// glTF's metallic-roughness material: a blend, by `metallic` (0–1), of a metal
    /// whose reflectance at normal incidence is `base` (Schlick's Fresnel) and a plastic
    /// (`base` under a coat of index `ior`, glTF's 4 % at 1.5), with one roughness.
    MetallicRoughness { base: ColorParam, metallic: ScalarParam, alpha: ScalarParam, ior: f32 },
}

/// Light arriving from infinitely far away in every direction: a constant radiance, or
/// an equirectangular image (latitude-longitude) scaled by `radiance`.
///
/// Directions map to the image as Mitsuba's `envmap` maps them, in the frame of
/// `transform`: u = atan2(x, −z)/2π (mod 1) runs left to right, v = acos(y)/π from the
/// top row (+y) down.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnvironmentDesc {
    pub radiance: Vec3,
    /// Index into [`super::SceneDesc::textures`]: an image texture in linear RGB.
    pub texture: Option<usize>,
    /// Rotation of the map (only rotations are meaningful; translation is ignored).
    pub transform: Vec<TransformOp>,
}

/// The distribution of microfacet normals of rough lobes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum MicrofacetKind {
    /// GGX (Trowbridge–Reitz): long tails; sampled by visible normals.
    #[default]
    Ggx,
    /// Beckmann: a Gaussian slope distribution, Mitsuba's default; sampled by its
    /// normal distribution.
    Beckmann,
}
