//! Two-level instancing: a mesh placed several times by transforms renders the same
//! as copies of it with the transforms baked into the vertices.

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::render;
use glint_core::scene::compile;

fn render_desc(desc: &SceneDesc) -> Image {
    let scene = compile(desc).expect("valid scene");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled").0
}

/// An octahedron with smooth vertex normals, counter-clockwise from outside.
fn octahedron() -> MeshDesc {
    let positions = vec![Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];
    let indices = vec![0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
    MeshDesc { name: "octahedron".into(), normals: positions.clone(), positions, indices, ..Default::default() }
}

fn placements() -> Vec<Vec<TransformOp>> {
    vec![
        vec![TransformOp::Translate(Vec3::new(-1.5, 0.0, 0.0))],
        vec![TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 }, TransformOp::Translate(Vec3::new(1.5, 0.2, 0.0))],
        vec![TransformOp::Scale(Vec3::new(0.5, 1.2, 0.5)), TransformOp::Translate(Vec3::new(0.0, -0.3, 1.0))],
    ]
}

fn base() -> SceneDesc {
    SceneDesc {
        settings: RenderSettings { width: 64, height: 48, ..Default::default() },
        lights: vec![LightDesc::Point { position: Vec3::new(3.0, 4.0, 5.0), color: Vec3::ONE, attenuation: Vec3::X }],
        materials: vec![MaterialDesc { specular: Vec3::splat(0.3), ..Default::default() }],
        ..Default::default()
    }
}

fn node(index: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc {
        transform,
        kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index }, material: 0 },
        origin: String::new(),
    }
}

#[test]
fn instanced_mesh_renders_like_its_flattened_copies() {
    let mut instanced = base();
    instanced.meshes.push(octahedron());
    instanced.objects = placements().into_iter().map(|ops| node(0, ops)).collect();

    let mut flattened = base();
    for (i, ops) in placements().into_iter().enumerate() {
        let m = matrix_of(&ops);
        let normal_m = m.inverse().transpose();
        let mut mesh = octahedron();
        mesh.positions.iter_mut().for_each(|p| *p = m.transform_point3(*p));
        mesh.normals.iter_mut().for_each(|n| *n = normal_m.transform_vector3(*n));
        flattened.meshes.push(mesh);
        flattened.objects.push(node(i, vec![]));
    }
    let (a, b) = (render_desc(&instanced), render_desc(&flattened));
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut lit = 0;
    let mut differ = 0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        lit += usize::from(p.max_element() > 0.05);
        differ += usize::from((*p - *q).abs().max_element() > 1e-3);
    }
    assert!(lit > 200, "the meshes are visible: {lit} lit pixels");
    // Only pixels whose sample lands exactly on a silhouette may round differently.
    assert!(differ <= 2, "{differ} pixels differ");
}

#[test]
fn bad_mesh_index_is_a_compile_error() {
    let mut desc = base();
    desc.objects.push(node(3, vec![]));
    let err = compile(&desc).unwrap_err().to_string();
    assert!(err.contains("mesh index 3 out of range"), "{err}");
}

#[test]
fn ten_thousand_instances_share_one_mesh() {
    let mut desc = base();
    desc.meshes.push(octahedron());
    for i in 0..100 {
        for j in 0..100 {
            let at = Vec3::new(i as f32 * 3.0, 0.0, j as f32 * -3.0);
            desc.objects.push(node(0, vec![TransformOp::Scale(Vec3::splat(0.5)), TransformOp::Translate(at)]));
        }
    }
    let scene = compile(&desc).expect("valid scene");
    assert_eq!((scene.meshes.len(), scene.instances.len()), (1, 10_000));
    // A ray down onto instance (57, 31) at (0.1, 0.05) from its centre: the face
    // |x| + |y| + |z| = 1 of the octahedron scaled by 0.5 is at y = 0.5 − 0.15 = 0.35.
    let target = Vec3::new(57.0 * 3.0 + 0.1, 0.0, 31.0 * -3.0 + 0.05);
    let ray = glint_core::math::Ray::new(target + Vec3::Y * 10.0, Vec3::NEG_Y);
    let hit = scene.intersect(&ray, f32::INFINITY).expect("hits the instance below");
    assert!((hit.point.y - 0.35).abs() < 1e-4, "{:?}", hit.point);
    assert!(hit.normal.y > 0.9 && hit.geometric_normal.y > 0.5);
}

