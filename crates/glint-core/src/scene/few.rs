//! Eight rays at once against a scene of a handful of analytic objects.
//!
//! A Cornell box or a classic Whitted scene holds fewer objects than a BVH node has
//! children. For one ray, the instance BVH walk is then mostly bookkeeping: setting up
//! the slab test, sorting the boxes it enters, transforming the ray for each object it
//! tests. Eight rays side by side (a wave of paths, [`crate::render`]) can instead take
//! each object once, in order, with the rays in the lanes: one transform and one
//! shape test per object serve all eight, and the loops compile to AVX2 with no
//! gathers. Every lane does the very arithmetic the object's own scalar test does, in
//! the same order, so each ray finds the hit the scalar walk finds (on an exact tie
//! between two objects either may win, as between two BVH orders).

// Lane loops index several arrays by the same lane: written so, they vectorize.
#![allow(clippy::needless_range_loop)]

use super::{Hit, Instance, NO_MOTION, RenderScene};
use crate::math::Ray;
use crate::shape::{Cone, Cube, Cylinder, Disk, Plane, Primitive, Rectangle, ShapeHit, ShapeKind, Sphere};
use glam::Vec3;

/// Rays traced side by side.
pub const WAVE: usize = 8;

/// The most objects a scene may have for [`FewObjects`]: beyond that the BVH's culling
/// wins over testing everything.
const MOST_OBJECTS: usize = 16;

/// One lane value per ray.
type Lanes = [f32; WAVE];

/// A wave of rays, structure of arrays: `origin[axis][lane]`.
#[derive(Clone, Copy, Debug, Default)]
pub struct RayWave {
    pub origin: [Lanes; 3],
    pub dir: [Lanes; 3],
    /// Each ray's segment ends here (`f32::INFINITY` for closest hits); 0 leaves the lane
    /// out.
    pub t_max: Lanes,
    /// All ones in lanes that ask "anything in the way?" (shadow rays): objects that
    /// cast no shadow are not tested for them. (Integer masks, not `bool`s, keep the
    /// lane loops in vector registers.)
    pub shadow: [u32; WAVE],
}

impl RayWave {
    /// Puts `ray`, to be traced over `0 < t < t_max`, in lane `lane`.
    #[inline(always)]
    pub fn set(&mut self, lane: usize, ray: &Ray, t_max: f32, shadow: bool) {
        for axis in 0..3 {
            self.origin[axis][lane] = ray.origin[axis];
            self.dir[axis][lane] = ray.dir[axis];
        }
        self.t_max[lane] = t_max;
        self.shadow[lane] = if shadow { u32::MAX } else { 0 };
    }
}

/// The nearest hit of each lane: `object` is [`NO_OBJECT`] where the ray found none.
#[derive(Clone, Copy, Debug)]
pub struct WaveHits {
    pub t: Lanes,
    pub object: [u32; WAVE],
    pub part: [u32; WAVE],
}

impl WaveHits {
    /// Takes object `index`'s hits (`t`, `f32::INFINITY` for none, and `part`) where
    /// they are nearer. Branch-free (integer masks), so it compiles to vector blends.
    #[inline(always)]
    fn keep_closer(&mut self, t: &Lanes, part: &[u32; WAVE], index: u32) {
        let mut closer = [0u32; WAVE];
        for lane in 0..WAVE {
            closer[lane] = 0u32.wrapping_sub(u32::from(t[lane] < self.t[lane]));
        }
        for lane in 0..WAVE {
            let keep = self.t[lane].to_bits() & !closer[lane];
            self.t[lane] = f32::from_bits(keep | (t[lane].to_bits() & closer[lane]));
            self.object[lane] = (self.object[lane] & !closer[lane]) | (index & closer[lane]);
            self.part[lane] = (self.part[lane] & !closer[lane]) | (part[lane] & closer[lane]);
        }
    }
}

/// `WaveHits::object` of a lane that hit nothing.
pub const NO_OBJECT: u32 = u32::MAX;

/// An object as the lanes read it: its kind and `M⁻¹` as the columns of an affine map.
#[derive(Clone, Copy, Debug)]
struct LaneObject {
    /// Its index among the scene's instances.
    index: u32,
    kind: ShapeKind,
    /// `object_from_world`'s x, y, z and w columns (three rows each).
    columns: [[f32; 3]; 4],
    casts_shadow: bool,
    /// Its world-space box, a little enlarged (`min`, `max`); `None` for an infinite
    /// plane.
    bounds: Option<([f32; 3], [f32; 3])>,
}

/// The kinds the lanes test, in the order [`FewObjects`] keeps them.
/// Infinite planes come last, as the instance BVH tests them after every bounded object:
/// where a plane and an object meet a ray at exactly the same distance (a cone's base
/// standing on the floor), the object wins, as it does there.
const LANE_KINDS: [ShapeKind; 7] = [
    ShapeKind::Rectangle,
    ShapeKind::Disk,
    ShapeKind::Sphere,
    ShapeKind::Cube,
    ShapeKind::Cylinder,
    ShapeKind::Cone,
    ShapeKind::Plane,
];

/// Where `kind` comes in [`LANE_KINDS`] (after them all if it is not one).
fn kind_rank(kind: ShapeKind) -> usize {
    LANE_KINDS.iter().position(|&k| k == kind).unwrap_or(LANE_KINDS.len())
}

/// The scene's objects, when there are few enough of kinds the lanes know, for
/// tracing waves of rays by testing each object once.
#[derive(Clone, Debug)]
pub struct FewObjects {
    /// The objects grouped by kind in the order of [`LANE_KINDS`], so each kind's test
    /// runs in a loop of its own, without a branch on the kind per object.
    objects: Vec<LaneObject>,
    /// Where each kind's group ends in `objects`.
    ends: [usize; LANE_KINDS.len()],
    /// Per instance, a plane's unit world normal, the same at every point of it: found
    /// once, a hit on the floor does not wait on normalizing it.
    plane_normals: [Option<Vec3>; MOST_OBJECTS],
}

