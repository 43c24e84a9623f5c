//! The path tracer against closed-form answers: a furnace, a glowing closed sphere, a
//! point light over a plane, a scene lit only by emissive triangles; and the properties
//! every render must keep (determinism for any thread count).

use std::f32::consts::PI;
use std::sync::atomic::AtomicBool;

use glam::{Vec2, Vec3};
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::render;
use glint_core::scene::compile;

fn render_desc(desc: &SceneDesc) -> Image {
    let scene = compile(desc).expect("valid scene");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled").0
}

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

fn diffuse(albedo: f32) -> MaterialDesc {
    MaterialDesc {
        bsdf: Some(BsdfDesc::Diffuse { reflectance: ColorParam::constant(Vec3::splat(albedo)) }),
        ..MaterialDesc::default()
    }
}

/// Smooth glass of index `ior` in air.
fn glass(ior: f32) -> MaterialDesc {
    MaterialDesc {
        bsdf: Some(BsdfDesc::Dielectric {
            int_ior: ior,
            ext_ior: 1.0,
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            alpha: ScalarParam::constant(0.0),
        }),
        ..MaterialDesc::default()
    }
}

fn path_settings(size: u32, spp: u32, max_depth: u32) -> RenderSettings {
    RenderSettings {
        width: size,
        height: size,
        spp: Some(spp),
        integrator: IntegratorDesc::Path(PathDesc { max_depth, ..PathDesc::default() }),
        ..RenderSettings::default()
    }
}

fn camera(eye: Vec3, look: Vec3, fov: f32) -> CameraDesc {
    CameraDesc { eye, look, up: Vec3::Y, fov_y_degrees: fov, ..CameraDesc::default() }
}

fn mean(pixels: impl Iterator<Item = Vec3>) -> Vec3 {
    let (sum, n) = pixels.fold((Vec3::ZERO, 0), |(s, n), p| (s + p, n + 1));
    sum / n as f32
}

#[test]
fn convex_diffuse_object_under_a_uniform_sky_reflects_albedo_times_sky() {
    let (a, sky) = (0.6, Vec3::new(0.5, 1.0, 2.0));
    for shape in [ShapeDesc::Sphere, ShapeDesc::Cube] {
        let desc = SceneDesc {
            settings: path_settings(16, 64, u32::MAX),
            // Close enough that the object fills the view.
            camera: camera(Vec3::new(0.0, 0.0, 2.2), Vec3::NEG_Z, 20.0),
            lights: vec![LightDesc::Environment(EnvironmentDesc { radiance: sky, texture: None, transform: vec![] })],
            materials: vec![diffuse(a)],
            objects: vec![node(shape, 0, vec![TransformOp::Rotate { axis: Vec3::new(1.0, 1.0, 0.0), degrees: 20.0 }])],
            ..SceneDesc::default()
        };
        let image = render_desc(&desc);
        let centre = mean((6..10).flat_map(|y| (6..10).map(move |x| (x, y))).map(|(x, y)| image.get(x, y)));
        let want = a * sky;
        assert!((centre - want).abs().max_element() < 0.01 * want.max_element(), "{shape:?}: {centre} vs {want}");
    }
}

#[test]
fn inside_a_glowing_sphere_radiance_is_emission_over_one_minus_albedo() {
    // Every point sees emission E plus albedo a times what it sees: L = E + aL.
    for a in [0.0f32, 0.5, 0.8] {
        let e = Vec3::new(1.0, 0.5, 0.25);
        let material = MaterialDesc { emission: e, two_sided: true, ..diffuse(a) };
        let desc = SceneDesc {
            settings: path_settings(8, 64, u32::MAX),
            camera: camera(Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.3, -0.2, -1.0), 60.0),
            materials: vec![material],
            objects: vec![node(ShapeDesc::Sphere, 0, vec![TransformOp::Scale(Vec3::splat(3.0))])],
            ..SceneDesc::default()
        };
        let got = mean(render_desc(&desc).pixels.into_iter());
        let want = e / (1.0 - a);
        assert!((got - want).abs().max_element() < 0.02 * want.max_element(), "a = {a}: {got} vs {want}");
    }
}

