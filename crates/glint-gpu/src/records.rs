//! The records the shaders read: glint-core's compiled-scene records as they are, and
//! the few the GPU layout adds (mesh offsets into the concatenated arrays, per-pass
//! parameters). Each is declared once here; the WGSL structs are generated from these
//! declarations (see [`crate::layout`]).

use bytemuck::{Pod, Zeroable};
use glam::Mat4;
use glint_core::accel::WideNode;
use glint_core::bsdf::Bsdf;
use glint_core::emitter::Emitter;
use glint_core::light::Light;
use glint_core::material::Material;
use glint_core::mesh::Triangle4;
use glint_core::scene::{Instance, Motion};
use glint_core::shape::CsgNode;
use glint_core::texture::Texture;

use crate::gpu_record;
use crate::layout::Record;

gpu_record!(pub INSTANCE = Instance as "Instance" {
    world_from_object: Mat4 => transform.world_from_object,
    object_from_world: Mat4 => transform.object_from_world,
    kind: U32 => shape.kind,
    param: F32 => shape.param,
    material: U32 => material,
    motion: U32 => motion,
});

gpu_record!(pub WIDE_NODE = WideNode as "WideNode" {
    bounds: F32s(48) => bounds,
    child: U32s(8) => child,
    count: U32s(8) => count,
});

gpu_record!(pub TRIANGLE4 = Triangle4 as "Triangle4" {
    p: F32s(36) => p,
    triangle: U32s(4) => triangle,
});

gpu_record!(pub BSDF = Bsdf as "Bsdf" {
    kind: U32 => kind,
    flags: U32 => flags,
    color: Vec3 => color,
    color_texture: U32 => color_texture,
    texture_scale: Vec3 => texture_scale,
    blend: F32 => blend,
    uv_repeat: Vec2 => uv_repeat,
    specular: Vec3 => specular,
    transmittance: Vec3 => transmittance,
    eta: Vec3 => eta,
    k: Vec3 => k,
    alpha: F32 => alpha,
    alpha_texture: U32 => alpha_texture,
    glossy: Vec3 => glossy,
    exponent: F32 => exponent,
    internal_reflectance: F32 => internal_reflectance,
    coat_transmittance: F32s(32) => coat_transmittance,
    emission: Vec3 => emission,
    emission_texture: U32 => emission_texture,
    metallic: F32 => metallic,
    metallic_texture: U32 => metallic_texture,
});

gpu_record!(pub EMITTER = Emitter as "Emitter" {
    kind: U32 => kind,
    p: Vec3 => p,
    e1: Vec3 => e1,
    e2: Vec3 => e2,
    normal: Vec3 => normal,
    radiance: Vec3 => radiance,
    size: F32 => size,
    attenuation: Vec3 => attenuation,
    cos_inner: F32 => cos_inner,
    cos_outer: F32 => cos_outer,
    two_sided: U32 => two_sided,
    linear_falloff: U32 => linear_falloff,
});

gpu_record!(pub TEXTURE = Texture as "Texture" {
    kind: U32 => kind,
    width: U32 => width,
    height: U32 => height,
    offset: U32 => offset,
    even: Vec3 => even,
    odd: Vec3 => odd,
    cells: Vec2 => cells,
    flags: U32 => flags,
});

gpu_record!(pub MOTION = Motion as "Motion" {
    inner_world_from_object: Mat4 => inner.world_from_object,
    inner_object_from_world: Mat4 => inner.object_from_world,
    outer_world_from_object: Mat4 => outer.world_from_object,
    outer_object_from_world: Mat4 => outer.object_from_world,
    open_rotation: Vec4 => open.rotation,
    open_translation: Vec3 => open.translation,
    open_pad: F32 => open._pad0,
    open_scale: Vec3 => open.scale,
    open_pad1: F32 => open._pad1,
    close_rotation: Vec4 => close.rotation,
    close_translation: Vec3 => close.translation,
    close_pad: F32 => close._pad0,
    close_scale: Vec3 => close.scale,
    close_pad1: F32 => close._pad1,
});