impl FewObjects {
    /// The lanes' view of `scene`'s instances, or `None` when the scene has too many,
    /// a kind the lanes do not test (meshes, CSG, implicits, …) or motion.
    pub fn of(scene: &RenderScene) -> Option<FewObjects> {
        if scene.instances.len() > MOST_OBJECTS {
            return None;
        }
        let mut objects = scene
            .instances
            .iter()
            .enumerate()
            .map(|(index, inst)| lane_object(scene, index as u32, inst))
            .collect::<Option<Vec<_>>>()?;
        // Stable: within a kind the scene's order, as the BVH-free loop had it.
        objects.sort_by_key(|o| kind_rank(o.kind));
        let mut plane_normals = [None; MOST_OBJECTS];
        for (normal, inst) in plane_normals.iter_mut().zip(&scene.instances) {
            // As a hit anywhere on the plane would find it.
            *normal = (inst.shape.kind == ShapeKind::Plane)
                .then(|| crate::math::unit_or(inst.transform.normal_to_world(Vec3::Y), Vec3::Y));
        }
        Some(FewObjects::grouped(objects, plane_normals))
    }

    /// `objects`, already in the order of [`LANE_KINDS`], with each kind's group marked.
    fn grouped(objects: Vec<LaneObject>, plane_normals: [Option<Vec3>; MOST_OBJECTS]) -> FewObjects {
        let ends = std::array::from_fn(|k| objects.iter().take_while(|o| kind_rank(o.kind) <= k).count());
        FewObjects { objects, ends, plane_normals }
    }

    /// Instance `index`'s unit world normal if it is a plane, the same everywhere on it.
    #[inline(always)]
    pub(crate) fn plane_normal(&self, index: u32) -> Option<Vec3> {
        self.plane_normals.get(index as usize).copied().flatten()
    }

    /// The objects that rays from `eye` can meet in directions inside the pyramid whose
    /// edges are `corners` (in order around it), in the same order: a tile's camera rays
    /// need test no other. An object stays unless its box lies wholly outside one of the
    /// pyramid's sides, so the rays find exactly the hits they find among all objects;
    /// planes, which have no box, always stay. Most of a tile's camera rays then test
    /// one to three objects of a Whitted scene's seven.
    pub fn seen_from(&self, eye: Vec3, corners: [Vec3; 4]) -> FewObjects {
        let centre = corners.iter().sum::<Vec3>();
        // The four sides, facing in, and the plane through the eye across the pyramid,
        // facing forward where every edge points forward (as a tile's do). A box is
        // kept when each plane has one of its corners inside, not necessarily the same
        // corner: a large box behind the eye passes every side so, but not that plane.
        let sides: [Vec3; 5] = std::array::from_fn(|k| match k {
            4 if corners.iter().all(|c| c.dot(centre) > 0.0) => centre,
            4 => Vec3::ZERO,
            _ => {
                let side = corners[k].cross(corners[(k + 1) % 4]);
                if side.dot(centre) < 0.0 { -side } else { side }
            }
        });
        if !sides.iter().all(|side| side.is_finite()) {
            return self.clone();
        }
        let inside_every_side = |(min, max): ([f32; 3], [f32; 3])| {
            let corner =
                |k: usize| Vec3::new([min[0], max[0]][k & 1], [min[1], max[1]][(k >> 1) & 1], [min[2], max[2]][k >> 2]);
            // A degenerate side (zero) keeps everything: 0 ≥ 0.
            sides.iter().all(|side| (0..8).any(|k| side.dot(corner(k) - eye) >= 0.0))
        };
        let objects = self.objects.iter().filter(|o| o.bounds.is_none_or(inside_every_side)).copied().collect();
        FewObjects::grouped(objects, self.plane_normals)
    }

    /// The objects of kind `LANE_KINDS[k]`.
    #[inline(always)]
    fn group(&self, k: usize) -> &[LaneObject] {
        let start = if k == 0 { 0 } else { self.ends[k - 1] };
        &self.objects[start..self.ends[k]]
    }

    /// Each lane's `1/d` where some objects are [`LaneTest::BOXED`] (cubes, cylinders,
    /// cones), else nothing worth computing.
    #[inline(always)]
    fn inverse_dirs(&self, rays: &RayWave) -> [Lanes; 3] {
        let mut inv_dir = [[0.0; WAVE]; 3];
        if self.ends[5] > self.ends[2] {
            for axis in 0..3 {
                for lane in 0..WAVE {
                    inv_dir[axis][lane] = 1.0 / rays.dir[axis][lane];
                }
            }
        }
        inv_dir
    }

    /// Whether the scene has cylinders or cones.
    #[inline(always)]
    fn has_round_bodies(&self) -> bool {
        self.ends[5] > self.ends[3]
    }

    /// The nearest hit in `0 < t < t_max` of every lane of `rays`.
    ///
    /// Scenes without cylinders and cones take a copy without their tests: inlined into
    /// every wave, the larger code slowed the Cornell box's paths, which have none, by
    /// 5–7% (and the same tests called instead of inlined, by 18%).
    #[inline(always)]
    pub fn trace(&self, rays: &RayWave) -> WaveHits {
        crate::accel::lanes::on_avx2_or!(|_avx| self.trace_avx2(rays), self.trace_portable(rays))
    }

    /// [`FewObjects::trace`] compiled for AVX2, called once a wave rather than inlined
    /// into the renderer's loops, which it made larger and slower.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline(never)]
    fn trace_avx2(&self, rays: &RayWave) -> WaveHits {
        self.trace_portable(rays)
    }

    #[inline(always)]
    fn trace_portable(&self, rays: &RayWave) -> WaveHits {
        if self.has_round_bodies() { self.trace_kinds::<true>(rays) } else { self.trace_kinds::<false>(rays) }
    }

    /// [`FewObjects::trace`], testing cylinders and cones where `ROUND`.
    #[inline(always)]
    fn trace_kinds<const ROUND: bool>(&self, rays: &RayWave) -> WaveHits {
        let mut hits = WaveHits { t: rays.t_max, object: [NO_OBJECT; WAVE], part: [0; WAVE] };
        let inv_dir = self.inverse_dirs(rays);
        test_each::<Rectangle>(&inv_dir, self.group(0), rays, &mut hits);
        test_each::<Disk>(&inv_dir, self.group(1), rays, &mut hits);
        test_each::<Sphere>(&inv_dir, self.group(2), rays, &mut hits);
        test_each::<Cube>(&inv_dir, self.group(3), rays, &mut hits);
        if ROUND {
            test_each::<Cylinder>(&inv_dir, self.group(4), rays, &mut hits);
            test_each::<Cone>(&inv_dir, self.group(5), rays, &mut hits);
        }
        test_each::<Plane>(&inv_dir, self.group(6), rays, &mut hits);
        hits
    }
}

