//! End-to-end properties of rendered images: the lighting equation term by term,
//! robustness of secondary rays at every scale, and determinism across thread counts.

use std::sync::atomic::AtomicBool;

use glam::{Vec2, Vec3};
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::{TileStore, render, render_resumable};
use glint_core::scene::compile;

fn render_desc(desc: &SceneDesc) -> Image {
    let scene = compile(desc).expect("valid scene");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled").0
}

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// A 1×1 image looking down −z at a plane z = 0 that faces the camera.
fn facing_plane(material: MaterialDesc, lights: Vec<LightDesc>, ambient: Vec3, background: Vec3) -> SceneDesc {
    SceneDesc {
        meshes: vec![],
        views: vec![],
        settings: RenderSettings { width: 1, height: 1, background, ambient_light: ambient, ..Default::default() },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 30.0,
            ..Default::default()
        },
        lights,
        materials: vec![material],
        textures: vec![],
        objects: vec![node(ShapeDesc::Plane, 0, vec![TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 }])],
    }
}

fn black() -> MaterialDesc {
    MaterialDesc { diffuse: Vec3::ZERO, specular: Vec3::ZERO, reflective: Some(Vec3::ZERO), ..Default::default() }
}

fn pixel(desc: &SceneDesc) -> Vec3 {
    render_desc(desc).get(0, 0)
}

fn assert_close(got: Vec3, want: Vec3) {
    assert!((got - want).abs().max_element() < 1e-5, "got {got}, want {want}");
}

/// A directional light arriving at `degrees` from the plane's normal (+z), tilted in x.
fn light_at(degrees: f32) -> LightDesc {
    let a = degrees.to_radians();
    LightDesc::Directional { direction: -Vec3::new(a.sin(), 0.0, a.cos()), color: Vec3::ONE }
}

#[test]
fn ambient_term_alone() {
    let m = MaterialDesc { ka: 0.5, ambient: Some(Vec3::new(0.2, 0.4, 0.6)), ..black() };
    let got = pixel(&facing_plane(m, vec![], Vec3::new(1.0, 0.5, 0.25), Vec3::ZERO));
    assert_close(got, Vec3::new(0.5 * 0.2, 0.5 * 0.4 * 0.5, 0.5 * 0.6 * 0.25));
}

#[test]
fn diffuse_term_alone_follows_lamberts_cosine() {
    for degrees in [0.0f32, 30.0, 60.0, 85.0] {
        let m = MaterialDesc { kd: 0.5, diffuse: Vec3::new(0.8, 0.6, 0.4), ambient: Some(Vec3::ZERO), ..black() };
        let got = pixel(&facing_plane(m, vec![light_at(degrees)], Vec3::ZERO, Vec3::ZERO));
        assert_close(got, 0.5 * Vec3::new(0.8, 0.6, 0.4) * degrees.to_radians().cos());
    }
    // A light behind the surface contributes nothing.
    let m = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
    assert_close(pixel(&facing_plane(m, vec![light_at(120.0)], Vec3::ZERO, Vec3::ZERO)), Vec3::ZERO);
}

#[test]
fn specular_term_alone_is_phong() {
    // Viewer on the normal, light at θ: r·v = cos θ, so the highlight is cos(θ)^n.
    for (degrees, n) in [(0.0f32, 10.0f32), (30.0, 2.0), (45.0, 8.0)] {
        let m = MaterialDesc {
            ks: 0.5,
            specular: Vec3::new(1.0, 0.5, 0.25),
            shininess: n,
            ambient: Some(Vec3::ZERO),
            ..black()
        };
        let got = pixel(&facing_plane(m, vec![light_at(degrees)], Vec3::ZERO, Vec3::ZERO));
        assert_close(got, 0.5 * Vec3::new(1.0, 0.5, 0.25) * degrees.to_radians().cos().powf(n));
    }
}

#[test]
fn point_light_attenuation() {
    let m = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
    let light = LightDesc::Point {
        position: Vec3::new(0.0, 0.0, 4.0),
        color: Vec3::ONE,
        attenuation: Vec3::new(1.0, 0.5, 0.25),
    };
    let got = pixel(&facing_plane(m, vec![light], Vec3::ZERO, Vec3::ZERO));
    assert_close(got, Vec3::splat(1.0 / (1.0 + 0.5 * 4.0 + 0.25 * 16.0)));
}

