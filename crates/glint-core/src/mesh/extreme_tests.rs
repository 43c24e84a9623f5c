//! Meshes at extreme scales and offsets, with needle, zero-area and shared-vertex
//! triangles: every traversal path (single rays and packets, portable lanes and AVX2)
//! finds the closest hit a brute-force loop over the triangles finds, and none panics.
//!
//! The reference is the triangle test itself, run on every triangle. Where f32 cannot
//! resolve a hit (corner products that underflow, a needle 1e8 times longer than the
//! ray's distance to it) the test can report a distance at which the ray is not even in
//! the triangle's bounding box; a BVH may rightly cull such a hit, so only hits inside
//! their triangle's box (up to rounding) are owed. Everywhere else that is every hit,
//! and the paths must find brute force's closest one.

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::triangle::{self, WatertightRay};
use super::*;
use crate::accel::lanes::Portable;

/// One triangle's hit by brute force: its distance, and whether the ray is in the
/// triangle's bounding box there.
#[derive(Clone, Copy, Debug)]
struct BruteHit {
    t: f32,
    in_box: bool,
}

/// Relative slack for "at the same distance": far above the rounding of a slab test.
const SLACK: f64 = 1e-5;

/// Every hit of `ray` in `(0, t_max)`, by brute force over the triangles of `desc` but
/// those whose corners are exactly collinear (which compile drops: no ray meets them,
/// though the rounding of the triangle test can report a hit on one).
fn brute_force(desc: &MeshDesc, ray: &Ray, t_max: f32) -> Vec<BruteHit> {
    let Some(w) = WatertightRay::new(ray) else { return vec![] };
    desc.indices
        .chunks_exact(3)
        .filter_map(|tri| {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(|i| desc.positions[i as usize]);
            let [a64, b64, c64] = [a, b, c].map(|p| p.as_dvec3());
            if (b64 - a64).cross(c64 - a64) == DVec3::ZERO {
                return None;
            }
            let t = triangle::intersect(&w, a, b, c, t_max)?.t;
            let t64 = f64::from(t);
            let in_box = box_interval(ray, a64.min(b64).min(c64), a64.max(b64).max(c64))
                .is_some_and(|(near, far)| near * (1.0 - SLACK) <= t64 && t64 <= far * (1.0 + SLACK));
            Some(BruteHit { t, in_box })
        })
        .collect()
}

/// Where the ray is inside the box `[lo, hi]`, in f64 (exact enough for f32 inputs),
/// `None` where it never is.
fn box_interval(ray: &Ray, lo: DVec3, hi: DVec3) -> Option<(f64, f64)> {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let (mut near, mut far) = (0.0f64, f64::INFINITY);
    for axis in 0..3 {
        if d[axis] == 0.0 {
            if o[axis] < lo[axis] || o[axis] > hi[axis] {
                return None;
            }
            continue;
        }
        let (t0, t1) = ((lo[axis] - o[axis]) / d[axis], (hi[axis] - o[axis]) / d[axis]);
        near = near.max(t0.min(t1));
        far = far.min(t0.max(t1));
    }
    (near <= far).then_some((near, far))
}

/// What one query path found for each ray of a packet: the closest hits, and the
/// mask of rays blocked.
#[derive(Debug, PartialEq)]
struct Found {
    closest: Vec<Option<ShapeHit>>,
    blocked: u32,
}

/// A packet query's hits, one slot per ray.
type PacketHits = [Option<ShapeHit>; PACKET];

/// Every query path on `rays` (a packet of at most eight): single rays and the packet,
/// on the portable lanes and, where the CPU has it, on AVX2.
fn every_path(mesh: &Mesh, rays: &[Ray], t_max: f32) -> Vec<(&'static str, Found)> {
    let all = (1u32 << rays.len()) - 1;
    let mask = |blocked: &mut dyn Iterator<Item = bool>| blocked.enumerate().fold(0, |m, (r, b)| m | u32::from(b) << r);
    let packet = |f: &dyn Fn(&mut [f32; PACKET], &mut PacketHits), blocked: u32| {
        let (mut t, mut hits) = ([t_max; PACKET], [None; PACKET]);
        f(&mut t, &mut hits);
        Found { closest: hits[..rays.len()].to_vec(), blocked }
    };
    let mut paths = vec![
        (
            "portable single",
            Found {
                closest: rays.iter().map(|r| mesh.intersect_on(Portable, r, t_max)).collect(),
                blocked: mask(&mut rays.iter().map(|r| mesh.occluded_on(Portable, r, t_max))),
            },
        ),
        (
            "portable packet",
            packet(
                &|t, h| mesh.intersect_packet_on(Portable, rays, all, t, h),
                mesh.occluded_packet_on(Portable, rays, t_max),
            ),
        ),
    ];
    #[cfg(target_arch = "x86_64")]
    if let Some(avx) = crate::accel::lanes::avx2_token_or_skip("mesh::extreme_tests (AVX2 against portable)") {
        // SAFETY (each block): the token says this CPU has AVX2.
        paths.push((
            "AVX2 single",
            Found {
                closest: rays.iter().map(|r| unsafe { mesh.intersect_avx2(avx, r, t_max) }).collect(),
                blocked: mask(&mut rays.iter().map(|r| unsafe { mesh.occluded_avx2(avx, r, t_max) })),
            },
        ));
        paths.push((
            "AVX2 packet",
            packet(&|t, h| unsafe { mesh.intersect_packet_avx2(avx, rays, all, t, h) }, unsafe {
                mesh.occluded_packet_avx2(avx, rays, t_max)
            }),
        ));
    }
    paths
}