impl FewObjects {
    /// All ones in the lanes whose segment `0 < t < t_max` some object that casts
    /// shadows crosses: what [`FewObjects::trace`] tells of a wave of shadow rays, without
    /// finding the nearest hit (no narrowing of the segments, no bookkeeping of which
    /// object and part).
    #[inline(always)]
    pub fn blocked(&self, rays: &RayWave) -> [u32; WAVE] {
        crate::accel::lanes::on_avx2_or!(|_avx| self.blocked_avx2(rays), self.blocked_portable(rays))
    }

    /// [`FewObjects::blocked`] compiled for AVX2, called once a wave.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline(never)]
    fn blocked_avx2(&self, rays: &RayWave) -> [u32; WAVE] {
        self.blocked_portable(rays)
    }

    #[inline(always)]
    fn blocked_portable(&self, rays: &RayWave) -> [u32; WAVE] {
        if self.has_round_bodies() { self.blocked_kinds::<true>(rays) } else { self.blocked_kinds::<false>(rays) }
    }

    /// [`FewObjects::blocked`], testing cylinders and cones where `ROUND`.
    #[inline(always)]
    fn blocked_kinds<const ROUND: bool>(&self, rays: &RayWave) -> [u32; WAVE] {
        let mut blocked = [0; WAVE];
        let inv_dir = self.inverse_dirs(rays);
        block_each::<Rectangle>(&inv_dir, self.group(0), rays, &mut blocked);
        block_each::<Disk>(&inv_dir, self.group(1), rays, &mut blocked);
        block_each::<Sphere>(&inv_dir, self.group(2), rays, &mut blocked);
        block_each::<Cube>(&inv_dir, self.group(3), rays, &mut blocked);
        if ROUND {
            block_each::<Cylinder>(&inv_dir, self.group(4), rays, &mut blocked);
            block_each::<Cone>(&inv_dir, self.group(5), rays, &mut blocked);
        }
        block_each::<Plane>(&inv_dir, self.group(6), rays, &mut blocked);
        blocked
    }
}

/// Marks in `blocked` the lanes whose segments an object of `objects` (all of one
/// kind, `S`) that casts shadows crosses.
#[inline(always)]
fn block_each<S: LaneTest>(inv_dir: &[Lanes; 3], objects: &[LaneObject], rays: &RayWave, blocked: &mut [u32; WAVE]) {
    for object in objects.iter().filter(|o| o.casts_shadow) {
        if S::BOXED && !object.some_lane_enters(rays, inv_dir, &rays.t_max) {
            continue;
        }
        let (t, _) = S::lanes(&object.rays_in_object_space(rays), &rays.t_max);
        for lane in 0..WAVE {
            blocked[lane] |= 0u32.wrapping_sub(u32::from(t[lane] < f32::INFINITY));
        }
    }
}

/// Tests every object of `objects`, all of kind `S`, keeping the closer hits.
#[inline(always)]
fn test_each<S: LaneTest>(inv_dir: &[Lanes; 3], objects: &[LaneObject], rays: &RayWave, hits: &mut WaveHits) {
    for object in objects {
        let t_max = object.t_max_for(rays, hits);
        if S::BOXED && !object.some_lane_enters(rays, inv_dir, &t_max) {
            continue;
        }
        let (t, part) = S::lanes(&object.rays_in_object_space(rays), &t_max);
        hits.keep_closer(&t, &part, object.index);
    }
}

impl RenderScene {
    /// The world-space hit of `ray` that [`FewObjects::trace`] found for its lane: the
    /// same surface data [`RenderScene::intersect`] gives for it.
    #[inline(always)]
    pub fn few_objects_hit(&self, ray: &Ray, hits: &WaveHits, lane: usize) -> Option<Hit> {
        let index = hits.object[lane];
        if index == NO_OBJECT {
            return None;
        }
        let local = self.instances[index as usize].transform.ray_to_object(ray);
        let hit = ShapeHit { t: hits.t[lane], part: hits.part[lane] };
        let plane_normal = self.few_objects.as_ref().and_then(|few| few.plane_normal(index));
        // Only analytic instances are few objects.
        Some(self.hit_on_analytic_with_normal(ray, &local, index, hit, plane_normal))
    }

    /// [`RenderScene::few_objects_hit`] for the lighting equation, which reads the
    /// texture coordinates only to look up a texture: an untextured surface's hit is
    /// built from the shapes' own formulas, inlined, with its uv left at zero (a
    /// sphere's is an arc tangent and an arc sine).
    #[inline(always)]
    pub fn few_objects_hit_for_lighting(&self, ray: &Ray, hits: &WaveHits, lane: usize) -> Option<Hit> {
        let index = hits.object[lane];
        if index == NO_OBJECT {
            return None;
        }
        let inst = &self.instances[index as usize];
        let material = inst.material;
        if self.materials[material as usize].texture != crate::material::NO_TEXTURE {
            return self.few_objects_hit(ray, hits, lane);
        }
        let (point, normal) = self.few_objects_surface(ray, hits, lane);
        Some(Hit {
            t: hits.t[lane],
            point,
            normal,
            geometric_normal: normal,
            shadow_point: point,
            uv: glam::Vec2::ZERO,
            color: Vec3::ONE,
            material,
            instance: index,
            part: hits.part[lane],
        })
    }
}

impl RenderScene {
    /// The world-space point and unit normal of the hit [`FewObjects::trace`] found for
    /// `ray`'s lane `lane` (which hit something): those [`RenderScene::few_objects_hit`]
    /// gives, without the rest of a [`Hit`] (texture coordinates, the hit record: see
    /// [`Primitive::point_and_normal`]) and
    /// with each shape's formula inlined rather than reached through the shape
    /// dispatch.
    #[inline(always)]
    pub fn few_objects_surface(&self, ray: &Ray, hits: &WaveHits, lane: usize) -> (Vec3, Vec3) {
        let inst = &self.instances[hits.object[lane] as usize];
        // Few objects do not move: the instance's own transform is the one at any time.
        let xf = &inst.transform;
        let local = xf.ray_to_object(ray);
        let hit = ShapeHit { t: hits.t[lane], part: hits.part[lane] };
        let (point, normal) = match inst.shape.kind {
            ShapeKind::Rectangle => Rectangle.point_and_normal(&local, hit),
            ShapeKind::Disk => Disk.point_and_normal(&local, hit),
            ShapeKind::Plane => {
                let (point, normal) = Plane.point_and_normal(&local, hit);
                if let Some(unit) = self.few_objects.as_ref().and_then(|few| few.plane_normal(hits.object[lane])) {
                    return (xf.point_to_world(point), unit);
                }
                (point, normal)
            }
            ShapeKind::Sphere => Sphere.point_and_normal(&local, hit),
            ShapeKind::Cube => Cube.point_and_normal(&local, hit),
            ShapeKind::Cylinder => Cylinder.point_and_normal(&local, hit),
            ShapeKind::Cone => Cone.point_and_normal(&local, hit),
            _ => {
                let surface = inst.shape.surface_with(&self.shape_tables, &local, hit);
                (surface.point, surface.normal)
            }
        };
        (xf.point_to_world(point), crate::math::unit_or(xf.normal_to_world(normal), Vec3::Y))
    }
}