#[test]
fn reflected_term_alone_mirrors_the_background() {
    let m = MaterialDesc { ks: 0.5, reflective: Some(Vec3::new(1.0, 0.5, 0.5)), ..black() };
    let background = Vec3::new(0.2, 0.4, 0.8);
    assert_close(pixel(&facing_plane(m, vec![], Vec3::ZERO, background)), 0.5 * Vec3::new(1.0, 0.5, 0.5) * background);
}

#[test]
fn transmitted_term_alone_shows_what_is_behind() {
    let m = MaterialDesc { kt: 0.5, transmissive: Vec3::new(1.0, 0.5, 0.5), ..black() };
    let background = Vec3::new(0.2, 0.4, 0.8);
    assert_close(pixel(&facing_plane(m, vec![], Vec3::ZERO, background)), 0.5 * Vec3::new(1.0, 0.5, 0.5) * background);
}

#[test]
fn recursion_stops_at_max_depth() {
    // Two facing mirrors: each bounce multiplies by 0.5, the background is never seen,
    // so the pixel is the sum of the ambient terms of the bounces traced.
    let mut desc = facing_plane(
        MaterialDesc { ka: 1.0, ambient: Some(Vec3::ONE), reflective: Some(Vec3::splat(0.5)), ..black() },
        vec![],
        Vec3::ONE,
        Vec3::ZERO,
    );
    desc.objects.push(node(
        ShapeDesc::Plane,
        0,
        vec![TransformOp::Rotate { axis: Vec3::X, degrees: -90.0 }, TransformOp::Translate(Vec3::new(0.0, 0.0, 10.0))],
    ));
    desc.settings.min_contribution = 0.0;
    for depth in [0u32, 1, 3] {
        desc.settings.max_depth = depth;
        let expected: f32 = (0..=depth).map(|k| 0.5f32.powi(k as i32)).sum();
        assert_close(pixel(&desc), Vec3::splat(expected));
    }
}

#[test]
fn opaque_occluders_cast_shadows_and_transparent_ones_filter() {
    let lit = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
    let mut desc = facing_plane(lit, vec![light_at(0.0)], Vec3::ZERO, Vec3::ZERO);
    assert_close(pixel(&desc), Vec3::ONE);
    // A pane (a disk, ior 1, k_t·O_t = 0.5) between the plane and the light, which the
    // camera also looks through: it halves the light once and the view once.
    desc.materials.push(MaterialDesc { kt: 1.0, transmissive: Vec3::splat(0.5), ..black() });
    desc.objects.push(node(
        ShapeDesc::Disk,
        1,
        vec![TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 }, TransformOp::Translate(Vec3::new(0.0, 0.0, 1.0))],
    ));
    // Light filtered once (0.5), then seen through the pane (0.5).
    assert_close(pixel(&desc), Vec3::splat(0.25));
    // An opaque pane blocks the light; the camera sees the pane itself (black).
    desc.materials[1] = black();
    assert_close(pixel(&desc), Vec3::ZERO);
}

/// A lit plane seen, and lit by a light straight above it, through two panes (disks at
/// z = 1 and 2) of material 1, which lets half the light through (`k_t·O_t` = 0.5).
fn plane_behind_two_panes() -> SceneDesc {
    let lit = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
    let mut desc = facing_plane(lit, vec![light_at(0.0)], Vec3::ZERO, Vec3::ZERO);
    desc.materials.push(MaterialDesc { kt: 1.0, transmissive: Vec3::splat(0.5), ..black() });
    for z in [1.0, 2.0] {
        desc.objects.push(node(
            ShapeDesc::Disk,
            1,
            vec![TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 }, TransformOp::Translate(Vec3::new(0.0, 0.0, z))],
        ));
    }
    desc
}

#[test]
fn every_transparent_occluder_filters_a_directional_light() {
    let desc = plane_behind_two_panes();
    // The light is infinitely far: past the first pane the shadow ray still runs to
    // infinity and meets the second. Light filtered twice, seen through both panes.
    assert_close(pixel(&desc), Vec3::splat(0.5f32.powi(4)));
}