#[test]
fn point_light_over_a_plane_follows_inverse_square_and_cosine() {
    let (a, intensity, height) = (0.7f32, 20.0f32, 2.0f32);
    let light = Vec3::new(0.5, height, -0.3);
    let desc = SceneDesc {
        settings: RenderSettings {
            filter: FilterDesc { kind: FilterKind::Box, radius: 0.5 },
            ..path_settings(12, 16, 8)
        },
        camera: CameraDesc { up: Vec3::NEG_Z, ..camera(Vec3::new(0.0, 6.0, 0.0), Vec3::NEG_Y, 50.0) },
        lights: vec![LightDesc::Point {
            position: light,
            color: Vec3::splat(intensity),
            attenuation: Vec3::new(0.0, 0.0, 1.0),
        }],
        materials: vec![diffuse(a)],
        objects: vec![node(ShapeDesc::Plane, 0, vec![])],
        ..SceneDesc::default()
    };
    let scene = compile(&desc).unwrap();
    let image = render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0;
    for y in 0..12 {
        for x in 0..12 {
            // The point of the plane under the pixel centre.
            let ray =
                scene.camera.ray(2.0 * (x as f32 + 0.5) / 12.0 - 1.0, 1.0 - 2.0 * (y as f32 + 0.5) / 12.0, Vec2::ZERO);
            let p = ray.at(-ray.origin.y / ray.dir.y);
            let to_light = light - p;
            let d2 = to_light.length_squared();
            let want = a / PI * intensity * (to_light.y / d2.sqrt()) / d2;
            let got = image.get(x, y).x;
            // The pixel averages over its footprint; the centre value is within 3 %.
            assert!((got - want).abs() < 0.03 * want, "pixel {x},{y}: {got} vs {want}");
        }
    }
}

/// A box of diffuse walls lit only through a ceiling panel made of many small emissive
/// triangles: light selection and triangle sampling must converge to the same image as
/// one emissive rectangle of the same size and radiance.
#[test]
fn many_emissive_triangles_light_like_one_panel() {
    let n = 24;
    let mut mesh = MeshDesc { name: "panel".into(), ..MeshDesc::default() };
    for j in 0..=n {
        for i in 0..=n {
            mesh.positions.push(Vec3::new(-1.0 + 2.0 * i as f32 / n as f32, 0.0, -1.0 + 2.0 * j as f32 / n as f32));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = (j * (n + 1) + i) as u32;
            let w = v + (n + 1) as u32;
            // Counter-clockwise seen from below (−y): the emitting side faces down.
            mesh.indices.extend([v, v + 1, w, v + 1, w + 1, w]);
        }
    }
    let emissive = MaterialDesc { emission: Vec3::splat(4.0), two_sided: false, ..diffuse(0.0) };
    let room = |panel: ShapeDesc, flip: Vec<TransformOp>| SceneDesc {
        settings: path_settings(16, 64, 4),
        camera: camera(Vec3::new(0.0, 0.0, 2.9), Vec3::NEG_Z, 60.0),
        materials: vec![diffuse(0.7), emissive.clone()],
        meshes: vec![mesh.clone()],
        objects: vec![
            NodeDesc {
                transform: vec![TransformOp::Scale(Vec3::splat(3.0))],
                kind: NodeKind::Shape { shape: ShapeDesc::Cube, material: 0 },
                origin: String::new(),
            },
            node(
                panel,
                1,
                [flip, vec![TransformOp::Scale(Vec3::splat(0.8)), TransformOp::Translate(Vec3::new(0.0, 2.9, 0.0))]]
                    .concat(),
            ),
        ],
        ..SceneDesc::default()
    };
    // The rectangle faces +y: turn it over so it shines down like the mesh.
    let triangles = mean(render_desc(&room(ShapeDesc::Mesh { index: 0 }, vec![])).pixels.into_iter());
    let rectangle = mean(
        render_desc(&room(ShapeDesc::Rectangle, vec![TransformOp::Rotate { axis: Vec3::X, degrees: 180.0 }]))
            .pixels
            .into_iter(),
    );
    assert!(triangles.x > 0.05, "{triangles}");
    assert!((triangles - rectangle).abs().max_element() < 0.03 * rectangle.max_element(), "{triangles} vs {rectangle}");
}

#[test]
fn path_traced_images_are_identical_for_any_thread_count() {
    let desc = SceneDesc {
        settings: path_settings(24, 4, 6),
        camera: camera(Vec3::new(0.0, 1.0, 4.0), Vec3::new(0.0, -0.2, -1.0), 50.0),
        lights: vec![
            LightDesc::Environment(EnvironmentDesc { radiance: Vec3::splat(0.3), texture: None, transform: vec![] }),
            LightDesc::Point { position: Vec3::new(1.0, 3.0, 1.0), color: Vec3::splat(5.0), attenuation: Vec3::Z },
        ],
        materials: vec![diffuse(0.5), glass(1.5)],
        objects: vec![
            node(ShapeDesc::Plane, 0, vec![TransformOp::Translate(Vec3::new(0.0, -1.0, 0.0))]),
            node(ShapeDesc::Sphere, 1, vec![]),
        ],
        ..SceneDesc::default()
    };
    let scene = compile(&desc).unwrap();
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0)
    };
    assert_eq!(run(1), run(2));
}