fn lane_object(scene: &RenderScene, index: u32, inst: &Instance) -> Option<LaneObject> {
    let supported = LANE_KINDS.contains(&inst.shape.kind);
    if !supported || inst.motion != NO_MOTION {
        return None;
    }
    let m = inst.transform.object_from_world;
    let column = |c: glam::Vec4| [c.x, c.y, c.z];
    let columns = [column(m.x_axis), column(m.y_axis), column(m.z_axis), column(m.w_axis)];
    let casts_shadow = !scene.casts_no_shadow(index);
    let bounds = inst.shape.bounds_with(&scene.shape_tables).transformed(&inst.transform.world_from_object);
    // Enlarged well past rounding, so no ray that meets the object misses its box: the
    // box only spares tests, it never decides a hit.
    let pad =
        Vec3::splat(1e-3 * (bounds.extent().max_element() + bounds.min.abs().max(bounds.max.abs()).max_element()));
    let bounds = bounds.is_finite().then(|| ((bounds.min - pad).to_array(), (bounds.max + pad).to_array()));
    Some(LaneObject { index, kind: inst.shape.kind, columns, casts_shadow, bounds })
}

/// A wave's rays in an object's space.
struct LocalWave {
    origin: [Lanes; 3],
    dir: [Lanes; 3],
}

impl LaneObject {
    /// Where each lane's search ends for this object: at the nearest hit so far, and
    /// before it for shadow rays when it casts no shadow (their segment ends there).
    #[inline(always)]
    fn t_max_for(&self, rays: &RayWave, hits: &WaveHits) -> Lanes {
        let mut t_max = hits.t;
        if !self.casts_shadow {
            for lane in 0..WAVE {
                t_max[lane] = f32::from_bits(t_max[lane].to_bits() & !rays.shadow[lane]);
            }
        }
        t_max
    }

    /// Whether some lane's segment `0 < t < t_max` passes through the object's box
    /// (`inv_dir`: each lane's `1/d`): where none does, the wave skips the object's own
    /// test (see [`LaneTest::BOXED`]). The slab test of
    /// [`crate::math::Aabb::hit_interval`] in lanes, the box's padding standing in for
    /// its widening of the far distances.
    #[inline(always)]
    fn some_lane_enters(&self, rays: &RayWave, inv_dir: &[Lanes; 3], t_max: &Lanes) -> bool {
        let Some((min, max)) = self.bounds else { return true };
        let mut enters = [0u32; WAVE];
        for lane in 0..WAVE {
            let (mut near, mut far) = (0.0f32, t_max[lane]);
            for axis in 0..3 {
                let (o, inv) = (rays.origin[axis][lane], inv_dir[axis][lane]);
                let (t0, t1) = ((min[axis] - o) * inv, (max[axis] - o) * inv);
                // min/max ignore the NaN of 0·∞ (an origin on a slab's plane).
                near = near.max(t0.min(t1));
                far = far.min(t0.max(t1));
            }
            enters[lane] = u32::from(near < far);
        }
        enters.iter().fold(0, |any, &e| any | e) != 0
    }

    /// `M⁻¹` applied to every ray as `Mat4::transform_point3` and `transform_vector3`
    /// apply it, sum for sum: `((x·p.x + y·p.y) + z·p.z) + w`.
    #[inline(always)]
    fn rays_in_object_space(&self, rays: &RayWave) -> LocalWave {
        let [x, y, z, w] = self.columns;
        let mut local = LocalWave { origin: [[0.0; WAVE]; 3], dir: [[0.0; WAVE]; 3] };
        let ([ox, oy, oz], [dx, dy, dz]) = (&rays.origin, &rays.dir);
        // One loop over the lanes computing all six rows: written as a loop over rows
        // around one over lanes, LLVM unrolled both and left every lane scalar.
        for lane in 0..WAVE {
            let (o, d) = ((ox[lane], oy[lane], oz[lane]), (dx[lane], dy[lane], dz[lane]));
            for row in 0..3 {
                local.origin[row][lane] = ((x[row] * o.0 + y[row] * o.1) + z[row] * o.2) + w[row];
                local.dir[row][lane] = (x[row] * d.0 + y[row] * d.1) + z[row] * d.2;
            }
        }
        local
    }
}

/// A shape's test in lanes. A trait rather than closures, so every test is inlined
/// into the wave's code, and compiled for AVX2 with it: passed as closures, the larger
/// tests were called instead, compiled without AVX2.
trait LaneTest {
    /// Whether a wave tests the object's box first: worth it where the shape's own test
    /// costs several slab tests (cube, cylinder, cone) and a wave's rays often all pass
    /// it by, as neighbouring camera rays and shadow rays to one light do. Flat shapes
    /// and spheres cost about a slab test: boxing them made the Cornell box's paths,
    /// whose walls nearly every wave meets, 14% slower.
    const BOXED: bool;
    /// The lanes' hits in `0 < t < t_max` (`f32::INFINITY` where a ray misses) and the
    /// parts hit.
    fn lanes(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]);
}

/// Implements [`LaneTest`] for shapes of one part by their lane function.
macro_rules! one_part_lane_test {
    ($($shape:ty => $test:ident),*) => {$(
        impl LaneTest for $shape {
            const BOXED: bool = false;

            #[inline(always)]
            fn lanes(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]) {
                ($test(ray, t_max), [0; WAVE])
            }
        }
    )*};
}
one_part_lane_test!(Rectangle => rectangle, Disk => disk, Plane => plane, Sphere => sphere);