/// Each leg a shadow ray traces past a transparent surface is a ray of its own (a
/// whole query of the scene), as POV-Ray counts its shadow ray tests: two panes make
/// two more rays, an opaque one none, and waves count as one-by-one tracing does.
#[test]
fn a_shadow_ray_counts_a_ray_for_each_leg_past_a_transparent_surface() {
    let mut desc = plane_behind_two_panes();
    let to_light = glint_core::math::Ray::new(Vec3::new(0.0, 0.0, 0.01), Vec3::Z);
    let scene = compile(&desc).expect("valid scene");
    assert_eq!(scene.transmittance_counted(&to_light, f32::INFINITY), (Vec3::splat(0.25), 2));
    assert!(scene.few_objects.is_some(), "a plane and two disks are traced in waves");
    let alone = glint_core::scene::RenderScene { few_objects: None, ..scene.clone() };
    let rays = |scene| render(scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled").1.rays;
    assert_eq!(rays(&scene), rays(&alone));
    desc.materials[1] = black();
    let scene = compile(&desc).expect("valid scene");
    assert_eq!(scene.transmittance_counted(&to_light, f32::INFINITY), (Vec3::ZERO, 0));
}

#[test]
fn corner_samples_reach_across_tile_borders() {
    // A plane lit by a point light on the view axis: the image is mirror-symmetric in
    // x. Tiles are 16 pixels wide, so the border between columns 15 and 16 of a 24-wide
    // image mirrors the inside of the first tile (columns 8 and 7): a corner sample,
    // shared by the pixels that meet there, must reach both sides of a border alike.
    let lit = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
    let light = LightDesc::Point { position: Vec3::new(0.0, 0.0, 1.0), color: Vec3::ONE, attenuation: Vec3::X };
    let mut desc = facing_plane(lit, vec![light], Vec3::ZERO, Vec3::ZERO);
    desc.settings.width = 24;
    desc.settings.height = 4;
    desc.settings.pattern = glint_core::sampling::SamplePattern::CornersAndCentre;
    let image = render_desc(&desc);
    for y in 0..4 {
        for x in 0..12 {
            let (a, b) = (image.get(x, y), image.get(23 - x, y));
            assert!((a - b).abs().max_element() < 1e-5 * (1.0 + a.max_element()), "({x}, {y}): {a} vs {b}");
        }
    }
}

#[test]
fn textures_blend_into_the_diffuse_colour() {
    let mut desc = facing_plane(
        MaterialDesc {
            diffuse: Vec3::new(1.0, 0.0, 0.0),
            ambient: Some(Vec3::ZERO),
            texture: Some(0),
            blend: 0.25,
            ..black()
        },
        vec![light_at(0.0)],
        Vec3::ZERO,
        Vec3::ZERO,
    );
    desc.textures.push(TextureDesc::Checker {
        name: "c".into(),
        even: Vec3::new(0.0, 1.0, 0.0),
        odd: Vec3::ZERO,
        cells: Vec2::ONE,
        filtered: false,
    });
    // The plane's uv at the centre pixel is (0, 0): the "even" cell.
    assert_close(pixel(&desc), 0.75 * Vec3::new(1.0, 0.0, 0.0) + 0.25 * Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn textured_ambient_follows_the_texture_as_the_diffuse_does() {
    let material = MaterialDesc {
        ka: 0.5,
        diffuse: Vec3::new(1.0, 0.0, 0.0),
        texture: Some(0),
        blend: 0.25,
        textured_ambient: true,
        ..black()
    };
    let mut desc = facing_plane(material, vec![], Vec3::new(1.0, 0.5, 1.0), Vec3::ZERO);
    desc.textures.push(TextureDesc::Checker {
        name: "c".into(),
        even: Vec3::new(0.0, 1.0, 0.0),
        odd: Vec3::ZERO,
        cells: Vec2::ONE,
        filtered: false,
    });
    // L_a·k_a·((1 − b)·O_a + b·T), O_a being O_d, at the "even" cell.
    let textured = 0.5 * (0.75 * Vec3::new(1.0, 0.0, 0.0) + 0.25 * Vec3::new(0.0, 1.0, 0.0));
    assert_close(pixel(&desc), Vec3::new(1.0, 0.5, 1.0) * textured);
    // The lecture's ambient ignores the texture.
    desc.materials[0].textured_ambient = false;
    assert_close(pixel(&desc), Vec3::new(0.5, 0.0, 0.0));
}

#[test]
fn specular_term_alone_is_blinn_where_asked() {
    // Viewer on the normal, light at θ: the half vector is θ/2 off the normal, so the
    // highlight is cos(θ/2)^n, where Phong's would be cos(θ)^n.
    for (degrees, n) in [(0.0f32, 10.0f32), (30.0, 2.0), (60.0, 8.0)] {
        let m = MaterialDesc {
            specular: Vec3::new(1.0, 0.5, 0.25),
            shininess: n,
            highlight: Highlight::Blinn,
            ambient: Some(Vec3::ZERO),
            ..black()
        };
        let got = pixel(&facing_plane(m, vec![light_at(degrees)], Vec3::ZERO, Vec3::ZERO));
        assert_close(got, Vec3::new(1.0, 0.5, 0.25) * (degrees / 2.0).to_radians().cos().powf(n));
    }
}

/// A lone mirror or glass sphere (no highlight, no local shading) against a plain
/// background, at `scale` and far from the origin. Every pixel of the mirror is exactly
/// `O_r·B` and every pixel of the glass `O_t²·B` (a ray through a sphere never meets
/// total internal reflection) — any self-intersection of a secondary ray breaks that.
fn sphere_at_scale(material: MaterialDesc, scale: f32, offset: Vec3) -> SceneDesc {
    let background = Vec3::new(0.25, 0.5, 1.0);
    SceneDesc {
        meshes: vec![],
        views: vec![],
        settings: RenderSettings {
            width: 48,
            height: 48,
            background,
            ambient_light: Vec3::ZERO,
            max_depth: 8,
            min_contribution: 0.0,
            ..Default::default()
        },
        camera: CameraDesc {
            eye: offset + Vec3::new(0.3, 0.2, 4.0) * scale,
            look: Vec3::NEG_Z,
            up: Vec3::Y,
            fov_y_degrees: 40.0,
            ..Default::default()
        },
        lights: vec![],
        materials: vec![material],
        textures: vec![],
        objects: vec![node(
            ShapeDesc::Sphere,
            0,
            vec![TransformOp::Scale(Vec3::splat(scale)), TransformOp::Translate(offset)],
        )],
    }
}

#[test]
fn no_self_intersection_at_any_scale() {
    let mirror = MaterialDesc { reflective: Some(Vec3::splat(0.5)), ..black() };
    let glass = MaterialDesc { transmissive: Vec3::splat(0.5), ior: 1.5, ..black() };
    for (scale, offset) in
        [(1.0, Vec3::ZERO), (1e-4, Vec3::ZERO), (1e-3, Vec3::splat(0.5)), (1e4, Vec3::ZERO), (100.0, Vec3::splat(1e5))]
    {
        for (material, factor) in [(mirror.clone(), 0.5), (glass.clone(), 0.25)] {
            let desc = sphere_at_scale(material, scale, offset);
            let b = desc.settings.background;
            let image = render_desc(&desc);
            let on_sphere: Vec<Vec3> = image.pixels.iter().copied().filter(|&p| p != b).collect();
            assert!(on_sphere.len() > 500, "the sphere fills the view");
            for p in on_sphere {
                assert!(
                    (p - factor * b).abs().max_element() < 1e-6,
                    "scale {scale}, offset {offset}: pixel {p}, want {}",
                    factor * b
                );
            }
        }
    }
}

/// Diffuse self-shadowing: on a lit sphere every pixel must equal the analytic shade
/// `k_d·O_d·max(n·l, 0)` — shadow acne would leave dark pixels where n·l > 0.
#[test]
fn no_shadow_acne_at_any_scale() {
    let l = Vec3::new(1.0, 1.0, 0.2).normalize();
    for (scale, offset) in [(1.0f32, Vec3::ZERO), (1e-4, Vec3::ZERO), (1e4, Vec3::splat(3e4)), (1.0, Vec3::splat(1e4))]
    {
        let m = MaterialDesc { diffuse: Vec3::ONE, ambient: Some(Vec3::ZERO), ..black() };
        let desc = SceneDesc {
            meshes: vec![],
            views: vec![],
            settings: RenderSettings { width: 48, height: 48, ambient_light: Vec3::ZERO, ..Default::default() },
            camera: CameraDesc {
                eye: offset + Vec3::new(0.0, 0.0, 4.0 * scale),
                look: Vec3::NEG_Z,
                up: Vec3::Y,
                fov_y_degrees: 40.0,
                ..Default::default()
            },
            lights: vec![LightDesc::Directional { direction: -l, color: Vec3::ONE }],
            materials: vec![m],
            textures: vec![],
            objects: vec![node(
                ShapeDesc::Sphere,
                0,
                vec![TransformOp::Scale(Vec3::splat(scale)), TransformOp::Translate(offset)],
            )],
        };
        let scene = compile(&desc).unwrap();
        let image = render_desc(&desc);
        let mut lit = 0;
        for y in 0..48 {
            for x in 0..48 {
                let ray = scene.camera.ray(
                    2.0 * (x as f32 + 0.5) / 48.0 - 1.0,
                    1.0 - 2.0 * (y as f32 + 0.5) / 48.0,
                    Vec2::ZERO,
                );
                let Some(hit) = scene.intersect(&ray, f32::INFINITY) else { continue };
                let n_dot_l = hit.normal.dot(l);
                if n_dot_l > 0.02 {
                    lit += 1;
                    let got = image.get(x, y).x;
                    assert!((got - n_dot_l).abs() < 2e-3, "scale {scale}: pixel ({x},{y}) = {got}, n·l = {n_dot_l}");
                }
            }
        }
        assert!(lit > 300);
    }
}

fn busy_scene() -> SceneDesc {
    let mut materials = vec![
        MaterialDesc {
            diffuse: Vec3::new(0.8, 0.3, 0.2),
            specular: Vec3::splat(0.5),
            reflective: Some(Vec3::splat(0.2)),
            ..Default::default()
        },
        MaterialDesc {
            diffuse: Vec3::ZERO,
            transmissive: Vec3::splat(0.9),
            ior: 1.5,
            specular: Vec3::ONE,
            shininess: 100.0,
            ..Default::default()
        },
    ];
    materials.push(MaterialDesc { diffuse: Vec3::new(0.2, 0.7, 0.3), ..Default::default() });
    let shapes = [
        ShapeDesc::Sphere,
        ShapeDesc::Cube,
        ShapeDesc::Cylinder,
        ShapeDesc::Cone,
        ShapeDesc::Torus { minor_radius: 0.3 },
        ShapeDesc::Disk,
    ];
    let mut objects: Vec<NodeDesc> = (0..24)
        .map(|i| {
            let pos = Vec3::new((i % 6) as f32 * 2.2 - 5.5, 1.0, (i / 6) as f32 * -2.5);
            node(
                shapes[i % shapes.len()],
                i % 3,
                vec![
                    TransformOp::Rotate { axis: Vec3::new(1.0, 2.0, 0.5), degrees: 17.0 * i as f32 },
                    TransformOp::Translate(pos),
                ],
            )
        })
        .collect();
    objects.push(node(ShapeDesc::Plane, 2, vec![]));
    SceneDesc {
        meshes: vec![],
        views: vec![],
        settings: RenderSettings { width: 96, height: 64, samples_per_axis: 2, ..Default::default() },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 4.0, 9.0),
            look: Vec3::new(0.0, -0.4, -1.0),
            up: Vec3::Y,
            fov_y_degrees: 50.0,
            ..Default::default()
        },
        lights: vec![
            LightDesc::Point { position: Vec3::new(4.0, 8.0, 6.0), color: Vec3::ONE, attenuation: Vec3::X },
            LightDesc::Spot {
                position: Vec3::new(-4.0, 6.0, 2.0),
                direction: Vec3::new(0.5, -1.0, -0.5),
                color: Vec3::splat(0.7),
                attenuation: Vec3::X,
                angle_degrees: 35.0,
                penumbra_degrees: 8.0,
                falloff: SpotFalloff::Smooth,
            },
        ],
        materials,
        textures: vec![],
        objects,
    }
}

#[test]
fn image_is_bit_identical_for_any_thread_count() {
    let scene = compile(&busy_scene()).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap())
    };
    let (one, stats_one) = run(1);
    let (three, stats_three) = run(3);
    assert!(
        one.pixels
            .iter()
            .zip(&three.pixels)
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits))
    );
    assert_eq!(stats_one, stats_three);
    // And it is not a blank image.
    assert!(one.pixels.iter().any(|p| p.x > 0.2) && one.pixels.iter().all(|p| p.is_finite()));
}