#[test]
fn a_mirrored_instance_keeps_its_normals_outside() {
    let mut desc = base();
    desc.meshes.push(octahedron());
    desc.objects.push(node(0, vec![TransformOp::Scale(Vec3::new(-1.0, 1.0, 1.0))]));
    let scene = compile(&desc).expect("valid scene");
    for dir in [Vec3::NEG_X, Vec3::X, Vec3::NEG_Y, Vec3::Z] {
        let ray = glint_core::math::Ray::new(-5.0 * dir + Vec3::new(0.01, 0.02, 0.03), dir);
        let hit = scene.intersect(&ray, f32::INFINITY).expect("hits");
        assert!(hit.normal.dot(dir) < 0.0 && hit.geometric_normal.dot(dir) < 0.0, "{dir}: {hit:?}");
    }
}

/// Camera-ray packets through a scene of instanced meshes, analytic shapes, an
/// unbounded plane and a moving mesh find, ray by ray, the hits single rays find.
#[test]
fn packets_find_what_single_rays_find() {
    let mut desc = base();
    desc.meshes.push(octahedron());
    desc.objects = placements().into_iter().map(|ops| node(0, ops)).collect();
    let shape =
        |shape, transform| NodeDesc { transform, kind: NodeKind::Shape { shape, material: 0 }, origin: String::new() };
    desc.objects.push(shape(ShapeDesc::Sphere, vec![TransformOp::Translate(Vec3::new(0.0, 1.2, -1.0))]));
    desc.objects.push(shape(ShapeDesc::Plane, vec![TransformOp::Translate(Vec3::new(0.0, -1.2, 0.0))]));
    desc.objects.push(NodeDesc {
        transform: vec![TransformOp::Translate(Vec3::new(0.0, 0.0, -2.0))],
        kind: NodeKind::Moving {
            close: vec![TransformOp::Translate(Vec3::new(0.8, 0.0, -2.0))],
            children: vec![node(0, vec![TransformOp::Scale(Vec3::splat(0.7))])],
        },
        origin: String::new(),
    });
    let scene = compile(&desc).expect("valid scene");
    let mut rng = glint_core::sampling::Rng::new(11);
    let mut next = move || rng.next_f32();
    let eye = Vec3::new(0.0, 0.5, 6.0);
    let mut tested = 0;
    for _ in 0..2000 {
        let (cx, cy) = (next() * 2.0 - 1.0, next() * 2.0 - 1.0);
        let rays: Vec<_> = (0..1 + (next() * 8.0) as usize)
            .map(|k| {
                let dir = Vec3::new(cx + 0.01 * k as f32, cy + 0.02 * next(), -1.0);
                let mut ray = glint_core::math::Ray::new(eye, dir);
                ray.time = next();
                ray
            })
            .collect();
        let mut hits = [None; 8];
        scene.intersect_packet(&rays, &mut hits);
        for (ray, packet) in rays.iter().zip(hits) {
            let single = scene.intersect(ray, f32::INFINITY);
            assert_eq!(
                single.map(|h| (h.t, h.point, h.normal, h.material)),
                packet.map(|h| (h.t, h.point, h.normal, h.material))
            );
            tested += usize::from(single.is_some());
        }
    }
    assert!(tested > 3000, "too few rays hit anything: {tested}");
}