/// Implements [`LaneTest`] for shapes of several parts by their lane function.
macro_rules! parts_lane_test {
    ($($shape:ty => $test:ident),*) => {$(
        impl LaneTest for $shape {
            const BOXED: bool = true;

            #[inline(always)]
            fn lanes(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]) {
                $test(ray, t_max)
            }
        }
    )*};
}
parts_lane_test!(Cube => cube, Cylinder => cylinder, Cone => cone);

/// The hits of the lanes on the plane `y = 0` of object space where `inside(x, z)`
/// holds of the point met: the test of [`crate::shape::Rectangle`],
/// [`crate::shape::Disk`] and [`crate::shape::Plane`], which differ only there;
/// `f32::INFINITY` where a ray misses. (Written without short-circuits, as every lane
/// test here, so the loop vectorizes.)
#[inline(always)]
fn flat(ray: &LocalWave, t_max: &Lanes, inside: impl Fn(f32, f32) -> bool) -> Lanes {
    let ([ox, oy, oz], [dx, dy, dz]) = (&ray.origin, &ray.dir);
    let mut out = [0.0; WAVE];
    for lane in 0..WAVE {
        let t = -oy[lane] / dy[lane];
        let (px, pz) = (ox[lane] + t * dx[lane], oz[lane] + t * dz[lane]);
        let hit = (t > 0.0) & (t < t_max[lane]) & inside(px, pz);
        out[lane] = if hit { t } else { f32::INFINITY };
    }
    out
}

/// [`crate::shape::Rectangle`]'s test in lanes: the square `|x|, |z| ≤ 1`.
#[inline(always)]
fn rectangle(ray: &LocalWave, t_max: &Lanes) -> Lanes {
    flat(ray, t_max, |x, z| (x.abs() <= 1.0) & (z.abs() <= 1.0))
}

/// [`crate::shape::Disk`]'s test in lanes: the unit disk.
#[inline(always)]
fn disk(ray: &LocalWave, t_max: &Lanes) -> Lanes {
    flat(ray, t_max, |x, z| x * x + z * z <= 1.0)
}

/// [`crate::shape::Plane`]'s test in lanes: all of it.
#[inline(always)]
fn plane(ray: &LocalWave, t_max: &Lanes) -> Lanes {
    flat(ray, t_max, |_, _| true)
}

/// [`crate::shape::Sphere`]'s test in lanes (from the line's point nearest the centre).
#[inline(always)]
fn sphere(ray: &LocalWave, t_max: &Lanes) -> Lanes {
    let ([ox, oy, oz], [dx, dy, dz]) = (&ray.origin, &ray.dir);
    let mut out = [0.0; WAVE];
    for lane in 0..WAVE {
        let (o, d) = ((ox[lane], oy[lane], oz[lane]), (dx[lane], dy[lane], dz[lane]));
        // Sums in glam's order, as the scalar test's dot products.
        let length_squared = (d.0 * d.0 + d.1 * d.1) + d.2 * d.2;
        let t0 = -((o.0 * d.0 + o.1 * d.1) + o.2 * d.2) / length_squared;
        let near = (o.0 + t0 * d.0, o.1 + t0 * d.1, o.2 + t0 * d.2);
        let discriminant = 1.0 - ((near.0 * near.0 + near.1 * near.1) + near.2 * near.2);
        let half_chord = (discriminant / length_squared).sqrt();
        let (t_in, t_out) = (t0 - half_chord, t0 + half_chord);
        let t = if (t_in > 0.0) & (t_in < t_max[lane]) { t_in } else { t_out };
        let hit = (discriminant >= 0.0) & (t > 0.0) & (t < t_max[lane]);
        out[lane] = if hit { t } else { f32::INFINITY };
    }
    out
}

/// [`crate::shape::Cube`]'s slab test in lanes, with the face hit (`2·axis`, +1 for the
/// +1 face) as its part.
#[inline(always)]
fn cube(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]) {
    let mut out = ([0.0; WAVE], [0; WAVE]);
    for lane in 0..WAVE {
        // Each lane's slabs in registers: values kept or replaced by selects, never by
        // conditional stores (which would compile to slow masked moves).
        let mut span = Span { near: f32::NEG_INFINITY, near_part: 0, far: f32::INFINITY, far_part: 0, outside: false };
        for axis in 0..3 {
            span.clip(ray.origin[axis][lane], ray.dir[axis][lane], axis as u32);
        }
        let Span { near, near_part, far, far_part, outside } = span;
        let near_counts = (near > 0.0) & (near < t_max[lane]);
        let t = if near_counts { near } else { far };
        let hit = !outside & (near <= far) & (t > 0.0) & (t < t_max[lane]);
        out.0[lane] = if hit { t } else { f32::INFINITY };
        out.1[lane] = if near_counts { near_part } else { far_part };
    }
    out
}

/// The nearer of a lane's hit so far (`best`, its part `best_part`) and a candidate
/// `t` on part `part` that counts where `valid`, as the scalar tests' `consider` keeps it:
/// ahead of the ray and nearer than `best` (which starts at the ray's `t_max`).
#[inline(always)]
fn consider(best: &mut f32, best_part: &mut u32, valid: bool, t: f32, part: u32) {
    let closer = valid & (t > 0.0) & (t < *best);
    *best = if closer { t } else { *best };
    *best_part = if closer { part } else { *best_part };
}

/// The first of two roots, in order, ahead of the ray, before `t_max` and accepted:
/// [`crate::shape`]'s `nearest_root` in lanes, `f32::INFINITY` for none.
#[inline(always)]
fn nearest_root(roots: [f32; 2], t_max: f32, accept: impl Fn(f32) -> bool) -> f32 {
    let counts = |t: f32| (t > 0.0) & (t < t_max) & accept(t);
    if counts(roots[0]) {
        roots[0]
    } else if counts(roots[1]) {
        roots[1]
    } else {
        f32::INFINITY
    }
}

