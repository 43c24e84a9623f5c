//! Integrators: what colour a ray brings back.

pub mod observe;
pub mod path;
pub mod whitted;

use crate::sampling::Rng;

/// What one camera sample carries through its whole ray tree: its own random stream
/// (derived from pixel, sample index and seed), its work counters, and how much of a
/// pixel its filtered textures average over.
#[derive(Clone, Debug)]
pub struct TraceContext {
    pub counters: Counters,
    pub rng: Rng,
    /// The pixel footprint as a fraction of a pixel
    /// ([`crate::scene::Settings::sample_footprint`]).
    pub footprint_scale: f32,
}

/// Work counted while tracing, summed per tile (no shared atomics in the hot path).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Primary, reflected, refracted and shadow rays traced.
    pub rays: u64,
    /// The surface whose shading first made the current sample's radiance NaN or
    /// infinite, if one did: the renderer takes it to report the sample, which it
    /// leaves out of the film. Unset when the culprit was no surface (the background).
    pub non_finite_at: Option<SurfaceId>,
}

/// A surface of the compiled scene: an instance and the material it was shaded with.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SurfaceId {
    /// Index into [`crate::scene::RenderScene::instances`].
    pub instance: u32,
    /// Index into the scene's materials (the description's order).
    pub material: u32,
}

impl SurfaceId {
    /// The surface `hit` lies on.
    pub fn of(hit: &crate::scene::Hit) -> Self {
        Self { instance: hit.instance, material: hit.material }
    }
}

impl Counters {
    /// Notes that shading `hit` left the sample's radiance non-finite, unless a deeper
    /// surface of the same sample already did (the first culprit is the cause).
    #[cold]
    pub fn blame(&mut self, hit: &crate::scene::Hit) {
        self.blame_surface(SurfaceId::of(hit));
    }

    /// [`Counters::blame`] for a surface known by its id (a pending shadow ray keeps
    /// only that of the surface it leaves).
    #[cold]
    pub fn blame_surface(&mut self, surface: SurfaceId) {
        self.non_finite_at.get_or_insert(surface);
    }
}
