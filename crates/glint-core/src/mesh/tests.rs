use glam::{Mat3, Vec3};
use proptest::prelude::*;

use super::triangle::{self, WatertightRay};
use super::*;

/// An n×n grid of unit quads, each split along alternating diagonals, bent out of the
/// z = 0 plane by `tilt` so the triangles are not axis-aligned.
fn grid(n: u32, tilt: Mat3) -> MeshDesc {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(tilt * Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            if (i + j) % 2 == 0 {
                indices.extend([a, b, c, a, c, d]);
            } else {
                indices.extend([a, b, d, b, c, d]);
            }
        }
    }
    MeshDesc { positions, indices, ..Default::default() }
}

/// How many triangles of `desc` the ray hits, by brute force.
fn hit_count(desc: &MeshDesc, origin: Vec3, dir: Vec3) -> usize {
    let w = WatertightRay::new(&Ray::new(origin, dir)).unwrap();
    desc.indices
        .chunks_exact(3)
        .filter(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| desc.positions[i as usize]);
            triangle::intersect(&w, a, b, c, f32::INFINITY).is_some()
        })
        .count()
}

#[test]
fn shared_edges_and_vertices_are_hit_exactly_once() {
    let n = 6;
    let tilts = [
        Mat3::IDENTITY,
        Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7)
            * Mat3::from_diagonal(Vec3::new(0.3, 1.7, 1.0)),
    ];
    let dirs = [Vec3::NEG_Z, Vec3::new(0.3, -0.2, -1.0), Vec3::new(-0.71, 0.05, -0.4), Vec3::new(0.1, 0.9, -0.33)];
    for tilt in tilts {
        let desc = grid(n, tilt);
        let mesh = Mesh::compile(&desc).unwrap();
        let normal = tilt * Vec3::Z;
        // Interior vertices and the midpoints of interior edges (axis-aligned ones and
        // both diagonal directions).
        let mut targets = Vec::new();
        for j in 1..n {
            for i in 1..n {
                let (x, y) = (i as f32, j as f32);
                targets.extend([(x, y), (x + 0.5, y), (x, y + 0.5), (x - 0.5, y - 0.5), (x + 0.5, y - 0.5)]);
            }
        }
        for (x, y) in targets {
            let p = tilt * Vec3::new(x, y, 0.0);
            for dir in dirs {
                let d = tilt * dir;
                // Through p from either side of the plane.
                for d in [d, -d] {
                    let origin = p - 7.0 * d;
                    if d.dot(normal).abs() < 1e-3 {
                        continue;
                    }
                    assert_eq!(hit_count(&desc, origin, d), 1, "target ({x}, {y}), dir {d}, tilt {tilt}");
                    // The BVH finds it too, with nothing culled at the box boundaries.
                    let hit = mesh.intersect(&Ray::new(origin, d), f32::INFINITY);
                    assert!(hit.is_some_and(|h| (h.t - 7.0).abs() < 1e-3), "BVH at ({x}, {y}), dir {d}");
                    assert!(mesh.occluded(&Ray::new(origin, d), f32::INFINITY), "any hit at ({x}, {y}), dir {d}");
                }
            }
        }
    }
}

#[test]
fn compile_rejects_bad_meshes_and_drops_degenerate_triangles() {
    let base = MeshDesc { positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y], indices: vec![0, 1, 2], ..Default::default() };
    assert!(Mesh::compile(&base).is_ok());
    let out_of_range = MeshDesc { indices: vec![0, 1, 3], ..base.clone() };
    assert!(matches!(Mesh::compile(&out_of_range), Err(MeshError::IndexOutOfRange { index: 3, .. })));
    let nan = MeshDesc { positions: vec![Vec3::ZERO, Vec3::X, Vec3::NAN], ..base.clone() };
    assert_eq!(Mesh::compile(&nan), Err(MeshError::NonFinite(2)));
    let ragged = MeshDesc { indices: vec![0, 1], ..base.clone() };
    assert_eq!(Mesh::compile(&ragged), Err(MeshError::Ragged(2)));
    let normals = MeshDesc { normals: vec![Vec3::Z], ..base.clone() };
    assert!(matches!(Mesh::compile(&normals), Err(MeshError::AttributeCount { .. })));
    // Small is not degenerate: 1e-12 across, the squared length of the f32 cross
    // product underflows, but the triangle has area and rays hit it.
    let tiny = MeshDesc { positions: base.positions.iter().map(|p| *p * 1e-12).collect(), ..base.clone() };
    let mesh = Mesh::compile(&tiny).unwrap();
    assert_eq!((mesh.triangles.len(), mesh.degenerate), (1, 0));
    let ray = Ray::new(Vec3::new(0.25, 0.25, 1.0) * 1e-12, Vec3::NEG_Z);
    assert!(mesh.intersect(&ray, f32::INFINITY).is_some_and(|h| (h.t - 1e-12).abs() < 1e-18));
    let degenerate = MeshDesc { indices: vec![0, 1, 2, 0, 0, 1, 1, 1, 1], ..base };
    let mesh = Mesh::compile(&degenerate).unwrap();
    assert_eq!((mesh.triangles.len(), mesh.degenerate), (1, 2));
}