/// `render` merges tiles band by band as they finish and drops them; a store's render
/// merges them all at the end. The two give the same bits, with a narrow filter and the
/// widest allowed (its halo half a tile), AOVs, adaptive sampling and partial tiles at
/// the edges, on three threads.
#[test]
fn merging_as_tiles_finish_gives_the_merge_at_the_end() {
    for (radius, adaptive) in
        [(1.5, None), (8.0, Some(AdaptiveDesc { min_samples: 2, max_samples: 8, threshold: 0.05 }))]
    {
        let mut desc = busy_scene();
        desc.settings.width = 75;
        desc.settings.height = 83;
        desc.settings.filter = FilterDesc { kind: FilterKind::Gaussian, radius };
        desc.settings.adaptive = adaptive;
        let mut scene = compile(&desc).unwrap();
        scene.settings.aovs = true;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        let (streamed, streamed_stats) = pool.install(|| render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap());
        let store = TileStore::default();
        let (kept, kept_stats) =
            pool.install(|| render_resumable(&scene, &store, &|_, _| {}, &AtomicBool::new(false)).unwrap());
        let bits = |image: &Image| image.pixels.iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&streamed), bits(&kept), "filter radius {radius}");
        assert_eq!(streamed_stats, kept_stats, "filter radius {radius}");
        assert!(streamed_stats.aovs.is_some());
        assert_eq!(store.len(), 5 * 6, "the store keeps every tile");
    }
}

