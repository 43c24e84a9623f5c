//! Distribution effects and adaptive sampling, measured on rendered images.

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::{RenderStats, render};
use glint_core::scene::compile;

fn run(desc: &SceneDesc) -> (Image, RenderStats) {
    render(&compile(desc).unwrap(), &|_, _| {}, &AtomicBool::new(false)).unwrap()
}

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

fn matte(color: Vec3) -> MaterialDesc {
    MaterialDesc { diffuse: color, ambient: Some(Vec3::ZERO), specular: Vec3::ZERO, ..Default::default() }
}

/// A white floor seen from above, a small black square hovering over it (optional),
/// lit by a square area light of side `light_size` straight above.
fn shadow_scene(light_size: f32, occluder: bool) -> SceneDesc {
    let half = 0.5 * light_size;
    let mut objects = vec![node(ShapeDesc::Plane, 0, vec![])];
    if occluder {
        let square =
            vec![TransformOp::Scale(Vec3::new(0.8, 0.02, 0.8)), TransformOp::Translate(Vec3::new(0.0, 3.0, 0.0))];
        objects.push(node(ShapeDesc::Cube, 1, square));
    }
    SceneDesc {
        meshes: vec![],
        settings: RenderSettings { width: 96, height: 96, ambient_light: Vec3::ZERO, ..Default::default() },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 10.0, 0.0),
            look: Vec3::NEG_Y,
            up: Vec3::NEG_Z,
            fov_y_degrees: 40.0,
            ..Default::default()
        },
        lights: vec![LightDesc::Area {
            shape: AreaShape::Rectangle {
                corner: Vec3::new(-half, 6.0, -half),
                edge_u: light_size * Vec3::X,
                edge_v: light_size * Vec3::Z,
            },
            color: Vec3::ONE,
            attenuation: Vec3::X,
            samples: 8,
        }],
        materials: vec![matte(Vec3::ONE), matte(Vec3::ZERO)],
        textures: vec![],
        objects,
        views: vec![],
    }
}

/// Pixels along the middle row where the floor is neither fully lit nor fully dark,
/// relative to the same view without the occluder: the penumbra's width (both sides).
fn penumbra_width(light_size: f32) -> usize {
    let (shadowed, _) = run(&shadow_scene(light_size, true));
    let (open, _) = run(&shadow_scene(light_size, false));
    let y = shadowed.height / 2;
    (0..shadowed.width)
        .map(|x| shadowed.get(x, y).x / open.get(x, y).x)
        .filter(|ratio| (0.05..0.95).contains(ratio))
        .count()
}

#[test]
fn penumbra_width_grows_with_light_size() {
    let widths: Vec<usize> = [0.05, 1.0, 2.5].iter().map(|&s| penumbra_width(s)).collect();
    assert!(widths[0] <= 4, "a nearly point light casts a nearly hard shadow: {widths:?}");
    assert!(widths[1] > widths[0] + 6 && widths[2] > widths[1] + 6, "{widths:?}");
}

/// A checkered plane face-on at distance 10, with the camera focused at 5.
fn defocus_scene(aperture: f32) -> SceneDesc {
    SceneDesc {
        meshes: vec![],
        settings: RenderSettings {
            width: 64,
            height: 64,
            samples_per_axis: 6,
            pattern: SamplePattern::Jittered,
            ambient_light: Vec3::ZERO,
            ..Default::default()
        },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 0.0, 10.0),
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 20.0,
            fov_axis: glint_core::desc::FovAxis::Y,
            aperture_radius: aperture,
            focal_distance: 5.0,
        },
        lights: vec![LightDesc::Directional { direction: Vec3::NEG_Z, color: Vec3::ONE }],
        materials: vec![MaterialDesc { texture: Some(0), blend: 1.0, ..matte(Vec3::ONE) }],
        textures: vec![TextureDesc::Checker {
            name: "c".into(),
            even: Vec3::ONE,
            odd: Vec3::ZERO,
            cells: glam::Vec2::splat(1.0),
            filtered: false,
        }],
        objects: vec![node(ShapeDesc::Plane, 0, vec![TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 }])],
        views: vec![],
    }
}