/// [`crate::shape::Cylinder`]'s test in lanes: the body (part 0), then the caps at
/// `y = 1` (part 1) and `y = −1` (part 2), the nearest kept.
#[inline(always)]
fn cylinder(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]) {
    let ([ox, oy, oz], [dx, dy, dz]) = (&ray.origin, &ray.dir);
    let mut out = ([0.0; WAVE], [0; WAVE]);
    for lane in 0..WAVE {
        let (o, d) = ((ox[lane], oy[lane], oz[lane]), (dx[lane], dy[lane], dz[lane]));
        let (mut best, mut part) = (t_max[lane], 0);
        let a = d.0 * d.0 + d.2 * d.2;
        let t0 = -(o.0 * d.0 + o.2 * d.2) / a;
        let (cx, cz) = (o.0 + t0 * d.0, o.2 + t0 * d.2);
        let discriminant = 1.0 - (cx * cx + cz * cz);
        let h = (discriminant / a).sqrt();
        let body = nearest_root([t0 - h, t0 + h], t_max[lane], |t| (o.1 + t * d.1).abs() <= 1.0);
        consider(&mut best, &mut part, (a > 0.0) & (discriminant >= 0.0) & (body < f32::INFINITY), body, 0);
        for (y, cap) in [(1.0, 1), (-1.0, 2)] {
            let t = (y - o.1) / d.1;
            let (x, z) = (o.0 + t * d.0, o.2 + t * d.2);
            consider(&mut best, &mut part, (d.1 != 0.0) & (x * x + z * z <= 1.0), t, cap);
        }
        let hit = best < t_max[lane];
        out.0[lane] = if hit { best } else { f32::INFINITY };
        out.1[lane] = part;
    }
    out
}

/// [`crate::shape::Cone`]'s test in lanes: the lower nappe between base and apex (part 0),
/// from the line's point nearest the origin, then the base at `y = −1` (part 2).
#[inline(always)]
fn cone(ray: &LocalWave, t_max: &Lanes) -> (Lanes, [u32; WAVE]) {
    let ([ox, oy, oz], [dx, dy, dz]) = (&ray.origin, &ray.dir);
    let mut out = ([0.0; WAVE], [0; WAVE]);
    for lane in 0..WAVE {
        let (o, d) = ((ox[lane], oy[lane], oz[lane]), (dx[lane], dy[lane], dz[lane]));
        let (mut best, mut part) = (t_max[lane], 0);
        let t0 = -((o.0 * d.0 + o.1 * d.1) + o.2 * d.2) / ((d.0 * d.0 + d.1 * d.1) + d.2 * d.2);
        let near = (o.0 + d.0 * t0, o.1 + d.1 * t0, o.2 + d.2 * t0);
        // With Y = 1 − y: x² + z² − Y²/4 = 0.
        let (near_y, d_y) = (1.0 - near.1, -d.1);
        let a = d.0 * d.0 + d.2 * d.2 - 0.25 * d_y * d_y;
        let b = 2.0 * (near.0 * d.0 + near.2 * d.2 - 0.25 * near_y * d_y);
        let c = near.0 * near.0 + near.2 * near.2 - 0.25 * near_y * near_y;
        let (s0, s1, real) = quadratic_roots(a, b, c);
        let body = nearest_root([t0 + s0, t0 + s1], t_max[lane], |t| (-1.0..=1.0).contains(&(o.1 + d.1 * t)));
        consider(&mut best, &mut part, real & (body < f32::INFINITY), body, 0);
        let t = (-1.0 - o.1) / d.1;
        let (x, z) = (o.0 + d.0 * t, o.2 + d.2 * t);
        consider(&mut best, &mut part, (d.1 != 0.0) & (x * x + z * z <= 1.0), t, 2);
        let hit = best < t_max[lane];
        out.0[lane] = if hit { best } else { f32::INFINITY };
        out.1[lane] = part;
    }
    out
}

/// [`crate::math::roots::solve_quadratic`] without branches: the roots in order and
/// whether they are real. The discriminant is taken in `f64`, where `b²` and `4ac` of
/// `f32`s are exact, so its one rounding is the fused multiply-add's of the scalar solver.
#[inline(always)]
fn quadratic_roots(a: f32, b: f32, c: f32) -> (f32, f32, bool) {
    let discriminant = (b as f64) * (b as f64) + -4.0 * a as f64 * c as f64;
    let root = discriminant.sqrt() as f32;
    let q = -0.5 * (b + root.copysign(b));
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    // A linear equation where a = 0.
    let linear = -c / b;
    let flat = a == 0.0;
    let (t0, t1) = if flat { (linear, linear) } else { (t0, t1) };
    let real = if flat { b != 0.0 } else { discriminant >= 0.0 };
    (t0, t1, real)
}

/// A ray's extent inside the slabs seen so far, and the faces that bound it.
struct Span {
    near: f32,
    near_part: u32,
    far: f32,
    far_part: u32,
    outside: bool,
}