#[test]
fn cancelled_render_returns_no_image() {
    let scene = compile(&busy_scene()).unwrap();
    assert!(render(&scene, &|_, _| {}, &AtomicBool::new(true)).is_err());
}

#[test]
fn degenerate_scenes_are_rejected_at_compile_time() {
    let mut desc = busy_scene();
    desc.objects[0].transform.push(TransformOp::Scale(Vec3::new(1.0, 0.0, 1.0)));
    desc.objects[0].origin = "scene.glint:7:3".into();
    let err = compile(&desc).unwrap_err().to_string();
    assert!(err.starts_with("scene.glint:7:3:"), "{err}");

    let mut desc = busy_scene();
    desc.camera.up = desc.camera.look;
    assert!(compile(&desc).is_err());

    let mut desc = busy_scene();
    desc.settings.width = 100_000;
    assert!(compile(&desc).unwrap_err().to_string().contains("out of range"));

    let mut desc = busy_scene();
    desc.lights.push(LightDesc::Point { position: Vec3::NAN, color: Vec3::ONE, attenuation: Vec3::X });
    assert!(compile(&desc).is_err());
}

/// A floor of fine checks, seen from eye height toward the horizon, lit from straight
/// above so each pixel shows its texture's colour; `filtered` sets the checker's filter.
fn checkered_floor(filtered: bool, spp: u32) -> SceneDesc {
    SceneDesc {
        meshes: vec![],
        views: vec![],
        settings: RenderSettings { width: 80, height: 40, spp: Some(spp), ..Default::default() },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 1.0, 0.0),
            look: Vec3::new(0.0, -0.2, -1.0),
            up: Vec3::Y,
            fov_y_degrees: 40.0,
            ..Default::default()
        },
        lights: vec![LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::ONE }],
        materials: vec![MaterialDesc {
            kd: 1.0,
            diffuse: Vec3::ONE,
            texture: Some(0),
            blend: 1.0,
            ambient: Some(Vec3::ZERO),
            ..black()
        }],
        textures: vec![TextureDesc::Checker {
            name: "c".into(),
            even: Vec3::ONE,
            odd: Vec3::ZERO,
            cells: Vec2::splat(8.0),
            filtered,
        }],
        objects: vec![node(ShapeDesc::Plane, 0, vec![])],
    }
}