/// A box of rectangles lit by an emissive rectangle, with a glass sphere, a rough
/// metal cube and a diffuse sphere: a handful of analytic objects, which the renderer
/// traces in waves of eight rays.
fn small_room() -> SceneDesc {
    let rotate = |axis: Vec3, degrees: f32| TransformOp::Rotate { axis, degrees };
    let translate = TransformOp::Translate;
    let lamp = MaterialDesc { emission: Vec3::new(12.0, 10.0, 8.0), ..diffuse(0.5) };
    let metal = MaterialDesc {
        bsdf: Some(BsdfDesc::Conductor {
            eta: Vec3::new(0.2, 0.4, 1.4),
            k: Vec3::new(3.9, 2.4, 1.6),
            specular: ColorParam::constant(Vec3::ONE),
            alpha: ScalarParam::constant(0.2),
        }),
        ..MaterialDesc::default()
    };
    SceneDesc {
        settings: path_settings(32, 8, 8),
        camera: camera(Vec3::new(0.0, 0.0, 3.9), Vec3::NEG_Z, 25.0),
        materials: vec![diffuse(0.7), lamp, glass(1.5), metal],
        objects: vec![
            node(ShapeDesc::Rectangle, 0, vec![translate(Vec3::new(0.0, -1.0, 0.0))]),
            node(ShapeDesc::Rectangle, 0, vec![rotate(Vec3::X, 180.0), translate(Vec3::new(0.0, 1.0, 0.0))]),
            node(ShapeDesc::Rectangle, 0, vec![rotate(Vec3::X, 90.0), translate(Vec3::new(0.0, 0.0, -1.0))]),
            node(ShapeDesc::Rectangle, 0, vec![rotate(Vec3::Z, -90.0), translate(Vec3::new(-1.0, 0.0, 0.0))]),
            node(ShapeDesc::Rectangle, 0, vec![rotate(Vec3::Z, 90.0), translate(Vec3::new(1.0, 0.0, 0.0))]),
            node(
                ShapeDesc::Rectangle,
                1,
                vec![
                    TransformOp::Scale(Vec3::new(0.3, 1.0, 0.3)),
                    rotate(Vec3::X, 180.0),
                    translate(Vec3::new(0.0, 0.99, 0.0)),
                ],
            ),
            node(
                ShapeDesc::Sphere,
                2,
                vec![TransformOp::Scale(Vec3::splat(0.3)), translate(Vec3::new(-0.4, -0.7, 0.3))],
            ),
            node(
                ShapeDesc::Sphere,
                0,
                vec![TransformOp::Scale(Vec3::splat(0.2)), translate(Vec3::new(0.5, -0.8, 0.4))],
            ),
            node(
                ShapeDesc::Cube,
                3,
                vec![
                    TransformOp::Scale(Vec3::new(0.3, 0.5, 0.3)),
                    rotate(Vec3::Y, 25.0),
                    translate(Vec3::new(0.3, -0.5, -0.4)),
                ],
            ),
        ],
        ..SceneDesc::default()
    }
}