/// Validation runs in parallel over big meshes; it must still report the first bad
/// triangle and vertex, and drop exactly the triangles a serial pass drops. (That the
/// kept ones stay in their order, `examples/mesh_build.rs`'s fingerprints show.)
#[test]
fn validation_of_a_big_mesh_reports_the_first_fault() {
    let n = 200_000u32;
    let positions: Vec<Vec3> = (0..n + 2).map(|i| Vec3::new(i as f32, (i % 7) as f32, (i % 3) as f32)).collect();
    let indices: Vec<u32> = (0..n).flat_map(|i| [i, i + 1, i + 2]).collect();
    let good = MeshDesc { positions, indices, ..Default::default() };
    let mut bad = good.clone();
    for (triangle, corner) in [(150_001usize, 2usize), (90_000, 1), (120_000, 0)] {
        bad.indices[3 * triangle + corner] = n + 2 + triangle as u32;
    }
    let expected = MeshError::IndexOutOfRange { triangle: 90_000, index: n + 2 + 90_000, count: n as usize + 2 };
    assert_eq!(Mesh::compile(&bad), Err(expected));
    let mut nan = good.clone();
    for i in [170_000, 60_000, 60_001] {
        nan.positions[i].y = f32::NAN;
    }
    assert_eq!(Mesh::compile(&nan), Err(MeshError::NonFinite(60_000)));
    // Triangles with a repeated corner are dropped, as one serial pass finds them.
    let mut flat = good.clone();
    for t in (0..n as usize).step_by(5) {
        flat.indices[3 * t + 2] = flat.indices[3 * t];
    }
    let corners = |t: &[u32]| [t[0], t[1], t[2]].map(|i| flat.positions[i as usize]);
    let kept = flat.indices.chunks(3).filter(|t| super::has_area(corners(t)[0], corners(t)[1], corners(t)[2])).count();
    assert!(kept <= (n - n.div_ceil(5)) as usize);
    let mesh = Mesh::compile(&flat).unwrap();
    assert_eq!((mesh.triangles.len(), mesh.degenerate), (kept, n as usize - kept));
}

#[test]
fn shading_normal_and_uv_are_interpolated() {
    let desc = MeshDesc {
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: vec![Vec3::Z, Vec3::new(1.0, 0.0, 1.0), Vec3::Z],
        uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
        indices: vec![0, 1, 2],
        ..Default::default()
    };
    let mesh = Mesh::compile(&desc).unwrap();
    let ray = Ray::new(Vec3::new(0.5, 0.25, 1.0), Vec3::NEG_Z);
    let hit = mesh.intersect(&ray, f32::INFINITY).unwrap();
    let MeshSurface { surface, geometric, shadow_point, .. } = mesh.surface(&ray, hit);
    // A flat triangle whose normals lean outward: the shadow point rises above it.
    assert!(shadow_point.z > 0.0 && (shadow_point.truncate() - surface.point.truncate()).length() < 0.2);
    assert!((hit.t - 1.0).abs() < 1e-6);
    assert!((surface.point - Vec3::new(0.5, 0.25, 0.0)).length() < 1e-6);
    assert!((surface.uv - Vec2::new(0.5, 0.25)).length() < 1e-6);
    assert!((surface.normal - Vec3::new(0.5, 0.0, 1.0)).length() < 1e-6);
    assert!(geometric.normalize().abs_diff_eq(Vec3::Z, 1e-6));
}

fn soup(seeds: &[[f32; 9]]) -> MeshDesc {
    let positions: Vec<Vec3> =
        seeds.iter().flat_map(|s| [0, 3, 6].map(|k| Vec3::new(s[k], s[k + 1], s[k + 2]))).collect();
    let indices = (0..positions.len() as u32).collect();
    MeshDesc { positions, indices, ..Default::default() }
}