fn rms_difference(a: &Image, b: &Image) -> f32 {
    let mut sum = 0.0;
    for y in 0..a.height {
        for x in 0..a.width {
            sum += (a.get(x, y) - b.get(x, y)).length_squared() / 3.0;
        }
    }
    (sum / (a.width * a.height) as f32).sqrt()
}

#[test]
fn a_filtered_checker_at_one_sample_comes_close_to_the_supersampled_floor() {
    let reference = render_desc(&checkered_floor(false, 256));
    let point_sampled = rms_difference(&render_desc(&checkered_floor(false, 1)), &reference);
    let filtered = rms_difference(&render_desc(&checkered_floor(true, 1)), &reference);
    // Point samples alias toward the horizon (errors of half the contrast and more);
    // the footprint's mean is what the 256 samples converge to, up to the difference
    // between a box over the pixel and the film's reconstruction filter.
    assert!(point_sampled > 0.2, "the scene must alias unfiltered: {point_sampled}");
    assert!(filtered < 0.4 * point_sampled && filtered < 0.1, "filtered {filtered} vs point-sampled {point_sampled}");
}

#[test]
fn footprints_in_uv_take_the_short_way_across_a_spheres_seam() {
    // A unit sphere seen from 4 units away, turned four ways so its seam (a meridian)
    // faces the camera in one of them; every pixel's uv step stays a pixel's worth.
    for degrees in [0.0, 90.0, 180.0, 270.0] {
        let mut desc = checkered_floor(true, 1);
        desc.camera = CameraDesc { eye: Vec3::new(0.0, 0.0, 4.0), look: Vec3::NEG_Z, ..desc.camera };
        desc.objects = vec![node(ShapeDesc::Sphere, 0, vec![TransformOp::Rotate { axis: Vec3::Y, degrees }])];
        let scene = compile(&desc).expect("valid scene");
        let mut largest: f32 = 0.0;
        for x in 0..80 {
            let film_x = 2.0 * (x as f32 + 0.5) / 80.0 - 1.0;
            let ray = scene.camera.ray(film_x, 0.0, Vec2::ZERO);
            if let Some(hit) = scene.intersect(&ray, f32::INFINITY) {
                let steps = scene.uv_steps(&hit, 0.0, 1.0).expect("a bounded footprint on a sphere seen whole");
                largest = largest.max(steps[0].length()).max(steps[1].length());
            }
        }
        // About 40 pixels span the sphere's front half (u from 0.25 to 0.75): a step of
        // 1/80 in u, more toward the rim.
        assert!(largest > 0.005 && largest < 0.2, "turned {degrees}°: largest uv step {largest}");
    }
}

