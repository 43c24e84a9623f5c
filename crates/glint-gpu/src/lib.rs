//! glint's GPU backend: the compiled [`glint_core::scene::RenderScene`] rendered by
//! WGSL compute shaders over wgpu, so it runs on Vulkan, Metal and DX12 GPUs and, for
//! tests without one, on Mesa's lavapipe.
//!
//! The scene is uploaded once from the same flat arrays the CPU renders
//! ([`upload`]); every record the shaders read is declared once for Rust and WGSL
//! ([`layout`], [`records`]); samples come from the same 32-bit generators as on the
//! CPU (the path sampler; the Whitted integrator's pixel patterns and per-sample random
//! stream), so both backends trace the same rays and their images can be compared pixel
//! by pixel.

pub mod device;
pub mod hardware;
pub mod layout;
pub mod records;
pub mod render;
pub mod shader;
pub mod upload;

pub use device::{Gpu, GpuError};
pub use render::{GpuRenderError, Progressive, RayHit, RayQuery, render, trace_rays};
