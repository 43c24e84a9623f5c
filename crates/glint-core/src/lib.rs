//! glint-core: the renderer itself.
//!
//! Data flows one way: [`desc::SceneDesc`] → [`scene::compile`] → [`scene::RenderScene`]
//! (flat arrays) → [`render::render`] over tiles → [`film::Image`]. This crate never
//! touches files and never prints; progress and cancellation go through callbacks.

pub mod accel;
pub mod bsdf;
pub mod camera;
pub mod desc;
pub mod emitter;
pub mod film;
pub mod fnv;
pub mod footprint;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod mesh;
pub mod normal_map;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shape;
pub mod texture;