#[test]
fn paths_traced_in_waves_give_the_image_of_paths_traced_alone() {
    let scene = compile(&small_room()).unwrap();
    assert!(scene.few_objects.is_some(), "the room is a handful of analytic objects");
    let alone = glint_core::scene::RenderScene { few_objects: None, ..scene.clone() };
    let image = |scene| render(scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0;
    let (waves, single) = (image(&scene), image(&alone));
    // The light reaches the whole room, so the images have something to compare.
    assert!(single.pixels.iter().all(|p| p.max_element() > 0.0));
    // Each path gives the value it gives alone: the same image, bit for bit, except
    // where a ray meets two objects at exactly the same distance (along the room's
    // edges), which either may win.
    let differing = waves.pixels.iter().zip(&single.pixels).filter(|(a, b)| a != b).count();
    assert!(differing <= single.pixels.len() / 100, "{differing} of {} pixels differ", single.pixels.len());
    let (mean_waves, mean_single) = (mean(waves.pixels.iter().copied()), mean(single.pixels.iter().copied()));
    assert!((mean_waves - mean_single).abs().max_element() < 1e-3 * mean_single.max_element());
}

#[test]
fn emission_leaves_the_front_only_unless_the_material_is_two_sided() {
    // A rectangle facing +y, seen from above (front) and from below (back), path-traced
    // with depth 1 (emitters seen directly). Phong materials scatter from both sides;
    // emission still follows `two_sided`.
    let seen_from = |y: f32, two_sided: bool| {
        let lamp = MaterialDesc { emission: Vec3::splat(3.0), two_sided, ..MaterialDesc::default() };
        let desc = SceneDesc {
            settings: path_settings(4, 1, 1),
            camera: CameraDesc { up: Vec3::Z, ..camera(Vec3::new(0.0, y, 0.0), Vec3::new(0.0, -y, 0.0), 20.0) },
            materials: vec![lamp],
            objects: vec![node(ShapeDesc::Rectangle, 0, vec![TransformOp::Scale(Vec3::splat(5.0))])],
            ..SceneDesc::default()
        };
        render_desc(&desc).get(2, 2)
    };
    assert_eq!(seen_from(3.0, false), Vec3::splat(3.0));
    assert_eq!(seen_from(-3.0, false), Vec3::ZERO);
    assert_eq!(seen_from(-3.0, true), Vec3::splat(3.0));
}

#[test]
fn invalid_physical_materials_are_compile_errors_not_panics() {
    let bad_texture = MaterialDesc {
        bsdf: Some(BsdfDesc::Diffuse { reflectance: ColorParam { value: Vec3::ONE, texture: Some(7) } }),
        ..MaterialDesc::default()
    };
    let bad_ior = glass(-1.5);
    let bad_emission = MaterialDesc { emission: Vec3::new(1.0, f32::NAN, 0.0), ..MaterialDesc::default() };
    for material in [bad_texture, bad_ior, bad_emission] {
        let desc = SceneDesc {
            settings: path_settings(4, 1, 2),
            materials: vec![material],
            objects: vec![node(ShapeDesc::Sphere, 0, vec![])],
            ..SceneDesc::default()
        };
        assert!(compile(&desc).is_err());
    }
}

/// A room lit by a ceiling panel whose emission is `texture`d (a 1×1 image) or not:
/// a textured emitter is found by BSDF sampling only, and must converge to the same
/// light as the sampled one when its texture is white.
fn room_with_panel(texel: Option<Vec3>) -> Image {
    let mut panel = MaterialDesc { emission: Vec3::splat(4.0), two_sided: false, ..diffuse(0.0) };
    let mut textures = vec![];
    if let Some(texel) = texel {
        textures.push(TextureDesc::Image {
            name: "screen".into(),
            path: String::new(),
            width: 1,
            height: 1,
            texels: vec![texel],
            sampling: ImageSampling::default(),
        });
        panel.emission_texture = Some(0);
    }
    let desc = SceneDesc {
        settings: path_settings(16, 256, 3),
        camera: camera(Vec3::new(0.0, 0.0, 2.9), Vec3::NEG_Z, 60.0),
        materials: vec![diffuse(0.7), panel],
        textures,
        objects: vec![
            node(ShapeDesc::Cube, 0, vec![TransformOp::Scale(Vec3::splat(3.0))]),
            node(
                ShapeDesc::Rectangle,
                1,
                vec![
                    TransformOp::Rotate { axis: Vec3::X, degrees: 180.0 },
                    TransformOp::Scale(Vec3::splat(2.0)),
                    TransformOp::Translate(Vec3::new(0.0, 2.9, 0.0)),
                ],
            ),
        ],
        ..SceneDesc::default()
    };
    let scene = compile(&desc).unwrap();
    assert_eq!(scene.emitters.len(), usize::from(texel.is_none()), "a textured emitter is not a sampled light");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0
}

#[test]
fn a_textured_emitter_lights_as_its_texture_says() {
    let sampled = mean(room_with_panel(None).pixels.into_iter());
    let white = mean(room_with_panel(Some(Vec3::ONE)).pixels.into_iter());
    let half = mean(room_with_panel(Some(Vec3::new(0.5, 0.25, 1.0))).pixels.into_iter());
    assert!(sampled.x > 0.05, "{sampled}");
    assert!((white - sampled).abs().max_element() < 0.05 * sampled.max_element(), "{white} vs {sampled}");
    // The walls reflect the panel's colour: each channel scales with the texel.
    let ratio = half / white;
    assert!((ratio - Vec3::new(0.5, 0.25, 1.0)).abs().max_element() < 0.05, "{ratio}");
}