/// Columns where the checker's edges are in transition (neither clearly black nor
/// clearly white) in a row profile averaged over a band of rows inside one row of
/// cells, so sampling noise averages out: the width of the blur.
fn blur_width(image: &Image) -> usize {
    let rows = 36..48;
    let n = rows.len() as f32;
    (0..image.width)
        .map(|x| rows.clone().map(|y| image.get(x, y).x).sum::<f32>() / n)
        .filter(|v| (0.1..0.9).contains(v))
        .count()
}

#[test]
fn defocus_blur_grows_with_aperture() {
    let w: Vec<usize> = [0.0, 0.2, 0.6].iter().map(|&a| blur_width(&run(&defocus_scene(a)).0)).collect();
    assert!(w[0] <= 3 && w[1] > w[0] && w[2] > w[1] + 3, "blur should widen as the aperture opens: {w:?}");
}

#[test]
fn in_focus_plane_stays_sharp_with_an_open_aperture() {
    let mut desc = defocus_scene(0.6);
    desc.camera.focal_distance = 10.0;
    assert!(blur_width(&run(&desc).0) <= blur_width(&run(&defocus_scene(0.0)).0) + 1);
}

fn edge_scene() -> SceneDesc {
    // A bright disk on a dark flat background: flat everywhere except along its rim.
    SceneDesc {
        meshes: vec![],
        settings: RenderSettings {
            width: 64,
            height: 64,
            ambient_light: Vec3::ONE,
            adaptive: Some(AdaptiveDesc { min_samples: 4, max_samples: 64, threshold: 0.005 }),
            ..Default::default()
        },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 30.0,
            ..Default::default()
        },
        lights: vec![],
        materials: vec![MaterialDesc { ambient: Some(Vec3::ONE), ..matte(Vec3::ONE) }],
        textures: vec![],
        objects: vec![node(ShapeDesc::Disk, 0, vec![TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 }])],
        views: vec![],
    }
}

#[test]
fn adaptive_sampling_spends_samples_on_edges_not_on_flat_regions() {
    let (image, stats) = run(&edge_scene());
    let counts = &stats.samples_per_pixel;
    let at = |x: u32, y: u32| counts[(y * 64 + x) as usize];
    assert_eq!(at(0, 0), 4, "flat background keeps the minimum");
    assert_eq!(at(32, 32), 4, "flat disk interior keeps the minimum");
    // Pixels the rim crosses are partly covered: they get the maximum.
    let rim: Vec<u32> = (0..64u32)
        .flat_map(|y| (0..64u32).map(move |x| (x, y)))
        .filter(|&(x, y)| (0.05..0.95).contains(&image.get(x, y).x))
        .map(|(x, y)| at(x, y))
        .collect();
    assert!(rim.len() > 20);
    let mean_rim = rim.iter().sum::<u32>() as f32 / rim.len() as f32;
    assert!(mean_rim > 32.0, "edge pixels average {mean_rim} samples");
    let total: u32 = counts.iter().sum();
    assert!(total < 64 * 64 * 16, "adaptive stays far below uniform maximum sampling: {total}");
}

#[test]
fn one_sample_that_agrees_with_its_neighbours_settles_a_pixel() {
    // From one sample the adaptive sampler cannot estimate a pixel's spread: a pixel
    // whose neighbours agree with it stops there, one whose neighbours differ (an edge)
    // goes on, and the rim still gets the maximum.
    let mut desc = edge_scene();
    desc.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 16, threshold: 0.02 });
    let (image, stats) = run(&desc);
    let counts = &stats.samples_per_pixel;
    let at = |x: u32, y: u32| counts[(y * 64 + x) as usize];
    assert_eq!((at(0, 0), at(32, 32)), (1, 1), "flat background and interior keep one sample");
    let rim: Vec<u32> = (0..64u32)
        .flat_map(|y| (0..64u32).map(move |x| (x, y)))
        .filter(|&(x, y)| (0.05..0.95).contains(&image.get(x, y).x))
        .map(|(x, y)| at(x, y))
        .collect();
    assert!(rim.len() > 20 && rim.iter().all(|&n| n >= 4), "every rim pixel refines: {rim:?}");
    let total: u32 = counts.iter().sum();
    assert!(total < 64 * 64 * 2, "most pixels take one sample: {total}");
}

