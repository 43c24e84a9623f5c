//! Geometry primitives shared by every part of the renderer: a thin layer over glam.

mod aabb;
mod finite;
mod offset;
pub mod polynomial;
mod ray;
pub mod roots;
mod transform;
mod unit;
pub mod wide;

pub use aabb::{Aabb, ROBUST_FAR};
pub use finite::all_finite;
pub use offset::{offset_ray_origin, offset_ray_origins};
pub use ray::Ray;
pub use transform::Transform;
pub use unit::{unit_or, unit_or_zero};

pub use glam::{Mat3, Mat4, Vec2, Vec3};