#[test]
fn adaptive_samples_narrow_the_footprint_as_their_count_grows() {
    let mut desc = checkered_floor(true, 4);
    let uniform = compile(&desc).expect("valid scene").settings;
    assert_eq!([uniform.sample_footprint(0), uniform.sample_footprint(3)], [0.5, 0.5], "1/√4 for every sample");
    desc.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 64, threshold: 0.05 });
    let adaptive = compile(&desc).expect("valid scene").settings;
    let scales: Vec<f32> = [0, 3, 15, 63].iter().map(|&i| adaptive.sample_footprint(i)).collect();
    assert_eq!(scales, [1.0, 0.5, 0.25, 0.125], "sample k as one of k + 1, at least an eighth");
}

#[test]
fn adaptive_pixels_that_stop_at_one_sample_take_it_at_their_centre() {
    // With a filtered texture, a Whitted pixel starts from a pilot at its centre,
    // filtered over the whole pixel, as one sample a pixel takes it: where every pixel settles there, the image is the
    // one-sample image bit for bit. Pixels that go on drop the pilot for their own
    // stratified samples, at least four.
    let one_sample = render_desc(&checkered_floor(true, 1));
    let mut desc = checkered_floor(true, 1);
    desc.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 16, threshold: 10.0 });
    assert_eq!(render_desc(&desc), one_sample);
    desc.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 16, threshold: 0.02 });
    let scene = compile(&desc).expect("valid scene");
    let (_, stats) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    let counts = &stats.samples_per_pixel;
    assert!(counts.contains(&1) && counts.iter().any(|&n| n > 1), "some settle, some go on");
    assert!(counts.iter().all(|&n| n == 1 || n >= 4), "a refined pixel takes at least four: {counts:?}");
    // A point-sampled checker keeps random first samples, so that its aliasing shows
    // as noise between neighbours and refines rather than settling as a coherent moiré.
    let mut point_sampled = checkered_floor(false, 1);
    let one_sample = render_desc(&point_sampled);
    point_sampled.settings.adaptive = Some(AdaptiveDesc { min_samples: 1, max_samples: 16, threshold: 10.0 });
    assert_ne!(render_desc(&point_sampled), one_sample);
}

