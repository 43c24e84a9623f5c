use glam::Vec3;

/// A ray `P + t·d`.
///
/// `d` is deliberately not required to be unit length: a world-space ray carried into
/// object space by `M⁻¹` keeps the same parameter `t` only if its direction is left
/// unnormalized (the lecture's "do NOT normalize d̃").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// `P`, the base point.
    pub origin: Vec3,
    /// `d`, the direction (any non-zero length).
    pub dir: Vec3,
    /// When the ray travels, in [0, 1) across the shutter interval: moving instances are
    /// where they are at this time (motion blur). Secondary rays inherit it.
    pub time: f32,
}

impl Ray {
    /// A ray at shutter open (time 0).
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir, time: 0.0 }
    }

    /// The same ray at another time.
    #[inline]
    pub fn at_time(self, time: f32) -> Self {
        Self { time, ..self }
    }

    /// The point `P + t·d`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}