proptest! {
    #[test]
    fn bvh_traversal_equals_brute_force(
        seeds in prop::collection::vec(prop::array::uniform9(-5.0f32..5.0), 1..120),
        origin in prop::array::uniform3(-8.0f32..8.0),
        dir in prop::array::uniform3(-1.0f32..1.0),
        t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..20.0],
    ) {
        let dir = Vec3::from(dir);
        prop_assume!(dir.length() > 1e-3);
        let ray = Ray::new(Vec3::from(origin), dir);
        let desc = soup(&seeds);
        let mesh = Mesh::compile(&desc).unwrap();
        let w = WatertightRay::new(&ray).unwrap();
        let brute = desc.indices.chunks_exact(3).filter_map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| desc.positions[i as usize]);
            triangle::intersect(&w, a, b, c, t_max).map(|h| h.t)
        }).min_by(f32::total_cmp);
        // The dispatched path (AVX2 where the CPU has it) and, where that is another
        // path, the portable one.
        let found = mesh.intersect(&ray, t_max).map(|h| h.t);
        prop_assert_eq!(brute, found);
        prop_assert_eq!(brute.is_some(), mesh.occluded(&ray, t_max));
        if crate::accel::lanes::avx2_or_skip("mesh::tests (portable against brute force)") {
            let portable = mesh.intersect_on(crate::accel::lanes::Portable, &ray, t_max).map(|h| h.t);
            prop_assert_eq!(brute, portable);
            prop_assert_eq!(brute.is_some(), mesh.occluded_on(crate::accel::lanes::Portable, &ray, t_max));
        }
    }
}

proptest! {
    /// A packet finds, ray by ray, the hit (distance and triangle) and the occlusion the
    /// single-ray queries find, on the dispatched and the portable paths, for packets of
    /// any size whose rays share an origin and fan out a little (as camera rays do) or
    /// not at all (some rays point elsewhere).
    #[test]
    fn packet_equals_single_rays(
        seeds in prop::collection::vec(prop::array::uniform9(-5.0f32..5.0), 1..300),
        origin in prop::array::uniform3(-8.0f32..8.0),
        dir in prop::array::uniform3(-1.0f32..1.0),
        spread in prop::collection::vec(prop::array::uniform3(-0.3f32..0.3), 1..=8),
        t_max in prop_oneof![Just(f32::INFINITY), 0.5f32..20.0],
    ) {
        let mesh = Mesh::compile(&soup(&seeds)).unwrap();
        let rays: Vec<Ray> = spread.iter().enumerate().map(|(i, s)| {
            let d = if i == 5 { Vec3::from(*s) } else { Vec3::from(dir) + Vec3::from(*s) };
            Ray::new(Vec3::from(origin), d)
        }).collect();
        let single: Vec<_> = rays.iter().map(|r| mesh.intersect(r, t_max)).collect();
        let blocked = rays.iter().enumerate().fold(0u32, |m, (i, r)| m | u32::from(mesh.occluded(r, t_max)) << i);
        let all = (1 << rays.len()) - 1;
        let mut hits = [None; PACKET];
        mesh.intersect_packet(&rays, all, &mut [t_max; PACKET], &mut hits);
        prop_assert_eq!(&single[..], &hits[..rays.len()]);
        prop_assert_eq!(blocked, mesh.occluded_packet(&rays, t_max));
        let mut hits = [None; PACKET];
        mesh.intersect_packet_on(crate::accel::lanes::Portable, &rays, all, &mut [t_max; PACKET], &mut hits);
        prop_assert_eq!(&single[..], &hits[..rays.len()]);
        // Rays outside the mask are left alone.
        let mut hits = [None; PACKET];
        let mut t = [t_max; PACKET];
        mesh.intersect_packet(&rays, all & 0b1010_1010, &mut t, &mut hits);
        for (i, hit) in hits.iter().enumerate().take(rays.len()) {
            let expected = if i % 2 == 1 { single[i] } else { None };
            prop_assert_eq!(*hit, expected);
            prop_assert_eq!(t[i], expected.map_or(t_max, |h| h.t));
        }
        prop_assert_eq!(blocked, mesh.occluded_packet_on(crate::accel::lanes::Portable, &rays, t_max));
    }
}