/// A classic Whitted scene of seven analytic objects: a checkered plane, mirror, glass
/// and matte spheres, a cylinder, a cone and a cube under two point lights, which the
/// renderer traces in waves of eight rays.
fn whitted_room() -> SceneDesc {
    let translate = TransformOp::Translate;
    let scale = TransformOp::Scale;
    let material = |diffuse: Vec3, reflective: Vec3, transmissive: Vec3| MaterialDesc {
        diffuse,
        specular: Vec3::splat(0.5),
        shininess: 60.0,
        reflective: Some(reflective),
        transmissive,
        ior: 1.5,
        ..Default::default()
    };
    let floor =
        MaterialDesc { texture: Some(0), textured_ambient: true, ..material(Vec3::ONE, Vec3::ZERO, Vec3::ZERO) };
    let checks = TextureDesc::Checker {
        name: "checks".into(),
        even: Vec3::splat(0.9),
        odd: Vec3::splat(0.1),
        cells: Vec2::splat(8.0),
        filtered: false,
    };
    let point =
        |position: Vec3, color: f32| LightDesc::Point { position, color: Vec3::splat(color), attenuation: Vec3::X };
    SceneDesc {
        settings: RenderSettings {
            width: 64,
            height: 48,
            max_depth: 5,
            ambient_light: Vec3::splat(0.1),
            background: Vec3::new(0.05, 0.08, 0.2),
            ..Default::default()
        },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 3.2, 10.0),
            look: Vec3::new(0.0, -2.3, -10.0),
            up: Vec3::Y,
            fov_y_degrees: 40.0,
            ..Default::default()
        },
        lights: vec![point(Vec3::new(5.0, 9.0, 6.0), 0.8), point(Vec3::new(-6.0, 7.0, 4.0), 0.4)],
        materials: vec![
            floor,
            material(Vec3::splat(0.05), Vec3::splat(0.85), Vec3::ZERO),
            material(Vec3::ZERO, Vec3::splat(0.1), Vec3::splat(0.9)),
            material(Vec3::new(0.8, 0.1, 0.1), Vec3::splat(0.05), Vec3::ZERO),
        ],
        textures: vec![checks],
        objects: vec![
            node(ShapeDesc::Plane, 0, vec![scale(Vec3::splat(4.0))]),
            node(ShapeDesc::Sphere, 1, vec![translate(Vec3::new(-1.2, 1.0, -0.5))]),
            node(ShapeDesc::Sphere, 2, vec![scale(Vec3::splat(0.75)), translate(Vec3::new(1.1, 0.75, 1.6))]),
            node(ShapeDesc::Sphere, 3, vec![scale(Vec3::splat(0.5)), translate(Vec3::new(-2.3, 0.5, 1.5))]),
            node(
                ShapeDesc::Cylinder,
                3,
                vec![scale(Vec3::new(0.45, 1.0, 0.45)), translate(Vec3::new(-3.6, 1.0, -2.0))],
            ),
            node(ShapeDesc::Cone, 1, vec![scale(Vec3::new(0.6, 0.9, 0.6)), translate(Vec3::new(3.4, 0.9, -1.4))]),
            node(
                ShapeDesc::Cube,
                2,
                vec![
                    scale(Vec3::splat(0.6)),
                    TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 },
                    translate(Vec3::new(1.0, 0.6, -2.8)),
                ],
            ),
        ],
        ..Default::default()
    }
}

#[test]
fn whitted_waves_give_the_image_of_rays_traced_one_by_one() {
    let scene = compile(&whitted_room()).unwrap();
    assert!(scene.few_objects.is_some(), "seven analytic objects are few");
    let alone = glint_core::scene::RenderScene { few_objects: None, ..scene.clone() };
    let run = |scene| render(scene, &|_, _| {}, &AtomicBool::new(false)).unwrap();
    let ((waves, wave_stats), (single, single_stats)) = (run(&scene), run(&alone));
    // The same ray trees: camera, reflected, refracted and shadow rays alike.
    assert_eq!(wave_stats.rays, single_stats.rays);
    assert!(single_stats.rays > 3 * 64 * 48, "mirrors, glass and shadows: {}", single_stats.rays);
    // The same terms summed in another order: equal to rounding.
    for (a, b) in waves.pixels.iter().zip(&single.pixels) {
        assert!((*a - *b).abs().max_element() <= 1e-5 * b.max_element().max(1.0), "{a} against {b}");
    }
}
