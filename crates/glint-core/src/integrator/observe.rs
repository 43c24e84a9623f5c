//! Watching the Whitted integrator at work: every ray of a pixel's ray tree and every
//! term of the lecture's lighting equation it adds, the way a student checks a ray
//! tracer against the lecture. Rendering passes [`NoObserver`], whose empty methods
//! compile away; explaining a pixel passes a [`RayTree`].

use glam::Vec3;

use crate::math::Ray;
use crate::scene::Hit;

/// Why a ray was traced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    Camera,
    Reflected,
    Refracted,
    /// Past the critical angle the transmitted share is reflected instead.
    TotalInternalReflection,
}

impl RayKind {
    /// The term of the lighting equation a secondary ray of this kind brings back.
    pub fn term_formula(self) -> &'static str {
        match self {
            RayKind::Reflected => "reflected k_s·O_r·I_r",
            _ => "transmitted k_t·O_t·I_t",
        }
    }
}

/// What the integrator tells as it traces. Calls nest: `ray` opens a ray's record,
/// the terms and shadow rays of its hit follow (and the rays it spawns, each opened and
/// closed in turn), and `done` closes it with the colour it returns.
pub trait Observer {
    /// A ray was traced; `hit` is what it met first, if anything.
    fn ray(&mut self, _ray: &Ray, _kind: RayKind, _depth: u32, _hit: Option<&Hit>) {}
    /// A shadow ray toward a light sample, and the filter it found (0 = blocked).
    fn shadow_ray(&mut self, _ray: &Ray, _distance: f32, _filter: Vec3) {}
    /// Light `light` (one of its samples) added these diffuse and specular terms; the
    /// specular one is `specular_formula` (Phong's or Blinn's).
    fn light(&mut self, _light: usize, _diffuse: Vec3, _specular: Vec3, _specular_formula: &'static str) {}
    /// A named term of the equation (ambient, reflected, transmitted) and its value.
    fn term(&mut self, _name: &'static str, _value: Vec3) {}
    /// The ray opened last returns `color`.
    fn done(&mut self, _color: Vec3) {}
}

/// Watches nothing: what rendering uses.
pub struct NoObserver;

impl Observer for NoObserver {}

/// The ray tree of one camera sample, rays in the order they were traced.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RayTree {
    pub rays: Vec<RayRecord>,
    /// Rays opened and not yet done: indices into `rays`.
    open: Vec<usize>,
}

/// One ray of a tree.
#[derive(Clone, Debug, PartialEq)]
pub struct RayRecord {
    pub kind: RayKind,
    /// Bounces from the camera ray (0 for it).
    pub depth: u32,
    /// The ray that spawned this one, as an index into [`RayTree::rays`].
    pub parent: Option<usize>,
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
    /// What it met, if anything.
    pub hit: Option<HitRecord>,
    /// The lighting equation's terms at the hit, in the order added.
    pub terms: Vec<(String, Vec3)>,
    pub shadow_rays: Vec<ShadowRecord>,
    /// The colour the ray brought back (the background where it met nothing).
    pub color: Vec3,
}

/// Where a ray met the scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitRecord {
    /// Distance along the unit direction.
    pub distance: f32,
    pub point: Vec3,
    pub normal: Vec3,
    /// Index into the compiled scene's instances.
    pub instance: u32,
    /// Index into the scene's materials.
    pub material: u32,
}

/// A shadow ray: from the hit toward a light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadowRecord {
    pub origin: Vec3,
    pub dir: Vec3,
    /// How far the light sample lies.
    pub distance: f32,
    /// What reaches the point through the occluders (0: in shadow, 1: lit).
    pub filter: Vec3,
}

impl RayTree {
    fn current(&mut self) -> Option<&mut RayRecord> {
        let at = *self.open.last()?;
        self.rays.get_mut(at)
    }

    /// The camera ray's colour: the sample's value.
    pub fn color(&self) -> Vec3 {
        self.rays.first().map_or(Vec3::ZERO, |r| r.color)
    }
}

impl Observer for RayTree {
    fn ray(&mut self, ray: &Ray, kind: RayKind, depth: u32, hit: Option<&Hit>) {
        let length = ray.dir.length();
        let hit = hit.map(|h| HitRecord {
            distance: h.t * length,
            point: h.point,
            normal: h.normal,
            instance: h.instance,
            material: h.material,
        });
        let parent = self.open.last().copied();
        self.open.push(self.rays.len());
        self.rays.push(RayRecord {
            kind,
            depth,
            parent,
            origin: ray.origin,
            dir: ray.dir / length,
            hit,
            terms: Vec::new(),
            shadow_rays: Vec::new(),
            color: Vec3::ZERO,
        });
    }

    fn shadow_ray(&mut self, ray: &Ray, distance: f32, filter: Vec3) {
        if let Some(current) = self.current() {
            current.shadow_rays.push(ShadowRecord { origin: ray.origin, dir: ray.dir, distance, filter });
        }
    }

    fn light(&mut self, light: usize, diffuse: Vec3, specular: Vec3, specular_formula: &'static str) {
        if let Some(current) = self.current() {
            current.terms.push((format!("light {light} diffuse k_d·O_d·(n·l)"), diffuse));
            current.terms.push((format!("light {light} specular {specular_formula}"), specular));
        }
    }

    fn term(&mut self, name: &'static str, value: Vec3) {
        if let Some(current) = self.current() {
            current.terms.push((name.to_string(), value));
        }
    }

    fn done(&mut self, color: Vec3) {
        if let Some(at) = self.open.pop() {
            self.rays[at].color = color;
        }
    }
}