/// The octahedron rendered with no highlights, so that a uniform vertex colour `tint`
/// must scale every pixel by exactly `tint` (one convex object: no inter-reflection).
fn tinted_render(tint: Option<Vec3>, integrator: IntegratorDesc) -> Image {
    let mut desc = base();
    desc.settings.integrator = integrator;
    desc.settings.spp = Some(4);
    desc.materials[0] = MaterialDesc { specular: Vec3::ZERO, bsdf: None, ..Default::default() };
    let mut mesh = octahedron();
    if let Some(tint) = tint {
        mesh.colors = vec![tint; mesh.positions.len()];
    }
    desc.meshes.push(mesh);
    desc.objects = vec![node(0, vec![])];
    render_desc(&desc)
}

#[test]
fn a_vertex_colour_tints_the_diffuse_colour_under_both_integrators() {
    let tint = Vec3::new(0.9, 0.4, 0.1);
    for integrator in [IntegratorDesc::Whitted, IntegratorDesc::Path(PathDesc::default())] {
        let plain = tinted_render(None, integrator);
        let tinted = tinted_render(Some(tint), integrator);
        let lit = plain.pixels.iter().filter(|p| p.max_element() > 0.05).count();
        assert!(lit > 100, "{integrator:?}: the octahedron is lit in {lit} pixels");
        for (p, t) in plain.pixels.iter().zip(&tinted.pixels) {
            assert!((*p * tint - *t).abs().max_element() < 1e-4, "{integrator:?}: {p} tinted by {tint} gave {t}");
        }
    }
}

#[test]
fn vertex_colours_are_interpolated_across_the_triangle() {
    let mut desc = base();
    let positions = vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let colors = vec![Vec3::X, Vec3::Y, Vec3::Z];
    desc.meshes.push(MeshDesc { positions, colors, indices: vec![0, 1, 2], ..Default::default() });
    desc.objects = vec![node(0, vec![TransformOp::Scale(Vec3::splat(2.0))])];
    let scene = compile(&desc).unwrap();
    // Straight down the z axis through the centroid (0, −1/3) of the scaled triangle.
    let centroid = Vec3::new(0.0, -2.0 / 3.0, 5.0);
    let hit = scene.intersect(&glint_core::math::Ray::new(centroid, Vec3::NEG_Z), f32::INFINITY).unwrap();
    assert!((hit.color - Vec3::splat(1.0 / 3.0)).abs().max_element() < 1e-5, "{}", hit.color);
    // Near the red corner.
    let corner = Vec3::new(-1.9, -1.95, 5.0);
    let hit = scene.intersect(&glint_core::math::Ray::new(corner, Vec3::NEG_Z), f32::INFINITY).unwrap();
    assert!(hit.color.x > 0.9 && hit.color.y < 0.1, "{}", hit.color);
}

/// A floor lit straight from above through a sphere; `casts_shadows` says whether the
/// sphere may shadow it.
fn shadowed_floor(casts_shadows: bool, integrator: IntegratorDesc) -> Image {
    let ball = MaterialDesc { casts_shadows, specular: Vec3::ZERO, ..Default::default() };
    let floor = MaterialDesc { specular: Vec3::ZERO, ..Default::default() };
    let desc = SceneDesc {
        settings: RenderSettings { width: 32, height: 32, integrator, spp: Some(4), ..Default::default() },
        camera: CameraDesc { eye: Vec3::new(0.0, 6.0, 0.01), look: Vec3::NEG_Y, up: Vec3::Z, ..Default::default() },
        lights: vec![LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::ONE }],
        materials: vec![floor, ball],
        objects: vec![
            NodeDesc {
                transform: vec![TransformOp::Scale(Vec3::splat(5.0))],
                kind: NodeKind::Shape { shape: ShapeDesc::Rectangle, material: 0 },
                origin: String::new(),
            },
            NodeDesc {
                transform: vec![TransformOp::Scale(Vec3::splat(0.5)), TransformOp::Translate(Vec3::new(1.5, 8.0, 0.0))],
                kind: NodeKind::Shape { shape: ShapeDesc::Sphere, material: 1 },
                origin: String::new(),
            },
        ],
        ..Default::default()
    };
    render_desc(&desc)
}