gpu_record!(pub MATERIAL = Material as "Material" {
    ambient: Vec3 => ambient,
    diffuse: Vec3 => diffuse,
    specular: Vec3 => specular,
    reflective: Vec3 => reflective,
    transmissive: Vec3 => transmissive,
    kd: F32 => kd,
    shininess: F32 => shininess,
    ior: F32 => ior,
    blend: F32 => blend,
    texture: U32 => texture,
    texture_repeat: Vec2 => texture_repeat,
    normal_texture: U32 => normal_texture,
    normal_scale: F32 => normal_scale,
    ka: F32 => ka,
    ambient_blend: F32 => ambient_blend,
    highlight: U32 => highlight,
});

// `kind` is a `#[repr(u32)]` enum: one word, read as the discriminant.
gpu_record!(pub LIGHT = Light as "Light" {
    kind: U32 => kind,
    color: Vec3 => color,
    position: Vec3 => position,
    direction: Vec3 => direction,
    attenuation: Vec3 => attenuation,
    inner_angle: F32 => inner_angle,
    outer_angle: F32 => outer_angle,
    edge_u: Vec3 => edge_u,
    edge_v: Vec3 => edge_v,
    radius: F32 => radius,
    samples_per_axis: U32 => samples_per_axis,
    linear_falloff: U32 => linear_falloff,
});

/// Where one mesh's data starts in the concatenated arrays: its BVH nodes and triangle
/// packets (whose indices stay mesh-relative), and its vertices, indices and optional
/// attributes in the shared float and word arrays.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuMesh {
    pub node_offset: u32,
    pub packet_offset: u32,
    /// Index into the float array of vertex 0's x.
    pub position_offset: u32,
    /// Index into the word array of triangle 0's first vertex index.
    pub index_offset: u32,
    /// Float-array index of the normals, or [`NONE`] without them.
    pub normal_offset: u32,
    /// Float-array index of the uvs, or [`NONE`] without them.
    pub uv_offset: u32,
    /// Whether the mesh has nodes at all (an empty mesh hits nothing).
    pub node_count: u32,
    /// Float-array index of the vertex colours, or [`NONE`] without them.
    pub color_offset: u32,
}

gpu_record!(pub CSG_NODE = CsgNode as "CsgNode" {
    world_from_object: Mat4 => transform.world_from_object,
    object_from_world: Mat4 => transform.object_from_world,
    min: Vec3 => min,
    op: U32 => op,
    max: Vec3 => max,
    material: U32 => material,
    kind: U32 => shape.kind,
    param: F32 => shape.param,
    first: U32 => first,
    pad: U32 => _pad,
});

/// Floats per quadric in the float array: its ten coefficients, then `min` and `max`.
/// A quadric is plain f32s in that order (checked below), so it goes up as it is.
pub const QUADRIC_FLOATS: usize = 16;
const _: () = {
    use glint_core::shape::Quadric;
    assert!(std::mem::size_of::<Quadric>() == 4 * QUADRIC_FLOATS);
    assert!(std::mem::offset_of!(Quadric, coefficients) == 0);
    assert!(std::mem::offset_of!(Quadric, min) == 40);
    assert!(std::mem::offset_of!(Quadric, max) == 52);
};

/// "No such array" in an offset field.
pub const NONE: u32 = u32::MAX;

gpu_record!(pub GPU_MESH = GpuMesh as "GpuMesh" {
    node_offset: U32 => node_offset,
    packet_offset: U32 => packet_offset,
    position_offset: U32 => position_offset,
    index_offset: U32 => index_offset,
    normal_offset: U32 => normal_offset,
    uv_offset: U32 => uv_offset,
    node_count: U32 => node_count,
    color_offset: U32 => color_offset,
});