impl Span {
    /// Clips the span to the slab `|x_axis| ≤ 1` of a ray with origin `o` and direction
    /// `d` along that axis.
    #[inline(always)]
    fn clip(&mut self, o: f32, d: f32, axis: u32) {
        let inv = 1.0 / d;
        // A ray parallel to the slab is inside it everywhere or nowhere.
        let parallel = inv.is_infinite();
        self.outside |= parallel & (o.abs() > 1.0);
        let t_minus = (-1.0 - o) * inv;
        let t_plus = (1.0 - o) * inv;
        let minus_first = t_minus < t_plus;
        let (minus_part, plus_part) = (2 * axis, 2 * axis + 1);
        let t_in = if minus_first { t_minus } else { t_plus };
        let t_out = if minus_first { t_plus } else { t_minus };
        let in_part = if minus_first { minus_part } else { plus_part };
        let out_part = if minus_first { plus_part } else { minus_part };
        let enters = !parallel & (t_in > self.near);
        self.near = if enters { t_in } else { self.near };
        self.near_part = if enters { in_part } else { self.near_part };
        let leaves = !parallel & (t_out < self.far);
        self.far = if leaves { t_out } else { self.far };
        self.far_part = if leaves { out_part } else { self.far_part };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A box of rectangles with a cube, a sphere, a disk, a tilted plane, a tilted
    /// cylinder and cone inside, and a sphere whose material casts no shadow.
    fn scene() -> RenderScene {
        use crate::desc::{MaterialDesc, NodeDesc, NodeKind, SceneDesc, ShapeDesc, TransformOp};
        let rotate = |axis: Vec3, degrees: f32| TransformOp::Rotate { axis, degrees };
        let translate = TransformOp::Translate;
        let walls = [
            vec![translate(Vec3::new(0.0, -1.0, 0.0))],
            vec![rotate(Vec3::X, 180.0), translate(Vec3::new(0.0, 1.0, 0.0))],
            vec![rotate(Vec3::X, 90.0), translate(Vec3::new(0.0, 0.0, -1.0))],
            vec![rotate(Vec3::Z, -90.0), translate(Vec3::new(-1.0, 0.0, 0.0))],
            vec![rotate(Vec3::Z, 90.0), translate(Vec3::new(1.0, 0.0, 0.0))],
        ];
        let node = |shape, transform, material| NodeDesc {
            transform,
            kind: NodeKind::Shape { shape, material },
            origin: String::new(),
        };
        let mut objects: Vec<NodeDesc> = walls.into_iter().map(|t| node(ShapeDesc::Rectangle, t, 0)).collect();
        let cube = vec![
            TransformOp::Scale(Vec3::new(0.3, 0.6, 0.3)),
            rotate(Vec3::Y, 20.0),
            translate(Vec3::new(0.4, -0.4, -0.3)),
        ];
        objects.push(node(ShapeDesc::Cube, cube, 0));
        let sphere = vec![TransformOp::Scale(Vec3::splat(0.3)), translate(Vec3::new(-0.4, -0.7, 0.2))];
        objects.push(node(ShapeDesc::Sphere, sphere, 0));
        let hidden = vec![TransformOp::Scale(Vec3::splat(0.2)), translate(Vec3::new(0.0, 0.3, 0.0))];
        objects.push(node(ShapeDesc::Sphere, hidden, 1));
        let disk =
            vec![TransformOp::Scale(Vec3::splat(0.35)), rotate(Vec3::X, 30.0), translate(Vec3::new(-0.3, 0.5, -0.2))];
        objects.push(node(ShapeDesc::Disk, disk, 0));
        let plane = vec![rotate(Vec3::Z, 4.0), translate(Vec3::new(0.0, -0.85, 0.0))];
        objects.push(node(ShapeDesc::Plane, plane, 0));
        let cylinder = vec![
            TransformOp::Scale(Vec3::new(0.15, 0.3, 0.15)),
            rotate(Vec3::X, 40.0),
            translate(Vec3::new(0.5, 0.4, 0.4)),
        ];
        objects.push(node(ShapeDesc::Cylinder, cylinder, 0));
        let cone = vec![
            TransformOp::Scale(Vec3::new(0.25, 0.3, 0.25)),
            rotate(Vec3::Z, 30.0),
            translate(Vec3::new(-0.55, 0.0, -0.5)),
        ];
        objects.push(node(ShapeDesc::Cone, cone, 0));
        let shadowless = MaterialDesc { casts_shadows: false, ..MaterialDesc::default() };
        let desc = SceneDesc { materials: vec![MaterialDesc::default(), shadowless], objects, ..Default::default() };
        super::super::compile(&desc).expect("the test scene compiles")
    }

    fn rays() -> Vec<Ray> {
        let mut rng = crate::sampling::Rng::new(7);
        let mut next = || 2.0 * rng.next_f32() - 1.0;
        (0..4000)
            .map(|i| {
                let origin = if i % 4 == 0 { Vec3::new(0.0, 0.0, 3.5) } else { Vec3::new(next(), next(), next()) };
                // Some rays exactly along an axis, to test the slabs' parallel case.
                let dir = match i % 7 {
                    0 => Vec3::new(0.0, -1.0, 0.0),
                    1 => Vec3::new(0.0, 0.0, -1.0),
                    _ => Vec3::new(next(), next(), next()),
                };
                Ray::new(origin, dir)
            })
            .collect()
    }

    #[test]
    fn waves_find_the_hits_single_rays_find() {
        let scene = scene();
        let few = FewObjects::of(&scene)
            .expect("rectangles, a cube, spheres, a disk, a plane, a cylinder and a cone are few objects");
        let mut found_on = vec![false; scene.instances.len()];
        for chunk in rays().chunks(WAVE) {
            let mut wave = RayWave::default();
            for (lane, ray) in chunk.iter().enumerate() {
                wave.set(lane, ray, f32::INFINITY, false);
            }
            let hits = few.trace(&wave);
            for (lane, ray) in chunk.iter().enumerate() {
                let expected = scene.intersect(ray, f32::INFINITY);
                let found = scene.few_objects_hit(ray, &hits, lane);
                match (expected, found) {
                    (None, None) => {}
                    (Some(a), Some(b)) => {
                        found_on[b.instance as usize] = true;
                        assert_eq!(a.t, b.t, "ray {ray:?}");
                        // Only an exact tie may pick another object.
                        if a.instance != b.instance {
                            assert_eq!(a.t, b.t);
                        } else {
                            assert_eq!((a.point, a.normal, a.part), (b.point, b.normal, b.part), "ray {ray:?}");
                        }
                        // The lean surface diffuse lanes take is the whole hit's.
                        assert_eq!(scene.few_objects_surface(ray, &hits, lane), (b.point, b.normal), "ray {ray:?}");
                        // So is the lighting's hit, but for the uv of untextured surfaces.
                        let lit = scene.few_objects_hit_for_lighting(ray, &hits, lane).unwrap();
                        let geometry = |h: &Hit| (h.t, h.point, h.normal, h.geometric_normal, h.shadow_point);
                        let identity = |h: &Hit| (h.color, h.material, h.instance, h.part);
                        assert_eq!(geometry(&lit), geometry(&b), "ray {ray:?}");
                        assert_eq!(identity(&lit), identity(&b), "ray {ray:?}");
                    }
                    (a, b) => panic!("ray {ray:?}: single {a:?}, wave {b:?}"),
                }
            }
        }
        // Every object, of every kind, is the nearest hit of some ray.
        assert!(found_on.iter().all(|&found| found), "{found_on:?}");
    }

    #[test]
    fn rays_inside_a_pyramid_find_among_the_objects_seen_from_its_apex_the_hits_they_find_among_all() {
        let scene = scene();
        let few = FewObjects::of(&scene).unwrap();
        let eye = Vec3::new(0.1, 0.2, 3.5);
        let mut rng = crate::sampling::Rng::new(5);
        let (mut culled, mut hits_compared) = (0, 0);
        for _ in 0..300 {
            // A narrow pyramid towards a point of the box, its sides a few degrees apart.
            let mut next = || 2.0 * rng.next_f32() - 1.0;
            let centre = Vec3::new(next(), next(), next()) * 1.2 - eye;
            let (side, up) = (centre.cross(Vec3::Y).normalize() * 0.15, centre.cross(Vec3::X).normalize() * 0.15);
            let corners = [centre - side + up, centre + side + up, centre + side - up, centre - side - up];
            let seen = few.seen_from(eye, corners);
            culled += usize::from(seen.objects.len() < few.objects.len());
            for _ in 0..4 {
                // Eight rays inside the pyramid, its edges among them.
                let mut wave = RayWave::default();
                for lane in 0..WAVE {
                    let (a, b) = if lane == 0 { (0.0, 0.0) } else { (0.5 + 0.5 * next(), 0.5 + 0.5 * next()) };
                    let dir = corners[0].lerp(corners[1], a).lerp(corners[3].lerp(corners[2], a), b);
                    wave.set(lane, &Ray::new(eye, dir), f32::INFINITY, false);
                }
                let (all, among_seen) = (few.trace(&wave), seen.trace(&wave));
                assert_eq!((all.t, all.object, all.part), (among_seen.t, among_seen.object, among_seen.part));
                hits_compared += all.object.iter().filter(|&&o| o != NO_OBJECT).count();
            }
        }
        // The pyramids leave objects out, and their rays hit things, so both sides count.
        assert!(culled > 150 && hits_compared > 5000, "{culled} pyramids culled, {hits_compared} hits");
        // Looking away from everything, only the plane (unbounded) stays.
        let away = [
            Vec3::new(-0.1, 0.1, 1.0),
            Vec3::new(0.1, 0.1, 1.0),
            Vec3::new(0.1, -0.1, 1.0),
            Vec3::new(-0.1, -0.1, 1.0),
        ];
        let kinds: Vec<ShapeKind> = few.seen_from(eye, away).objects.iter().map(|o| o.kind).collect();
        assert_eq!(kinds, [ShapeKind::Plane]);
    }

    #[test]
    fn shadow_lanes_agree_with_occluded() {
        let scene = scene();
        let few = FewObjects::of(&scene).unwrap();
        let all = rays();
        let mut blocked_count = 0;
        for chunk in all.chunks(WAVE) {
            let mut wave = RayWave::default();
            for (lane, ray) in chunk.iter().enumerate() {
                wave.set(lane, ray, 0.5 + lane as f32 * 0.2, true);
            }
            let (hits, blocked_lanes) = (few.trace(&wave), few.blocked(&wave));
            for (lane, ray) in chunk.iter().enumerate() {
                let blocked = hits.object[lane] != NO_OBJECT;
                assert_eq!(blocked, scene.occluded(ray, wave.t_max[lane]), "ray {ray:?}");
                assert_eq!(blocked, blocked_lanes[lane] != 0, "ray {ray:?}");
                blocked_count += usize::from(blocked);
            }
        }
        // Both answers occur, so the test compares something.
        assert!(blocked_count > 100 && blocked_count < all.len() - 100, "{blocked_count}");
    }

    #[test]
    fn a_boxed_object_is_tested_by_every_wave_that_can_hit_it_and_skipped_by_those_that_cannot() {
        let scene = scene();
        let few = FewObjects::of(&scene).unwrap();
        let boxed = |kind| matches!(kind, ShapeKind::Cube | ShapeKind::Cylinder | ShapeKind::Cone);
        let (mut hit_count, mut skipped) = (0, 0);
        let mut rng = crate::sampling::Rng::new(11);
        let mut next = || 2.0 * rng.next_f32() - 1.0;
        for object in few.objects.iter().filter(|o| boxed(o.kind)) {
            let (min, max) = object.bounds.expect("bounded");
            let centre = (Vec3::from(min) + Vec3::from(max)) * 0.5;
            let extent = Vec3::from(max) - Vec3::from(min);
            let world_from_object = scene.instances[object.index as usize].transform.world_from_object;
            for _ in 0..3000 {
                // Aimed at the object's extremes (a cube's corners, the rims of caps and
                // bases, a cone's apex), where it touches its box, with the segment
                // ending just past the hit, as the nearest hit so far ends it in a wave.
                let (angle, up) = (std::f32::consts::PI * next(), next() > 0.0);
                let y = if up { 1.0 } else { -1.0 };
                let extreme = match object.kind {
                    ShapeKind::Cube => Vec3::new(next().signum(), y, next().signum()),
                    ShapeKind::Cone if up => Vec3::Y,
                    _ => Vec3::new(angle.cos(), y, angle.sin()),
                };
                let target = world_from_object.transform_point3(extreme * 0.9995);
                let origin = Vec3::new(next(), next(), next()) * 0.9;
                let ray = Ray::new(origin, target - origin);
                let local = scene.instances[object.index as usize].transform.ray_to_object(&ray);
                let shape = scene.instances[object.index as usize].shape;
                if let Some(hit) = shape.intersect_with(&scene.shape_tables, &local, f32::INFINITY) {
                    let mut wave = RayWave::default();
                    wave.set(0, &ray, hit.t * (1.0 + 1e-6), false);
                    let enters = object.some_lane_enters(&wave, &few.inverse_dirs(&wave), &wave.t_max);
                    assert!(enters, "ray {ray:?} meets object {} at {} outside its box", object.index, hit.t);
                    hit_count += 1;
                }
                // Eight rays from beyond the box, heading away: none can meet it.
                let away = centre + extent * 2.0 * Vec3::new(next(), next(), next()).normalize_or(Vec3::X);
                let mut wave = RayWave::default();
                for lane in 0..WAVE {
                    let dir = (away - centre) + Vec3::new(next(), next(), next()) * 0.1 * extent.length();
                    wave.set(lane, &Ray::new(away, dir), f32::INFINITY, lane % 2 == 0);
                }
                assert!(!object.some_lane_enters(&wave, &few.inverse_dirs(&wave), &wave.t_max));
                skipped += 1;
            }
        }
        // Both answers were asked for many times.
        assert!(hit_count > 1000 && skipped > 1000, "{hit_count} hits, {skipped} skipped");
    }

    #[test]
    fn a_lane_with_t_max_zero_finds_nothing() {
        let scene = scene();
        let few = FewObjects::of(&scene).unwrap();
        let mut wave = RayWave::default();
        let down = Ray::new(Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0));
        wave.set(3, &down, f32::INFINITY, false);
        let hits = few.trace(&wave);
        for lane in 0..WAVE {
            assert_eq!(hits.object[lane] == NO_OBJECT, lane != 3, "lane {lane}");
        }
        // Straight down onto the tilted plane just above the floor.
        assert_eq!(hits.t[3], scene.intersect(&down, f32::INFINITY).unwrap().t);
        assert!((hits.t[3] - 0.85).abs() < 1e-3, "{}", hits.t[3]);
    }
}
