//! Explaining a pixel: its Whitted ray tree holds the rays the render traces, their
//! analytic hits, and terms of the lighting equation that add up to the pixel; the
//! debug views show the first hit's normal, depth and the work behind each pixel.

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::integrator::observe::RayKind;
use glint_core::render::inspect::{DebugView, debug_image, explain_pixel, first_sample_value};
use glint_core::render::render;
use glint_core::scene::{RenderScene, compile};

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// A mirror sphere of radius 1 at the origin, seen from z = 5, before a diffuse wall at
/// z = −3; one point light. 21×21 pixels: the centre pixel looks straight down −z.
fn scene() -> RenderScene {
    let mirror = MaterialDesc {
        diffuse: Vec3::splat(0.1),
        specular: Vec3::splat(0.5),
        reflective: Some(Vec3::splat(0.7)),
        ..Default::default()
    };
    let wall = MaterialDesc { diffuse: Vec3::new(0.2, 0.6, 0.3), ..Default::default() };
    let desc = SceneDesc {
        settings: RenderSettings { width: 21, height: 21, ..Default::default() },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 40.0,
            ..Default::default()
        },
        lights: vec![LightDesc::Point { position: Vec3::new(3.0, 4.0, 6.0), color: Vec3::ONE, attenuation: Vec3::X }],
        materials: vec![mirror, wall],
        textures: vec![],
        objects: vec![
            node(ShapeDesc::Sphere, 0, vec![]),
            node(
                ShapeDesc::Plane,
                1,
                vec![
                    TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 },
                    TransformOp::Translate(Vec3::new(0.0, 0.0, -3.0)),
                ],
            ),
        ],
        meshes: vec![],
        views: vec![],
    };
    compile(&desc).expect("valid scene")
}

#[test]
fn the_centre_pixels_tree_has_the_analytic_hits_and_adds_up() {
    let scene = scene();
    let tree = explain_pixel(&scene, 10, 10);
    let camera = &tree.rays[0];
    assert_eq!((camera.kind, camera.depth, camera.parent), (RayKind::Camera, 0, None));
    let hit = camera.hit.expect("meets the sphere");
    assert!((hit.distance - 4.0).abs() < 1e-4, "the sphere's front at distance 4, got {}", hit.distance);
    assert!((hit.normal - Vec3::Z).length() < 1e-3);
    assert_eq!(camera.shadow_rays.len(), 1, "one point light, one shadow ray");
    assert_eq!(camera.shadow_rays[0].filter, Vec3::ONE, "nothing between the sphere's front and the light");
    // The mirror sends the ray straight back to the camera side: it leaves the scene.
    let reflected = &tree.rays[1];
    assert_eq!((reflected.kind, reflected.depth, reflected.parent), (RayKind::Reflected, 1, Some(0)));
    assert!((reflected.dir - Vec3::Z).length() < 1e-3 && reflected.hit.is_none());
    // Every hit's terms add up to the colour it returns: the lighting equation.
    for ray in tree.rays.iter().filter(|r| r.hit.is_some()) {
        let sum: Vec3 = ray.terms.iter().map(|(_, v)| *v).sum();
        assert!((sum - ray.color).abs().max_element() < 1e-5, "{:?}: terms {sum} vs colour {}", ray.kind, ray.color);
    }
    assert_eq!(tree.color(), first_sample_value(&scene, 10, 10), "observing changes nothing");
    let (image, _) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    assert!((image.get(10, 10) - tree.color()).abs().max_element() < 1e-6, "the tree is the rendered pixel");
}

#[test]
fn an_off_centre_pixel_reflects_onto_the_wall_and_names_it() {
    let scene = scene();
    // Near the sphere's rim the mirror turns the ray sideways and back toward the wall.
    let tree = (0..21)
        .map(|x| explain_pixel(&scene, x, 10))
        .find(|t| t.rays.iter().any(|r| r.kind == RayKind::Reflected && r.hit.is_some_and(|h| h.material == 1)))
        .expect("some rim pixel reflects the wall");
    let on_wall = tree.rays.iter().find(|r| r.hit.is_some_and(|h| h.material == 1)).unwrap();
    assert!((on_wall.hit.unwrap().point.z + 3.0).abs() < 1e-3, "the wall lies at z = −3");
    assert!(on_wall.terms.iter().any(|(name, _)| name.contains("diffuse")));
}

#[test]
fn debug_views_show_normals_depth_and_work() {
    let scene = scene();
    let normals = debug_image(&scene, DebugView::Normal);
    assert!((normals.get(10, 10) - Vec3::new(0.5, 0.5, 1.0)).length() < 1e-3, "{}", normals.get(10, 10));
    let depth = debug_image(&scene, DebugView::Depth);
    assert!(depth.get(10, 10).x > depth.get(0, 0).x, "the sphere is nearer than the wall");
    let cost = debug_image(&scene, DebugView::TraversalCost);
    assert!(cost.pixels.iter().all(|p| p.is_finite() && p.max_element() > 0.0));
    let depth_of_tree = debug_image(&scene, DebugView::RecursionDepth);
    assert_ne!(depth_of_tree.get(10, 10), depth_of_tree.get(0, 0), "the mirror bounces, the wall does not");
}
