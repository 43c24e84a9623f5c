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
}

impl Ray {
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The point `P + t·d`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}