#[test]
fn an_object_that_casts_no_shadow_lets_light_through_under_both_integrators() {
    for integrator in [IntegratorDesc::Whitted, IntegratorDesc::Path(PathDesc { max_depth: 2, ..Default::default() })] {
        let (shadowing, passing) = (shadowed_floor(true, integrator), shadowed_floor(false, integrator));
        // The sphere hangs above the camera, out of its view; its shadow falls on the
        // floor in view. The pixel at the image's centre is floor in the open.
        let open = shadowing.pixels[(16 * 32 + 16) as usize];
        let dark = shadowing.pixels.iter().filter(|p| p.max_element() < 0.1 * open.max_element()).count();
        let dark_passing = passing.pixels.iter().filter(|p| p.max_element() < 0.1 * open.max_element()).count();
        assert!(dark > 4, "{integrator:?}: the sphere shadows the floor in {dark} pixels");
        assert_eq!(dark_passing, 0, "{integrator:?}: a sphere that casts no shadow darkens {dark_passing} pixels");
    }
}

/// A unit quad in z = 0 facing +z, its uvs along x and y (or x and −y, `mirrored`),
/// whose material bends normals by a 1×1 normal map of `texel`.
fn normal_mapped_quad(texel: Vec3, mirrored: bool) -> glint_core::scene::RenderScene {
    let mut desc = base();
    let positions = vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(1.0, -1.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(-1.0, 1.0, 0.0),
    ];
    let v = |y: f32| if mirrored { 1.0 - y } else { y };
    let uvs = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(|(x, y)| glam::Vec2::new(x, v(y))).to_vec();
    let indices = vec![0, 1, 2, 0, 2, 3];
    desc.meshes.push(MeshDesc { positions, uvs, indices, ..Default::default() });
    desc.textures.push(TextureDesc::Image {
        name: "bumps".into(),
        path: String::new(),
        width: 1,
        height: 1,
        texels: vec![texel],
        sampling: Default::default(),
    });
    desc.materials[0].normal_map = Some(NormalMapDesc { texture: 0, scale: 1.0 });
    desc.objects = vec![node(0, vec![TransformOp::Rotate { axis: Vec3::Z, degrees: 90.0 }])];
    compile(&desc).unwrap()
}

#[test]
fn a_normal_map_bends_the_shading_normal_in_the_uv_frame() {
    let ray = glint_core::math::Ray::new(Vec3::new(0.1, 0.2, 3.0), Vec3::NEG_Z);
    let normal = |texel, mirrored| normal_mapped_quad(texel, mirrored).intersect(&ray, f32::INFINITY).unwrap().normal;
    // The flat texel leaves the normal alone.
    assert!((normal(Vec3::new(0.5, 0.5, 1.0), false) - Vec3::Z).length() < 1e-5);
    // Full red turns it onto +u, which the quarter turn about z took to +y.
    let red = normal(Vec3::new(1.0, 0.5, 0.5), false);
    assert!((red - Vec3::Y).length() < 1e-5, "{red}");
    // Full green turns it onto +v: −x after the turn; −v (so +x) when the uvs are mirrored.
    let green = normal(Vec3::new(0.5, 1.0, 0.5), false);
    assert!((green - Vec3::NEG_X).length() < 1e-5, "{green}");
    let mirrored = normal(Vec3::new(0.5, 1.0, 0.5), true);
    assert!((mirrored - Vec3::X).length() < 1e-5, "{mirrored}");
}

#[test]
fn an_image_texture_whose_texels_do_not_fill_it_is_a_compile_error() {
    let mut desc = base();
    desc.textures.push(TextureDesc::Image {
        name: "short".into(),
        path: String::new(),
        width: 4,
        height: 4,
        texels: vec![Vec3::ONE; 15],
        sampling: Default::default(),
    });
    let e = compile(&desc).unwrap_err().to_string();
    assert!(e.contains("short") && e.contains("4×4") && e.contains("15"), "{e}");
}
