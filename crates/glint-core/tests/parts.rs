//! A render cut into parts merges to the single render's image, bit for bit, for any
//! number of parts, any filter and either integrator; a set of parts with one missing,
//! one twice or from another render is refused.

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::{Part, PartError, PartialFilm, merge_parts, render, render_part, tile_count};
use glint_core::scene::{RenderScene, compile};

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// A mirror sphere and a box on a plane, 50×37 (ragged tiles at the edges).
fn scene(integrator: IntegratorDesc, filter: FilterDesc, adaptive: Option<AdaptiveDesc>) -> RenderScene {
    let mirror = MaterialDesc { diffuse: Vec3::splat(0.05), reflective: Some(Vec3::splat(0.8)), ..Default::default() };
    let desc = SceneDesc {
        settings: RenderSettings {
            width: 50,
            height: 37,
            filter,
            integrator,
            adaptive,
            spp: Some(3),
            ..Default::default()
        },
        camera: CameraDesc { eye: Vec3::new(0.5, 1.5, 6.0), look: Vec3::NEG_Z, up: Vec3::Y, ..Default::default() },
        lights: vec![LightDesc::Point { position: Vec3::new(-2.0, 5.0, 4.0), color: Vec3::ONE, attenuation: Vec3::X }],
        materials: vec![MaterialDesc { diffuse: Vec3::new(0.3, 0.6, 0.4), ..Default::default() }, mirror],
        textures: vec![],
        objects: vec![
            node(ShapeDesc::Plane, 0, vec![TransformOp::Translate(Vec3::new(0.0, -1.0, 0.0))]),
            node(ShapeDesc::Sphere, 1, vec![TransformOp::Translate(Vec3::new(-1.0, 0.0, 0.0))]),
            node(
                ShapeDesc::Cube,
                0,
                vec![TransformOp::Scale(Vec3::splat(0.6)), TransformOp::Translate(Vec3::new(1.3, -0.4, 0.5))],
            ),
        ],
        meshes: vec![],
        views: vec![],
    };
    compile(&desc).expect("valid scene")
}

fn parts(scene: &RenderScene, count: u32) -> Vec<PartialFilm> {
    (0..count)
        .map(|i| {
            let part = Part::new(i, count, scene).expect("a part");
            render_part(scene, part, &|_, _| {}, &AtomicBool::new(false)).expect("renders")
        })
        .collect()
}

fn bits(image: &Image) -> Vec<u32> {
    image.pixels.iter().flat_map(|p| p.to_array()).map(f32::to_bits).collect()
}

#[test]
fn merged_parts_are_the_single_render_bit_for_bit() {
    let gaussian = FilterDesc { kind: FilterKind::Gaussian, radius: 1.5 };
    let lanczos = FilterDesc { kind: FilterKind::Lanczos, radius: 3.0 };
    let adaptive = Some(AdaptiveDesc { min_samples: 2, max_samples: 8, threshold: 0.02 });
    let cases = [
        ("whitted box", IntegratorDesc::Whitted, FilterDesc::default(), None),
        ("whitted gaussian", IntegratorDesc::Whitted, gaussian, None),
        ("path lanczos", IntegratorDesc::Path(PathDesc::default()), lanczos, None),
        ("adaptive gaussian", IntegratorDesc::Whitted, gaussian, adaptive),
    ];
    for (name, integrator, filter, adaptive) in cases {
        let scene = scene(integrator, filter, adaptive);
        let (whole, stats) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
        for count in [1, 2, 3, 5, tile_count(&scene)] {
            let mut cut = parts(&scene, count);
            cut.reverse(); // any order
            let (merged, merged_stats) = merge_parts(&cut).expect("merges");
            assert!(bits(&merged) == bits(&whole), "{name}: {count} parts differ from the single render");
            assert_eq!(merged_stats.samples_per_pixel, stats.samples_per_pixel, "{name}: {count} parts");
            assert_eq!(merged_stats.rays, stats.rays, "{name}: {count} parts");
        }
    }
}

#[test]
fn a_part_traces_only_its_tiles() {
    let scene = scene(IntegratorDesc::Whitted, FilterDesc::default(), None);
    let cut = parts(&scene, 4);
    let traced: u64 = cut.iter().map(|p| p.rays).sum();
    let (_, stats) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    assert_eq!(traced, stats.rays);
    for p in &cut {
        assert!(
            p.rays > 0 && p.rays < stats.rays / 2,
            "part {} traced {} of {} rays",
            p.part.index,
            p.rays,
            stats.rays
        );
        let preview = p.preview();
        let lit = preview.pixels.iter().filter(|c| c.max_element() > 0.0).count();
        assert!(lit < preview.pixels.len() / 2, "part {}'s own pixels cover {lit}", p.part.index);
    }
}

#[test]
fn incomplete_or_foreign_sets_of_parts_are_refused() {
    let scene = scene(IntegratorDesc::Whitted, FilterDesc::default(), None);
    let cut = parts(&scene, 3);
    assert_eq!(merge_parts(&cut[..2]).err(), Some(PartError::Missing { index: 2, count: 3 }));
    let twice = [cut[0].clone(), cut[1].clone(), cut[1].clone()];
    assert_eq!(merge_parts(&twice).err(), Some(PartError::Twice { index: 1, count: 3 }));
    let mut other = cut.clone();
    other[2] = parts(&scene, 4).pop().unwrap();
    assert!(matches!(merge_parts(&other), Err(PartError::Mismatch(_))));
    assert_eq!(Part::new(3, 3, &scene).err(), Some(PartError::NoSuchPart { index: 3, count: 3 }));
    let tiles = tile_count(&scene);
    assert_eq!(Part::new(0, tiles + 1, &scene).err(), Some(PartError::TooManyParts { count: tiles + 1, tiles }));
}