/// Everything a pass needs besides the scene arrays: image and sample range, the
/// integrator's settings, the camera, the environment and the filter. A uniform, so
/// only scalars, `vec4` and `mat4x4` (no 4-byte-stride arrays).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Params {
    pub width: u32,
    pub height: u32,
    /// Index of the pass's first sample per pixel.
    pub sample_offset: u32,
    /// Samples per pixel in this pass.
    pub pass_samples: u32,
    pub seed: u32,
    /// 0 = Sobol, 1 = independent.
    pub sampler: u32,
    /// Path: vertices per path at most; Whitted: the recursion depth at most.
    pub max_depth: u32,
    pub rr_depth: u32,
    pub bounded_count: u32,
    pub instance_count: u32,
    /// Number of emitters (0: no light to sample).
    pub emitter_count: u32,
    /// Float-array index of the light-selection cdf (`emitter_count + 1` entries).
    pub light_cdf_offset: u32,
    pub environment_emitter: u32,
    /// 0: constant background; 1: constant environment light; 2: image map.
    pub environment_kind: u32,
    pub env_width: u32,
    pub env_height: u32,
    pub env_texel_offset: u32,
    /// Float-array index of the map's marginal cdf, followed by each row's cdf.
    pub env_cdf_offset: u32,
    pub filter_kind: u32,
    pub filter_radius: f32,
    pub filter_scale: f32,
    pub aperture_radius: f32,
    pub focal_distance: f32,
    pub node_count: u32,
    /// Float-array index of the texture texels.
    pub texel_offset: u32,
    /// Word-array index of the per-instance first emitter.
    pub instance_emitter_offset: u32,
    /// [`INTEGRATOR_PATH`] or [`INTEGRATOR_WHITTED`].
    pub integrator: u32,
    /// Whitted: a reflected or transmitted ray whose weight in the pixel is at most
    /// this is not traced.
    pub min_contribution: f32,
    /// Whitted: the [`FEATURE_SHADOWS`], … bits that are on.
    pub features: u32,
    /// Whitted: 1 when some material lets light through (shadow rays look past hits).
    pub has_transmissive: u32,
    /// Whitted: the pixel pattern, [`PATTERN_GRID`] to [`PATTERN_SOBOL`].
    pub pattern: u32,
    /// Whitted: samples along each axis of the grid-based patterns.
    pub per_axis: u32,
    /// Whitted: number of lights.
    pub light_count: u32,
    /// Whitted: the pixel pattern's seed (jittered and Sobol).
    pub pattern_seed: u32,
    /// Float-array index of the quadrics: 16 floats each (see [`QUADRIC_FLOATS`]).
    pub quadric_offset: u32,
    /// 1 when some instance moves: each path then draws a time in the shutter.
    pub has_motion: u32,
    /// 1 when the film keeps AOV planes (albedo and depth, normal) beside the colour.
    pub aovs: u32,
    /// Adaptive sampling's minimum samples per pixel; 0 in a uniform pass.
    pub adaptive_min: u32,
    /// Adaptive sampling's maximum samples per pixel.
    pub adaptive_max: u32,
    /// Adaptive sampling's standard-error threshold on display luminance.
    pub adaptive_threshold: f32,
    /// 1 in the adaptive round whose samples bring every pixel to the minimum: its
    /// decision looks at the neighbours' means (film.wgsl's `adaptive_decide`);
    /// [`ADAPTIVE_PILOT`] when that round is each pixel's pilot at its centre.
    pub adaptive_first: u32,
    /// Float-array index of the superellipsoids' exponents: `e1`, `e2` each.
    pub superellipsoid_offset: u32,
    /// Word-array index of the implicit surfaces' records (see implicit.wgsl).
    pub implicit_offset: u32,
    /// Word-array index of the blobs' records (see implicit.wgsl).
    pub blob_offset: u32,
    pub background: [f32; 4],
    /// Whitted: the ambient light `L_a`.
    pub ambient: [f32; 4],
    pub env_scale: [f32; 4],
    pub eye: [f32; 4],
    pub right: [f32; 4],
    pub up: [f32; 4],
    pub forward: [f32; 4],
    /// Whitted: one pixel's step across and down the film (glint_core::footprint), for
    /// textures filtered over a pixel's footprint; `pixel_dx[3]` is the footprint's
    /// scale in a uniform render (`Settings::footprint_scale`).
    pub pixel_dx: [f32; 4],
    pub pixel_dy: [f32; 4],
    pub world_from_canonical: Mat4,
    pub env_from_world: Mat4,
    pub world_from_env: Mat4,
}

