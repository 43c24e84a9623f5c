//! A Whitted tile of a scene with BVHs, traced in packets: the camera rays of up to
//! [`PACKET`] neighbouring pixels (one sample index each) go through the BVHs together
//! ([`RenderScene::intersect_packet`]), and so do the shadow rays from their hits to
//! each light sample ([`RenderScene::occluded_packet`]): neighbouring hits send nearly
//! parallel rays to one light, which walk the same nodes. Reflected and refracted rays,
//! which part ways at curved surfaces, are traced one by one with their shadow rays.
//!
//! A sample sums the same terms in the same order as the recursion ([`whitted::shade`]):
//! the ambient term, each light in order, then the reflected and the transmitted term.
//! So the image is the recursion's, bit for bit. Where transparent occluders filter
//! shadows, the shadow rays are traced one by one as they come.

use glam::Vec3;

use super::{CameraSample, TileFilm, Traced, camera_sample, whitted_aov};
use crate::accel::PACKET;
use crate::film::Aov;
use crate::integrator::observe::NoObserver;
use crate::integrator::whitted::{self, Facing, ShadowRays, TracedNow, for_each_secondary, shade_vertex};
use crate::integrator::{Counters, TraceContext};
use crate::math::Ray;
use crate::scene::{Hit, RenderScene};

