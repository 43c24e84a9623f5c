use glam::{Mat4, Vec3};

use super::Ray;

/// `1 + 2γ₃` with `γₙ = n·ε/(1 − n·ε)`, ε = 2⁻²⁴: how far rounding can shrink a slab
/// test's exit distance.
pub const ROBUST_FAR: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// An axis-aligned bounding box; the empty box has `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The box that contains nothing; growing it by any point gives that point.
    pub const EMPTY: Aabb = Aabb { min: Vec3::INFINITY, max: Vec3::NEG_INFINITY };

    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn union(self, other: Aabb) -> Aabb {
        Aabb { min: self.min.min(other.min), max: self.max.max(other.max) }
    }

    pub fn grow(self, p: Vec3) -> Aabb {
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// True when every bound is a finite number (an infinite plane is not).
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the surface area: the SAH only needs ratios, so the factor 2 is dropped.
    pub fn half_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// The box around this box's eight corners after the affine map `m`
    /// (Arvo's method: per matrix entry, take the smaller and larger product).
    pub fn transformed(&self, m: &Mat4) -> Aabb {
        if self.is_empty() {
            return *self;
        }
        let translation = m.w_axis.truncate();
        let (mut min, mut max) = (translation, translation);
        for (col, (lo, hi)) in [
            (m.x_axis.truncate(), (self.min.x, self.max.x)),
            (m.y_axis.truncate(), (self.min.y, self.max.y)),
            (m.z_axis.truncate(), (self.min.z, self.max.z)),
        ] {
            let a = col * lo;
            let b = col * hi;
            min += a.min(b);
            max += a.max(b);
        }
        Aabb { min, max }
    }

    /// Slab test: the parameter interval where the ray is inside the box, if it meets
    /// `(0, t_max)`. `inv_dir` is `1/d` per component (±∞ for zero components).
    #[inline]
    pub fn hit_interval(&self, ray: &Ray, inv_dir: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let t0 = (self.min - ray.origin) * inv_dir;
        let t1 = (self.max - ray.origin) * inv_dir;
        // min/max ignore a NaN operand (0·∞ when the origin lies on a slab plane).
        let near = t0.min(t1).max_element().max(0.0);
        // Widened by the rounding bound of the operations before it, so a ray that meets
        // a flat box exactly on its edge is not culled (Ize, "Robust BVH Ray Traversal",
        // JCGT 2013: 1 + 2γ₃). The widening goes into 1/d: (b − o)·(1/d·R) has the
        // four roundings (b − o)·(1/d)·R has, and saves the wide traversal a multiply.
        let inv_far = inv_dir * ROBUST_FAR;
        let (t0_far, t1_far) = ((self.min - ray.origin) * inv_far, (self.max - ray.origin) * inv_far);
        let far = t0_far.max(t1_far).min_element().min(t_max);
        (near <= far).then_some((near, far))
    }
}