/// [`Params::adaptive_first`] in a pilot round: each pixel's one sample at its centre.
pub const ADAPTIVE_PILOT: u32 = 2;

/// [`Params::integrator`] values.
pub const INTEGRATOR_PATH: u32 = 0;
pub const INTEGRATOR_WHITTED: u32 = 1;

/// [`Params::features`] bits, after `glint_core::desc::Features`.
pub const FEATURE_SHADOWS: u32 = 1;
pub const FEATURE_REFLECTIONS: u32 = 2;
pub const FEATURE_REFRACTIONS: u32 = 4;
pub const FEATURE_TEXTURES: u32 = 8;
pub const FEATURE_TRANSPARENT_SHADOWS: u32 = 16;

/// [`Params::pattern`] values, after `glint_core::sampling::SamplePattern`.
pub const PATTERN_GRID: u32 = 0;
pub const PATTERN_CORNERS: u32 = 1;
pub const PATTERN_JITTERED: u32 = 2;
pub const PATTERN_SOBOL: u32 = 3;

gpu_record!(pub PARAMS = Params as "Params" {
    width: U32 => width,
    height: U32 => height,
    sample_offset: U32 => sample_offset,
    pass_samples: U32 => pass_samples,
    seed: U32 => seed,
    sampler: U32 => sampler,
    max_depth: U32 => max_depth,
    rr_depth: U32 => rr_depth,
    bounded_count: U32 => bounded_count,
    instance_count: U32 => instance_count,
    emitter_count: U32 => emitter_count,
    light_cdf_offset: U32 => light_cdf_offset,
    environment_emitter: U32 => environment_emitter,
    environment_kind: U32 => environment_kind,
    env_width: U32 => env_width,
    env_height: U32 => env_height,
    env_texel_offset: U32 => env_texel_offset,
    env_cdf_offset: U32 => env_cdf_offset,
    filter_kind: U32 => filter_kind,
    filter_radius: F32 => filter_radius,
    filter_scale: F32 => filter_scale,
    aperture_radius: F32 => aperture_radius,
    focal_distance: F32 => focal_distance,
    node_count: U32 => node_count,
    texel_offset: U32 => texel_offset,
    instance_emitter_offset: U32 => instance_emitter_offset,
    integrator: U32 => integrator,
    min_contribution: F32 => min_contribution,
    features: U32 => features,
    has_transmissive: U32 => has_transmissive,
    pattern: U32 => pattern,
    per_axis: U32 => per_axis,
    light_count: U32 => light_count,
    pattern_seed: U32 => pattern_seed,
    quadric_offset: U32 => quadric_offset,
    has_motion: U32 => has_motion,
    aovs: U32 => aovs,
    adaptive_min: U32 => adaptive_min,
    adaptive_max: U32 => adaptive_max,
    adaptive_threshold: F32 => adaptive_threshold,
    adaptive_first: U32 => adaptive_first,
    superellipsoid_offset: U32 => superellipsoid_offset,
    implicit_offset: U32 => implicit_offset,
    blob_offset: U32 => blob_offset,
    background: Vec4 => background,
    ambient: Vec4 => ambient,
    env_scale: Vec4 => env_scale,
    eye: Vec4 => eye,
    right: Vec4 => right,
    up: Vec4 => up,
    forward: Vec4 => forward,
    pixel_dx: Vec4 => pixel_dx,
    pixel_dy: Vec4 => pixel_dy,
    world_from_canonical: Mat4 => world_from_canonical,
    env_from_world: Mat4 => env_from_world,
    world_from_env: Mat4 => world_from_env,
});

/// Every record, for the layout test and for generating the shader prelude.
pub const ALL: [Record; 12] =
    [INSTANCE, WIDE_NODE, TRIANGLE4, BSDF, EMITTER, TEXTURE, MOTION, MATERIAL, LIGHT, CSG_NODE, GPU_MESH, PARAMS];