/// Checks every path on `case`: a hit is in `(0, t_max)` and is the triangle test's
/// hit on the triangle it names, and no hit brute force finds inside its triangle's box
/// is closer; a ray is blocked only where brute force finds a hit, and is blocked
/// wherever it finds one inside its box; the AVX2 lanes find exactly what the portable
/// ones find.
fn check(case: &Case) -> Result<(), TestCaseError> {
    let Case { desc, rays, t_max } = case;
    let mesh = Mesh::compile(desc).map_err(|e| TestCaseError::fail(format!("compile: {e}")))?;
    let paths = every_path(&mesh, rays, *t_max);
    for (r, ray) in rays.iter().enumerate() {
        let brute = brute_force(desc, ray, *t_max);
        let owed = brute.iter().filter(|h| h.in_box).map(|h| h.t).min_by(f32::total_cmp);
        for (name, found) in &paths {
            let context = || format!("{name}, ray {r} {ray:?}: brute force {brute:?}");
            match found.closest[r] {
                Some(hit) => {
                    let [a, b, c] = mesh.vertices(hit.part as usize);
                    let own = WatertightRay::new(ray).and_then(|w| triangle::intersect(&w, a, b, c, *t_max));
                    prop_assert!(own.is_some_and(|h| h.t == hit.t), "{}: found {hit:?}", context());
                    let slack = f64::from(hit.t) * (1.0 - SLACK);
                    prop_assert!(owed.is_none_or(|t| f64::from(t) >= slack), "{}: found {hit:?}", context());
                }
                None => prop_assert!(owed.is_none(), "{}: found nothing", context()),
            }
            let blocked = found.blocked >> r & 1 == 1;
            prop_assert!(!blocked || !brute.is_empty(), "{}: blocked", context());
            prop_assert!(blocked || owed.is_none(), "{}: not blocked", context());
        }
    }
    // Single rays on both lanes, then packets on both lanes.
    for pair in [[0, 2], [1, 3]] {
        if let (Some(portable), Some(avx2)) = (paths.get(pair[0]), paths.get(pair[1])) {
            prop_assert_eq!(&portable.1, &avx2.1, "{} and {} differ", portable.0, avx2.0);
        }
    }
    Ok(())
}

/// What one generated triangle is.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// Three independent corners.
    Plain,
    /// One corner pulled far out (10 to 10⁸ times the mesh's scale) along an axis.
    Needle,
    /// Three collinear corners: no area.
    Collinear,
    /// A vertex used twice by the triangle: no area.
    Repeated,
    /// Two vertices shared with the triangle before it.
    Shared,
}

/// A mesh and a packet of rays aimed at its triangles, with a `t_max` for all of them.
#[derive(Clone, Debug)]
struct Case {
    desc: MeshDesc,
    rays: Vec<Ray>,
    t_max: f32,
}