/// Every sample of every pixel of the tile `(x0, y0, x1, y1)`, splatted into `film` in
/// pixel order; the shading compiled for AVX2 where the CPU has it.
pub(super) fn packet_tile(
    scene: &RenderScene,
    tile: (u32, u32, u32, u32),
    film: &mut TileFilm,
    counters: &mut Counters,
) {
    crate::accel::lanes::on_avx2_or!(
        |_avx| packet_tile_avx2(scene, tile, film, counters),
        packet_tile_on(scene, tile, film, counters)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn packet_tile_avx2(scene: &RenderScene, tile: (u32, u32, u32, u32), film: &mut TileFilm, counters: &mut Counters) {
    packet_tile_on(scene, tile, film, counters)
}

#[inline(always)]
fn packet_tile_on(scene: &RenderScene, tile: (u32, u32, u32, u32), film: &mut TileFilm, counters: &mut Counters) {
    let (x0, y0, x1, y1) = tile;
    let s = &scene.settings;
    let count = s.spp as usize;
    // Per pixel of a run, per sample: film position, value and AOVs.
    let mut values: Vec<Traced> = (0..PACKET * count)
        .map(|_| Traced { fx: 0.0, fy: 0.0, value: Vec3::ZERO, aov: Aov::default(), culprit: None })
        .collect();
    let mut shadows = Shadows { defer: defers_shadow_rays(scene), pending: Vec::new(), starts: [0; PACKET + 1] };
    for py in y0..y1 {
        for run_x in (x0..x1).step_by(PACKET) {
            let run = (x1 - run_x).min(PACKET as u32) as usize;
            for index in 0..count as u32 {
                let mut samples: [CameraSample; PACKET] =
                    std::array::from_fn(|k| camera_sample(scene, &s.sampler, run_x + k.min(run - 1) as u32, py, index));
                let rays: [Ray; PACKET] = std::array::from_fn(|k| samples[k].ray);
                let mut hits = [None; PACKET];
                scene.intersect_packet(&rays[..run], &mut hits[..run]);
                let mut shaded = [Shaded::default(); PACKET];
                for (k, sample) in samples.iter_mut().enumerate().take(run) {
                    shadows.starts[k] = shadows.pending.len();
                    let collector = &mut Collector { shadows: &mut shadows };
                    shaded[k] = shade_camera_hit(scene, &sample.ray, hits[k].as_ref(), &mut sample.ctx, collector);
                }
                shadows.resolve(scene, run, &mut shaded);
                for (k, sample) in samples.iter_mut().enumerate().take(run) {
                    let value = shaded[k].sum();
                    if let Some(hit) = hits[k].as_ref().filter(|_| !value.is_finite()) {
                        sample.ctx.counters.blame(hit);
                    }
                    counters.rays += sample.ctx.counters.rays;
                    let aov = whitted_aov(scene, &sample.ray, hits[k].as_ref(), sample.ctx.footprint_scale);
                    let culprit = sample.ctx.counters.non_finite_at;
                    values[k * count + index as usize] = Traced { fx: sample.fx, fy: sample.fy, value, aov, culprit };
                }
            }
            for traced in &values[..run * count] {
                film.splat(traced);
            }
        }
    }
}

/// Whether shadow rays can wait to be traced in packets: they can where each is only
/// blocked or not, and not where transparent occluders filter them (those rays go on
/// past each surface they cross, one by one).
fn defers_shadow_rays(scene: &RenderScene) -> bool {
    !(scene.has_transmissive && scene.settings.features.transparent_shadows)
}

/// A camera sample's terms, kept apart until its waiting shadow rays are traced: its
/// local light (the background, or the ambient term and every light found unblocked so
/// far) and the reflected and transmitted terms, added last as the recursion adds them.
#[derive(Clone, Copy, Default)]
struct Shaded {
    local: Vec3,
    secondary: [Option<Vec3>; 2],
}

impl Shaded {
    /// The sample's value, summed in the recursion's order.
    #[inline(always)]
    fn sum(&self) -> Vec3 {
        self.secondary.iter().flatten().fold(self.local, |sum, &term| sum + term)
    }
}

/// The recursion's top level ([`whitted::shade`] at depth 0) for a camera ray and its
/// closest hit, its own shadow rays handed to `shadows`; the reflected and refracted
/// rays are traced and shaded at once.
#[inline(always)]
fn shade_camera_hit(
    scene: &RenderScene,
    ray: &Ray,
    hit: Option<&Hit>,
    ctx: &mut TraceContext,
    shadows: &mut Collector,
) -> Shaded {
    ctx.counters.rays += 1;
    let Some(hit) = hit else { return Shaded { local: scene.background(ray.dir), secondary: [None; 2] } };
    let facing = Facing::of(ray, hit);
    let seen = (ray, hit, &facing);
    let local = shade_vertex(scene, seen, ctx, shadows, &mut NoObserver);
    let mut secondary = [None; 2];
    let mut slots = secondary.iter_mut();
    for_each_secondary(scene, seen, 0, Vec3::ONE, |r, _, k, weight| {
        let hit = scene.intersect(&r, f32::INFINITY);
        let term = k * whitted::shade(scene, &r, hit, 1, weight, ctx);
        *slots.next().expect("at most a reflected and a transmitted ray") = Some(term);
    });
    Shaded { local, secondary }
}

/// A shadow ray waiting for its packet, with the light it adds to its sample's local
/// term if nothing is in the way.
struct PendingShadow {
    slot: u32,
    ray: Ray,
    t_max: f32,
    light: Vec3,
}

/// The shadow rays of one packet of camera samples, waiting to be traced together:
/// each sample's rays in a run of their own, in the order of their light samples.
struct Shadows {
    defer: bool,
    pending: Vec<PendingShadow>,
    /// Where each sample's run begins, and after the last sample, where the runs end.
    starts: [usize; PACKET + 1],
}

impl Shadows {
    /// Traces the waiting rays of the first `count` samples, those to one light sample
    /// together (one packet: a sample sends one ray to each), light samples in order,
    /// and adds each unblocked ray's light to its sample: so each sample adds its lights
    /// in the recursion's order.
    #[inline(always)]
    fn resolve(&mut self, scene: &RenderScene, count: usize, shaded: &mut [Shaded; PACKET]) {
        self.starts[count] = self.pending.len();
        let mut next: [usize; PACKET] = std::array::from_fn(|k| self.starts[k.min(count)]);
        loop {
            // The first light sample still waiting, and the samples whose next ray goes to it.
            let head = |k: usize| (next[k] < self.starts[k + 1]).then(|| self.pending[next[k]].slot);
            let Some(slot) = (0..count).filter_map(head).min() else { break };
            let mut members = [0usize; PACKET];
            let mut size = 0;
            for k in 0..count {
                if head(k) == Some(slot) {
                    members[size] = k;
                    size += 1;
                }
            }
            let ray_of = |i: usize| &self.pending[next[members[i]]];
            let rays: [Ray; PACKET] = std::array::from_fn(|i| ray_of(i.min(size - 1)).ray);
            let t_max: [f32; PACKET] = std::array::from_fn(|i| ray_of(i.min(size - 1)).t_max);
            let blocked = scene.occluded_packet(&rays[..size], &t_max);
            for (i, &k) in members[..size].iter().enumerate() {
                if blocked >> i & 1 == 0 {
                    shaded[k].local += self.pending[next[k]].light;
                }
                next[k] += 1;
            }
        }
        self.pending.clear();
    }
}

/// A sample's view of [`Shadows`]: its shadow rays wait there, or where they cannot
/// wait, are traced at once.
struct Collector<'a> {
    shadows: &'a mut Shadows,
}

impl ShadowRays for Collector<'_> {
    #[inline(always)]
    fn filter(&mut self, scene: &RenderScene, ray: &Ray, t_max: f32) -> Option<Vec3> {
        if self.shadows.defer { None } else { TracedNow.filter(scene, ray, t_max) }
    }

    #[inline(always)]
    fn defer(&mut self, ray: &Ray, t_max: f32, light: Vec3, slot: u32) {
        self.shadows.pending.push(PendingShadow { slot, ray: *ray, t_max, light });
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::desc::{
        AreaShape, CameraDesc, LightDesc, MaterialDesc, MeshDesc, NodeDesc, NodeKind, SceneDesc, ShapeDesc, TransformOp,
    };
    use crate::render::{new_film, trace_sample};

    /// Mesh instances (a BVH scene, not a handful of analytic objects) on a mirror
    /// floor, lit by two point lights and an area light, seen by a jittered 2×2
    /// pattern: neighbouring pixels' shadow rays go in packets.
    fn scene(transmissive: Vec3) -> RenderScene {
        let tetrahedron = MeshDesc {
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z],
            indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
            ..Default::default()
        };
        let shapes = [ShapeDesc::Sphere, ShapeDesc::Mesh { index: 0 }];
        let mut objects: Vec<NodeDesc> = (0..40)
            .map(|i| NodeDesc {
                transform: vec![
                    TransformOp::Scale(Vec3::splat(0.4)),
                    TransformOp::Translate(Vec3::new((i % 8) as f32 - 3.5, 0.2, -((i / 8) as f32))),
                ],
                kind: NodeKind::Shape { shape: shapes[i % 2], material: i % 2 },
                origin: String::new(),
            })
            .collect();
        objects.push(NodeDesc {
            transform: Vec::new(),
            kind: NodeKind::Shape { shape: ShapeDesc::Plane, material: 2 },
            origin: String::new(),
        });
        let mut desc = SceneDesc {
            meshes: vec![tetrahedron],
            materials: vec![
                MaterialDesc { specular: Vec3::splat(0.5), transmissive, ..Default::default() },
                MaterialDesc { diffuse: Vec3::new(0.2, 0.6, 0.7), ..Default::default() },
                MaterialDesc { reflective: Some(Vec3::splat(0.3)), ..Default::default() },
            ],
            lights: vec![
                LightDesc::Point { position: Vec3::new(-3.0, 5.0, 3.0), color: Vec3::splat(0.7), attenuation: Vec3::X },
                LightDesc::Area {
                    shape: AreaShape::Disk { center: Vec3::new(2.0, 4.0, 1.0), normal: Vec3::NEG_Y, radius: 0.8 },
                    color: Vec3::splat(0.5),
                    attenuation: Vec3::X,
                    samples: 4,
                },
                LightDesc::Point { position: Vec3::new(4.0, 2.0, -1.0), color: Vec3::splat(0.3), attenuation: Vec3::X },
            ],
            camera: CameraDesc {
                eye: Vec3::new(0.0, 3.0, 5.0),
                look: Vec3::new(0.0, -0.5, -1.0),
                ..Default::default()
            },
            objects,
            ..Default::default()
        };
        desc.settings.width = 40;
        desc.settings.height = 30;
        desc.settings.samples_per_axis = 2;
        desc.settings.pattern = crate::sampling::SamplePattern::Jittered;
        desc.settings.max_depth = 3;
        let scene = crate::scene::compile(&desc).expect("valid scene");
        assert!(scene.few_objects.is_none(), "the test needs the BVH path");
        scene
    }

    /// A tile traced in packets is the tile traced sample by sample through the
    /// recursion, bit for bit: the same hits, the same shadows, the same sums in the
    /// same order. With transparent occluders (shadow rays traced as they come), too.
    #[test]
    fn packets_sum_what_the_recursion_sums() {
        for transmissive in [Vec3::ZERO, Vec3::splat(0.4)] {
            let scene = scene(transmissive);
            assert_eq!(defers_shadow_rays(&scene), transmissive == Vec3::ZERO);
            let (width, height) = (scene.settings.width, scene.settings.height);
            let film = || TileFilm {
                scene: &scene,
                film: new_film(&scene, 0, 0, width, height),
                non_finite: Default::default(),
            };
            let (mut packed, mut packed_counters) = (film(), Counters::default());
            packet_tile(&scene, (0, 0, width, height), &mut packed, &mut packed_counters);
            let (mut single, mut single_counters) = (film(), Counters::default());
            for py in 0..height {
                for px in 0..width {
                    for index in 0..scene.settings.spp {
                        let traced = trace_sample(&scene, &scene.settings.sampler, px, py, index, &mut single_counters);
                        single.splat(&traced);
                    }
                }
            }
            assert!(packed.film == single.film, "packets and recursion differ (transmissive {transmissive})");
            assert_eq!(packed_counters.rays, single_counters.rays);
            // Enough happens to test: several rays per camera ray (shadows, reflections).
            assert!(packed_counters.rays > 3 * u64::from(width * height * scene.settings.spp));
        }
    }
}
