//! The WGSL program: record structs and bindings generated from [`crate::records`],
//! then the hand-written modules, in dependency order.

use crate::records::{self, ALL};

/// Binding numbers of group 0, shared by every kernel.
pub mod binding {
    pub const PARAMS: u32 = 0;
    pub const INSTANCES: u32 = 1;
    pub const NODES: u32 = 2;
    pub const PACKETS: u32 = 3;
    pub const MESHES: u32 = 4;
    pub const BSDFS: u32 = 5;
    pub const EMITTERS: u32 = 6;
    pub const FLOATS: u32 = 7;
    pub const WORDS: u32 = 8;
    pub const TEXTURES: u32 = 9;
    pub const MATERIALS: u32 = 10;
    pub const LIGHTS: u32 = 11;
    pub const SAMPLES: u32 = 12;
    pub const ACCUM: u32 = 13;
    pub const MOTIONS: u32 = 14;
    pub const CSG_NODES: u32 = 15;
    /// Non-finite samples per source, as atomic counters: see film.wgsl's `write_sample`.
    pub const FAULTS: u32 = 16;
    /// Storage buffers (everything but the parameters).
    pub const STORAGE_COUNT: u32 = 16;
}

const MODULES: [&str; 12] = [
    include_str!("shaders/common.wgsl"),
    include_str!("shaders/geometry.wgsl"),
    include_str!("shaders/quadric.wgsl"),
    include_str!("shaders/torus.wgsl"),
    include_str!("shaders/csg.wgsl"),
    include_str!("shaders/implicit.wgsl"),
    include_str!("shaders/bsdf.wgsl"),
    include_str!("shaders/emitter.wgsl"),
    include_str!("shaders/path.wgsl"),
    include_str!("shaders/whitted.wgsl"),
    include_str!("shaders/film.wgsl"),
    include_str!("shaders/rays.wgsl"),
];

/// The record structs, in WGSL.
pub fn structs() -> String {
    ALL.iter().map(|r| r.wgsl()).collect::<Vec<_>>().join("\n")
}

/// The declarations of group 0.
pub fn bindings() -> String {
    use binding::*;
    let storage = |b: u32, name: &str, ty: &str| format!("@group(0) @binding({b}) var<storage, read> {name}: {ty};\n");
    let mut out = format!("@group(0) @binding({PARAMS}) var<uniform> params: {};\n", records::PARAMS.name);
    out += &storage(INSTANCES, "instances", "array<Instance>");
    out += &storage(NODES, "nodes", "array<WideNode>");
    out += &storage(PACKETS, "packets", "array<Triangle4>");
    out += &storage(MESHES, "meshes", "array<GpuMesh>");
    out += &storage(BSDFS, "bsdfs", "array<Bsdf>");
    out += &storage(EMITTERS, "emitters", "array<Emitter>");
    out += &storage(FLOATS, "floats", "array<f32>");
    out += &storage(WORDS, "words", "array<u32>");
    out += &storage(TEXTURES, "textures", "array<Texture>");
    out += &storage(MOTIONS, "motions", "array<Motion>");
    out += &storage(CSG_NODES, "csg_nodes", "array<CsgNode>");
    out += &storage(MATERIALS, "materials", "array<Material>");
    out += &storage(LIGHTS, "lights", "array<Light>");
    out += &format!("@group(0) @binding({SAMPLES}) var<storage, read_write> samples: array<vec4<f32>>;\n");
    out += &format!("@group(0) @binding({ACCUM}) var<storage, read_write> accum: array<vec4<f32>>;\n");
    out += &format!("@group(0) @binding({FAULTS}) var<storage, read_write> faults: array<atomic<u32>>;\n");
    out
}

/// The constants the shaders compare record fields with, from their Rust definitions.
pub fn constants() -> String {
    use glint_core::light::LightKind;
    let values = [
        ("ADAPTIVE_PILOT", records::ADAPTIVE_PILOT),
        ("INTEGRATOR_PATH", records::INTEGRATOR_PATH),
        ("INTEGRATOR_WHITTED", records::INTEGRATOR_WHITTED),
        ("FEATURE_SHADOWS", records::FEATURE_SHADOWS),
        ("FEATURE_REFLECTIONS", records::FEATURE_REFLECTIONS),
        ("FEATURE_REFRACTIONS", records::FEATURE_REFRACTIONS),
        ("FEATURE_TEXTURES", records::FEATURE_TEXTURES),
        ("FEATURE_TRANSPARENT_SHADOWS", records::FEATURE_TRANSPARENT_SHADOWS),
        ("PATTERN_GRID", records::PATTERN_GRID),
        ("PATTERN_CORNERS", records::PATTERN_CORNERS),
        ("PATTERN_JITTERED", records::PATTERN_JITTERED),
        ("PATTERN_SOBOL", records::PATTERN_SOBOL),
        ("LIGHT_POINT", LightKind::Point as u32),
        ("LIGHT_DIRECTIONAL", LightKind::Directional as u32),
        ("LIGHT_SPOT", LightKind::Spot as u32),
        ("LIGHT_RECTANGLE", LightKind::Rectangle as u32),
        ("LIGHT_DISK", LightKind::Disk as u32),
        ("LIGHT_SPHERE", LightKind::Sphere as u32),
        ("NO_TEXTURE", glint_core::material::NO_TEXTURE),
        ("BLINN_HIGHLIGHT", glint_core::material::BLINN_HIGHLIGHT),
        ("KIND_SUPERELLIPSOID", glint_core::shape::ShapeKind::Superellipsoid as u32),
        ("KIND_IMPLICIT", glint_core::shape::ShapeKind::Implicit as u32),
        ("KIND_BLOB", glint_core::shape::ShapeKind::Blob as u32),
    ];
    values.iter().map(|(name, value)| format!("const {name}: u32 = {value}u;\n")).collect()
}

/// The whole program the render kernels are compiled from.
pub fn source() -> String {
    let mut out = structs();
    out += "\n";
    out += &bindings();
    out += "\n";
    out += &constants();
    for module in MODULES {
        out += "\n";
        out += module;
    }
    out
}