/// Up to 24 triangles at scale `10^scale` around an offset of up to 1e30, and up to
/// eight rays, some axis-parallel, each aimed at a point of a triangle's plane (mostly
/// inside it, some just beyond an edge) from up to four times the scale away, direction
/// lengths `10^dir_scale`.
fn case(scale: std::ops::RangeInclusive<i32>, dir_scale: std::ops::RangeInclusive<i32>) -> impl Strategy<Value = Case> {
    let kind = prop_oneof![
        3 => Just(Kind::Plain),
        2 => Just(Kind::Needle),
        1 => Just(Kind::Collinear),
        1 => Just(Kind::Repeated),
        1 => Just(Kind::Shared),
    ];
    let triangles = prop::collection::vec((kind, prop::array::uniform9(-1.0f32..1.0), 0usize..3, 1.0f32..8.0), 1..24);
    let offset = prop_oneof![
        Just(Vec3::ZERO),
        (prop::array::uniform3(-1.0f32..1.0), 0i32..=30).prop_map(|(o, e)| Vec3::from(o) * 10f32.powi(e)),
    ];
    let ray = (
        any::<prop::sample::Index>(),
        (0.0f32..1.0, 0.0f32..1.0),
        prop::array::uniform3(-1.0f32..1.0),
        0u8..7,
        dir_scale,
        0.0f32..4.0,
    );
    let t_max = prop_oneof![3 => Just(None), 1 => (0.0f32..50.0).prop_map(Some)];
    (triangles, scale, offset, prop::collection::vec(ray, 1..=PACKET), t_max).prop_map(
        |(triangles, scale, offset, rays, t_max)| {
            let s = 10f32.powi(scale);
            let mut positions: Vec<Vec3> = Vec::new();
            let mut indices: Vec<u32> = Vec::new();
            for (kind, seed, axis, needle) in triangles {
                let corner = |k: usize| offset + s * Vec3::new(seed[3 * k], seed[3 * k + 1], seed[3 * k + 2]);
                let base = positions.len() as u32;
                let [a, b, c] = [corner(0), corner(1), corner(2)];
                match kind {
                    Kind::Plain => positions.extend([a, b, c]),
                    Kind::Needle => {
                        let mut far = a;
                        far[axis] += s * 10f32.powf(needle);
                        positions.extend([far, b, c]);
                    }
                    Kind::Collinear => positions.extend([a, b, a + (b - a) * 0.5]),
                    Kind::Repeated => {
                        positions.extend([a, b]);
                        indices.extend([base, base + 1, base]);
                        continue;
                    }
                    Kind::Shared if base >= 3 => {
                        positions.push(c);
                        indices.extend([base - 1, base - 2, base]);
                        continue;
                    }
                    Kind::Shared => positions.extend([a, b, c]),
                }
                indices.extend([base, base + 1, base + 2]);
            }
            let triangle_count = indices.len() / 3;
            let rays = rays
                .into_iter()
                .map(|(target, (b1, b2), dir, zeros, dir_scale, back)| {
                    let t = target.index(triangle_count);
                    let [p0, p1, p2] = [0, 1, 2].map(|k| positions[indices[3 * t + k] as usize]);
                    let p = p0 + b1 * (p1 - p0) + b2 * 1.2 * (1.0 - b1) * (p2 - p0);
                    let mut dir = Vec3::from(dir);
                    // Zero components (axis-parallel rays) where `zeros` has bits, never all three.
                    for axis in 0..3 {
                        if zeros >> axis & 1 == 1 {
                            dir[axis] = 0.0;
                        }
                    }
                    let dir = dir.normalize_or(Vec3::X);
                    // Subnormal components flushed to zero: the slab test takes 1/d = ±∞
                    // for them, as for zero, and so would miss a ray that crawls along.
                    let scaled =
                        (dir * 10f32.powi(dir_scale)).map(|x| if x.abs() < f32::MIN_POSITIVE { 0.0 } else { x });
                    Ray::new(p - back * s * dir, scaled)
                })
                .collect();
            let desc = MeshDesc { positions, indices, ..Default::default() };
            Case { desc, rays, t_max: t_max.map_or(f32::INFINITY, |t| t * s) }
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Scales where most hits are resolved (1e-10 to 1e12; past that products
    /// overflow and nothing is hit) and direction lengths from 0.01 to 100, over
    /// offsets up to 1e30, needles, zero-area triangles, shared vertices and
    /// axis-parallel rays.
    #[test]
    fn every_path_finds_the_closest_hit(case in case(-10..=12, -2..=2)) {
        check(&case)?;
    }

    /// Scales from 1e-30 to 1e30 and direction lengths from 1e-30 to 1e30 (object-space
    /// rays of extremely scaled instances).
    #[test]
    fn every_path_finds_the_closest_hit_at_any_scale(case in case(-30..=30, -30..=30)) {
        check(&case)?;
    }
}

/// The OBJ: one triangle with a corner at x = 2e7, the others near 1.
#[test]
fn needle_triangle_is_found_on_every_path() {
    let corners = [Vec3::new(2e7, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 1.0)];
    let desc = MeshDesc { positions: corners.to_vec(), indices: vec![0, 1, 2], ..Default::default() };
    // Points on the needle's midline near the base, halfway and near the tip, seen from
    // beside it and obliquely.
    let on_needle = |b0: f32| corners[0] * b0 + (corners[1] + corners[2]) * 0.5 * (1.0 - b0);
    let mut rays = Vec::new();
    for p in [1e-7, 0.5, 0.999].map(on_needle) {
        rays.push(Ray::new(p + Vec3::new(0.0, 2.0, 2.0), Vec3::new(0.0, -1.0, -1.0)));
        rays.push(Ray::new(p + Vec3::new(-5.0, 3.0, 4.0), Vec3::new(5.0, -3.0, -4.0)));
    }
    // Down onto the base edge (which this side owns), in the plane x = 1 of the
    // needle's lowest x: the box test once took the −0 x direction for a tiny negative
    // one, which leaves that plane at t = 0, and missed the box.
    rays.push(Ray::new(Vec3::new(1.0, 0.5, 5.0), Vec3::new(-0.0, 0.0, -1.0)));
    // All hit inside the triangle's box but one: near the tip, where a step of x is 2,
    // the oblique ray's hit is not resolved in f32 (the paths must still agree).
    for (r, ray) in rays.iter().enumerate().filter(|&(r, _)| r != 5) {
        let brute = brute_force(&desc, ray, f32::INFINITY);
        assert!(!brute.is_empty() && brute.iter().all(|h| h.in_box), "ray {r} {ray:?} hits the needle: {brute:?}");
    }
    check(&Case { desc, rays, t_max: f32::INFINITY }).unwrap();
}