#[test]
fn same_seed_gives_the_same_image_and_another_seed_other_noise() {
    let mut desc = shadow_scene(2.0, true);
    desc.settings.pattern = SamplePattern::Jittered;
    desc.settings.samples_per_axis = 2;
    let (a, _) = run(&desc);
    let (b, _) = run(&desc);
    assert_eq!(a, b);
    desc.settings.seed = 1;
    let (c, _) = run(&desc);
    assert_ne!(a, c);
    assert!(a.mean_abs_diff(&c) < 0.05, "only the noise differs");
}

#[test]
fn wide_filters_blend_neighbouring_pixels_and_keep_flat_regions_exact() {
    let mut desc = edge_scene();
    desc.settings.adaptive = None;
    desc.settings.samples_per_axis = 2;
    let (boxed, _) = run(&desc);
    for kind in [FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell, FilterKind::Lanczos] {
        desc.settings.filter = FilterDesc { kind, radius: 2.0 };
        let (filtered, _) = run(&desc);
        // Far from the rim every filter reproduces the flat colour exactly (normalized weights).
        assert!((filtered.get(2, 2) - boxed.get(2, 2)).abs().max_element() < 1e-5, "{kind:?}");
        assert!((filtered.get(32, 32) - boxed.get(32, 32)).abs().max_element() < 1e-5, "{kind:?}");
        assert_ne!(filtered, boxed, "{kind:?} changes the edges");
    }
}

/// A flat white ball (ambient only) against black, as a group or moving from
/// `open` to `close` during the shutter interval.
fn moving_ball(open: Vec3, close: Option<Vec3>) -> SceneDesc {
    let ball = node(ShapeDesc::Sphere, 0, vec![TransformOp::Scale(Vec3::splat(0.5))]);
    let kind = match close {
        Some(c) => NodeKind::Moving { close: vec![TransformOp::Translate(c)], children: vec![ball] },
        None => NodeKind::Group(vec![ball]),
    };
    SceneDesc {
        settings: RenderSettings {
            width: 64,
            height: 32,
            samples_per_axis: 8,
            pattern: SamplePattern::Jittered,
            ambient_light: Vec3::ONE,
            ..Default::default()
        },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 0.0, 6.0),
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 30.0,
            ..Default::default()
        },
        lights: vec![],
        materials: vec![MaterialDesc { ambient: Some(Vec3::ONE), ..matte(Vec3::ONE) }],
        textures: vec![],
        objects: vec![NodeDesc { transform: vec![TransformOp::Translate(open)], kind, origin: String::new() }],
        ..Default::default()
    }
}

#[test]
fn motion_blur_smears_a_moving_ball_along_its_path() {
    let still = run(&moving_ball(Vec3::ZERO, None)).0;
    let moving = run(&moving_ball(Vec3::new(-1.0, 0.0, 0.0), Some(Vec3::new(1.0, 0.0, 0.0)))).0;
    let partial = |image: &Image| (0..image.width).filter(|&x| (0.05..0.95).contains(&image.get(x, 16).x)).count();
    assert!(partial(&still) <= 4, "a still ball has crisp edges: {}", partial(&still));
    assert!(partial(&moving) > 12, "a moving ball is smeared: {}", partial(&moving));
    // The ball is in the picture for the whole shutter: the same total brightness.
    let total = |image: &Image| image.pixels.iter().map(|p| p.x).sum::<f32>();
    assert!((total(&moving) / total(&still) - 1.0).abs() < 0.05, "{} vs {}", total(&moving), total(&still));
}

#[test]
fn a_moving_node_that_does_not_move_renders_like_a_group() {
    let group = run(&moving_ball(Vec3::new(0.3, 0.1, 0.0), None)).0;
    let moving = run(&moving_ball(Vec3::new(0.3, 0.1, 0.0), Some(Vec3::new(0.3, 0.1, 0.0)))).0;
    assert!(group.mean_abs_diff(&moving) < 1e-6);
}
