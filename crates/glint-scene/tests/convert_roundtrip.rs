//! `glint convert` and the `.glint` writer: `parse(write(desc))` is `desc` again (up to
//! node origins and the renaming of clashing names) and renders the same image.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use glam::{Vec2, Vec3};
use glint_core::desc::{
    AdaptiveDesc, AreaShape, BsdfDesc, CameraDesc, ColorParam, EnvironmentDesc, FilterDesc, FilterKind, IntegratorDesc,
    LightDesc, MaterialDesc, NodeDesc, NodeKind, PathDesc, RenderSettings, SamplePattern, SamplerKind, ScalarParam,
    SceneDesc, ShapeDesc, TextureDesc, Transfer, TransformOp,
};
use glint_core::render::render;
use glint_core::scene::compile;
use glint_scene::convert::{ConvertError, convert};
use glint_scene::native::writer::{WriteOptions, difference, write_scene};
use glint_scene::{default_scene, load_any, load_scene, parse_scene};

/// A fresh folder under the system temp dir, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(test: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("glint-convert-{test}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        Self(dir)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Writes `desc`, reads it back, and checks that nothing that matters changed.
fn round_trip(desc: &SceneDesc) -> SceneDesc {
    let written = write_scene(desc, &WriteOptions::default()).expect("the scene can be written");
    assert!(written.warnings.is_empty(), "{:?}", written.warnings);
    let back = parse_scene(&written.text, "written.glint", Path::new(""))
        .unwrap_or_else(|e| panic!("written text should parse: {e}\n{}", written.text));
    if let Some(d) = difference(desc, &back) {
        panic!("round trip changed the scene: {d}\n{}", written.text);
    }
    back
}

fn draw(desc: &SceneDesc, width: u32, height: u32) -> glint_core::film::Image {
    let mut desc = desc.clone();
    desc.settings.width = width;
    desc.settings.height = height;
    desc.settings.adaptive = None;
    let scene = compile(&desc).expect("scene compiles");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders").0
}

fn assert_same_image(a: &SceneDesc, b: &SceneDesc) {
    let (x, y) = (draw(a, 64, 48), draw(b, 64, 48));
    assert_eq!(x.pixels, y.pixels, "the written scene renders differently");
}

#[test]
fn the_default_scene_round_trips_with_its_names() {
    let desc = default_scene();
    let back = round_trip(&desc);
    let names = |s: &SceneDesc| s.materials.iter().map(|m| m.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&back), names(&desc));
    assert_same_image(&desc, &back);
}

#[test]
fn the_challenge_examples_round_trip() {
    for name in ["spheres", "shapes", "mapped"] {
        let path = scenes_dir().join(format!("challenge/{name}.yml"));
        let loaded = load_any(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(loaded.warnings.is_empty(), "{name}: {:?}", loaded.warnings);
        let back = round_trip(&loaded.scene);
        assert_same_image(&loaded.scene, &back);
    }
}

/// Writes a 2×2 PNG for image textures.
fn write_png(path: &Path) {
    std::fs::create_dir_all(path.parent().expect("a folder")).expect("create folder");
    let pixels = [255, 0, 0, 255, 255, 255, 128, 128, 128, 0, 0, 0];
    image::save_buffer(path, &pixels, 2, 2, image::ExtendedColorType::Rgb8).expect("save png");
}

/// A scene built in code, as an importer of another format would, using every field the
/// description has: odd numbers, clashing names, every light, texture, shape and
/// transform kind, nested groups.
fn everything(texture: &Path) -> SceneDesc {
    let image = glint_scene::texture_io::load_texture("photo", texture).expect("png loads");
    let settings = RenderSettings {
        width: 123,
        height: 45,
        samples_per_axis: 3,
        max_depth: 7,
        min_contribution: 0.1 + 1e-7,
        background: Vec3::new(0.1, 0.2, 0.3),
        ambient_light: Vec3::new(1.0 / 3.0, 0.0, 2.5),
        features: glint_core::desc::Features {
            shadows: false,
            reflections: true,
            refractions: false,
            textures: true,
            transparent_shadows: true,
        },
        output_transfer: Transfer::Identity,
        pattern: SamplePattern::Sobol,
        filter: FilterDesc { kind: FilterKind::Gaussian, radius: 1.25 },
        adaptive: Some(AdaptiveDesc { min_samples: 2, max_samples: 32, threshold: 0.005 }),
        seed: 77,
        integrator: IntegratorDesc::Path(PathDesc { max_depth: 13, rr_depth: 7, sampler: SamplerKind::Independent }),
        spp: Some(37),
        fps: 30.0,
        frames: Some([3, 90]),
    };
    let camera = CameraDesc {
        eye: Vec3::new(0.3, 2.0, 9.5),
        look: Vec3::new(-0.1, -0.2, -1.0),
        up: Vec3::new(0.0, 1.0, 0.1),
        fov_y_degrees: 38.5,
        fov_axis: glint_core::desc::FovAxis::Y,
        aperture_radius: 0.05,
        focal_distance: 9.0,
    };
    let lights = vec![
        LightDesc::Point {
            position: Vec3::new(1.0, 5.0, 2.0),
            color: Vec3::splat(0.7),
            attenuation: Vec3::new(1.0, 0.1, 0.01),
        },
        LightDesc::Directional { direction: Vec3::new(1.0, -1.0, -1.0), color: Vec3::new(0.2, 0.25, 0.3) },
        LightDesc::Spot {
            position: Vec3::new(0.0, 6.0, 0.0),
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            attenuation: Vec3::X,
            angle_degrees: 25.0,
            penumbra_degrees: 4.5,
            falloff: glint_core::desc::SpotFalloff::Linear,
        },
        LightDesc::Area {
            shape: AreaShape::Rectangle {
                corner: Vec3::new(-1.0, 4.0, -1.0),
                edge_u: Vec3::X * 2.0,
                edge_v: Vec3::Z * 2.0,
            },
            color: Vec3::splat(0.5),
            attenuation: Vec3::X,
            samples: 3,
        },
        LightDesc::Area {
            shape: AreaShape::Disk { center: Vec3::new(2.0, 3.0, 0.0), normal: Vec3::NEG_Y, radius: 0.5 },
            color: Vec3::splat(0.3),
            attenuation: Vec3::X,
            samples: 2,
        },
        LightDesc::Area {
            shape: AreaShape::Sphere { center: Vec3::new(-2.0, 3.0, 1.0), radius: 0.25 },
            color: Vec3::splat(0.2),
            attenuation: Vec3::new(0.5, 0.0, 0.1),
            samples: 1,
        },
        LightDesc::Environment(EnvironmentDesc {
            radiance: Vec3::new(0.7, 1.0 / 3.0, 2.5),
            texture: Some(1),
            transform: vec![
                TransformOp::Rotate { axis: Vec3::new(0.0, 1.0, 0.1), degrees: -47.5 },
                TransformOp::Scale(Vec3::new(-1.0, 1.0, 1.0)),
            ],
        }),
    ];
    let textures = vec![
        TextureDesc::Checker {
            name: "checks".into(),
            even: Vec3::ONE,
            odd: Vec3::ZERO,
            cells: Vec2::new(3.0, 5.0),
            filtered: true,
        },
        image,
    ];
    let materials = vec![
        MaterialDesc { name: "plain".into(), ..MaterialDesc::default() },
        MaterialDesc {
            name: "say \"cheese\"".into(),
            ka: 0.2,
            kd: 0.6,
            ks: 0.33,
            kt: 0.9,
            ambient: Some(Vec3::new(0.1, 0.0, 0.0)),
            diffuse: Vec3::new(0.7, 0.1, 0.05),
            specular: Vec3::splat(0.4),
            reflective: Some(Vec3::splat(0.25)),
            transmissive: Vec3::new(0.5, 0.6, 0.7),
            shininess: 17.5,
            ior: 1.45,
            texture: Some(1),
            blend: 0.4,
            texture_repeat: Vec2::new(2.0, 0.5),
            bsdf: Some(BsdfDesc::Plastic {
                diffuse: ColorParam { value: Vec3::new(0.6, 0.2, 0.1), texture: Some(1) },
                int_ior: 1.49,
                ext_ior: 1.000277,
                specular: Vec3::splat(0.7),
                alpha: ScalarParam { value: 0.15, texture: Some(0) },
                nonlinear: true,
            }),
            emission: Vec3::new(0.1, 2.0, 17.5),
            two_sided: false,
            microfacet: glint_core::desc::MicrofacetKind::Beckmann,
            casts_shadows: false,
            normal_map: Some(glint_core::desc::NormalMapDesc { texture: 0, scale: 0.75 }),
            emission_texture: Some(0),
            highlight: glint_core::desc::Highlight::Blinn,
            textured_ambient: true,
        },
        MaterialDesc { name: "plain".into(), texture: Some(0), diffuse: Vec3::splat(0.5), ..MaterialDesc::default() },
        MaterialDesc { name: String::new(), ..MaterialDesc::default() },
        MaterialDesc {
            name: "rough gold".into(),
            bsdf: Some(BsdfDesc::Conductor {
                eta: Vec3::new(0.143, 0.3749, 1.4424),
                k: Vec3::new(3.983, 2.3857, 1.6032),
                specular: ColorParam { value: Vec3::new(0.9, 0.95, 1.0), texture: Some(0) },
                alpha: ScalarParam { value: 0.3, texture: Some(1) },
            }),
            ..MaterialDesc::default()
        },
        MaterialDesc {
            name: "glass".into(),
            bsdf: Some(BsdfDesc::Dielectric {
                int_ior: 1.5046,
                ext_ior: 1.33,
                reflectance: Vec3::new(0.9, 1.0, 0.8),
                transmittance: Vec3::new(0.5, 0.75, 1.0),
                alpha: ScalarParam::constant(0.01),
            }),
            two_sided: false,
            ..MaterialDesc::default()
        },
        MaterialDesc {
            name: "pane".into(),
            bsdf: Some(BsdfDesc::ThinDielectric {
                int_ior: 1.6,
                ext_ior: 1.1,
                reflectance: Vec3::splat(0.3),
                transmittance: Vec3::new(1.0, 0.9, 0.8),
            }),
            ..MaterialDesc::default()
        },
        MaterialDesc {
            name: "lamp".into(),
            bsdf: Some(BsdfDesc::Diffuse { reflectance: ColorParam::constant(Vec3::new(0.25, 0.5, 0.125)) }),
            emission: Vec3::new(17.0, 12.0, 4.0),
            two_sided: false,
            ..MaterialDesc::default()
        },
        MaterialDesc {
            name: "textured lambert".into(),
            bsdf: Some(BsdfDesc::Diffuse { reflectance: ColorParam { value: Vec3::ONE, texture: Some(0) } }),
            ..MaterialDesc::default()
        },
        MaterialDesc {
            name: "car paint".into(),
            bsdf: Some(BsdfDesc::MetallicRoughness {
                base: ColorParam { value: Vec3::new(0.8, 0.1, 0.05), texture: Some(0) },
                metallic: ScalarParam { value: 0.35, texture: Some(1) },
                alpha: ScalarParam { value: 0.2, texture: Some(1) },
                ior: 1.45,
            }),
            ..MaterialDesc::default()
        },
    ];
    let leaf = |shape, material, transform| NodeDesc {
        transform,
        kind: NodeKind::Shape { shape, material },
        origin: "code".into(),
    };
    let matrix = [[1.0, 0.5, 0.0, 0.25], [0.0, 1.0, 0.0, 0.0], [0.0, 0.1, 2.0, -1.0], [0.0, 0.0, 0.0, 1.0]];
    let objects = vec![
        leaf(ShapeDesc::Plane, 2, vec![]),
        leaf(
            ShapeDesc::Sphere,
            1,
            vec![TransformOp::Scale(Vec3::splat(0.75)), TransformOp::Translate(Vec3::new(1.0, 0.75, 0.0))],
        ),
        NodeDesc {
            transform: vec![
                TransformOp::Rotate { axis: Vec3::new(0.0, 1.0, 0.2), degrees: 33.3 },
                TransformOp::Matrix(matrix),
            ],
            kind: NodeKind::Group(vec![
                leaf(ShapeDesc::Cube, 0, vec![TransformOp::Scale(Vec3::new(0.3, -0.4, 0.5))]),
                leaf(ShapeDesc::Cylinder, 3, vec![]),
                NodeDesc {
                    transform: vec![TransformOp::Translate(Vec3::new(-2.0, 0.0, 0.0))],
                    kind: NodeKind::Group(vec![
                        leaf(ShapeDesc::Cone, 0, vec![]),
                        leaf(ShapeDesc::Disk, 1, vec![TransformOp::Translate(Vec3::Y * 0.01)]),
                        leaf(ShapeDesc::Torus { minor_radius: 0.3 }, 2, vec![]),
                        leaf(ShapeDesc::Sphere, 4, vec![TransformOp::Translate(Vec3::new(0.0, 2.0, 0.0))]),
                        leaf(ShapeDesc::Sphere, 5, vec![TransformOp::Scale(Vec3::splat(0.4))]),
                        leaf(ShapeDesc::Cube, 6, vec![TransformOp::Scale(Vec3::new(1.0, 0.01, 1.0))]),
                        leaf(ShapeDesc::Rectangle, 7, vec![TransformOp::Translate(Vec3::new(0.0, 3.0, 0.0))]),
                        leaf(ShapeDesc::Sphere, 8, vec![TransformOp::Translate(Vec3::new(3.0, 0.5, 0.0))]),
                        leaf(ShapeDesc::Sphere, 9, vec![TransformOp::Translate(Vec3::new(-3.0, 0.5, 0.0))]),
                    ]),
                    origin: "code".into(),
                },
                NodeDesc { transform: vec![], kind: NodeKind::Group(vec![]), origin: "code".into() },
            ]),
            origin: "code".into(),
        },
    ];
    SceneDesc { settings, camera, lights, materials, textures, objects, ..SceneDesc::default() }
}

#[test]
fn a_scene_using_every_field_round_trips() {
    let dir = TempDir::new("everything");
    let texture = dir.0.join("tex/photo.png");
    write_png(&texture);
    let desc = everything(&texture);
    let back = round_trip(&desc);
    // Clashing and unwritable names are made unique; the rest are kept.
    let names: Vec<&str> = back.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "plain",
            "say \"cheese\"",
            "plain-2",
            "material-4",
            "rough gold",
            "glass",
            "pane",
            "lamp",
            "textured lambert",
            "car paint"
        ]
    );
    // The new fields are really there, not defaults that match by accident.
    assert!(matches!(back.settings.integrator, IntegratorDesc::Path(PathDesc { max_depth: 13, .. })));
    assert!(back.lights.iter().any(|l| matches!(l, LightDesc::Environment(_))));
    assert_same_image(&desc, &back);
}

#[test]
fn convert_writes_a_glint_file_that_loads_as_the_same_scene() {
    let dir = TempDir::new("yaml");
    let input = scenes_dir().join("challenge/spheres.yml");
    let output = dir.0.join("out/spheres.glint");
    std::fs::create_dir_all(output.parent().unwrap()).unwrap();
    let converted = convert(&input, &output).expect("converts");
    assert!(converted.warnings.is_empty(), "{:?}", converted.warnings);
    let back = load_scene(&output).expect("the written file loads");
    let original = load_any(&input).unwrap().scene;
    assert_eq!(difference(&original, &back), None);
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(text.starts_with("# Converted by `glint convert` from "), "{text}");
    // Written through a temporary file that is gone afterwards.
    let leftovers: Vec<_> =
        std::fs::read_dir(output.parent().unwrap()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers, vec![std::ffi::OsString::from("spheres.glint")]);
}

#[test]
fn image_textures_are_referenced_relative_to_the_output() {
    let dir = TempDir::new("texture");
    write_png(&dir.0.join("scene/tex/wood.png"));
    let input = dir.0.join("scene/table.glint");
    std::fs::write(
        &input,
        "texture \"wood\" image { file \"tex/wood.png\" }\nmaterial \"m\" { texture \"wood\" }\nsphere { material \"m\" }\n",
    )
    .unwrap();
    let output = dir.0.join("converted/table.glint");
    std::fs::create_dir_all(output.parent().unwrap()).unwrap();
    convert(&input, &output).expect("converts");
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(text.contains("file \"../scene/tex/wood.png\""), "{text}");
    let back = load_scene(&output).expect("loads from its new folder");
    assert_eq!(difference(&load_scene(&input).unwrap(), &back), None);
}

#[test]
fn convert_refuses_bad_outputs_and_inputs_without_writing() {
    let dir = TempDir::new("errors");
    let input = scenes_dir().join("challenge/spheres.yml");
    let err = convert(&input, &dir.0.join("out.png")).expect_err("not a .glint name");
    assert!(matches!(err, ConvertError::NotGlint { .. }), "{err}");
    assert!(err.to_string().contains("out.glint"), "{err}");
    let bad = dir.0.join("bad.yml");
    std::fs::write(&bad, "- add: camera\n  width: x\n").unwrap();
    let err = convert(&bad, &dir.0.join("bad.glint")).expect_err("input error");
    assert!(err.to_string().starts_with(&format!("{}:2:10: ", bad.display())), "{err}");
    let err = convert(&dir.0.join("missing.yml"), &dir.0.join("missing.glint")).expect_err("no input");
    assert!(err.to_string().contains("cannot read scene file"), "{err}");
    let entries: Vec<_> = std::fs::read_dir(&dir.0).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(entries, vec![std::ffi::OsString::from("bad.yml")], "nothing was written");
}

/// A glTF model whose metallic-roughness texture glint splits into two derived
/// textures (roughness² from green, metallic from blue): their texels are not the
/// file's, so convert refuses in one sentence naming the texture, not as a bug.
#[test]
fn derived_gltf_textures_are_refused_by_name() {
    let dir = TempDir::new("gltf");
    write_png(&dir.0.join("mr.png"));
    let mut buffer = Vec::new();
    for x in [0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0] {
        buffer.extend_from_slice(&x.to_le_bytes());
    }
    std::fs::write(dir.0.join("model.bin"), &buffer).unwrap();
    let gltf = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"metallicFactor":0.5,"metallicRoughnessTexture":{"index":0}}}],
"textures":[{"source":0}],"images":[{"uri":"mr.png"}],
"buffers":[{"byteLength":60,"uri":"model.bin"}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}]}"#;
    let input = dir.0.join("model.gltf");
    std::fs::write(&input, gltf).unwrap();
    let err = convert(&input, &dir.0.join("model.glint")).expect_err("derived texels cannot be named").to_string();
    assert!(err.contains("has no source file, so a .glint file cannot refer to it"), "{err}");
    assert!(!err.contains("bug in glint"), "{err}");
    assert!(!dir.0.join("model.glint").exists());
}

#[test]
fn solid_and_mesh_examples_round_trip() {
    for name in ["csg", "blobs", "implicit", "mesh-instances", "motion-blur", "soft-shadows", "cornell-path"] {
        let path = scenes_dir().join(format!("{name}.glint"));
        let desc = load_scene(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        // Written beside the examples, so mesh files are named relative to them.
        let options = WriteOptions { base_dir: Some(scenes_dir()), ..WriteOptions::default() };
        let written = write_scene(&desc, &options).unwrap_or_else(|e| panic!("{name}: {e}"));
        let back = parse_scene(&written.text, "written.glint", &scenes_dir())
            .unwrap_or_else(|e| panic!("{name}: written text should parse: {e}\n{}", written.text));
        if name != "mesh-instances" {
            // Meshes come back with the path as written; everything else is identical.
            if let Some(d) = difference(&desc, &back) {
                panic!("{name}: round trip changed the scene: {d}\n{}", written.text);
            }
        }
        assert_eq!(back.meshes.len(), desc.meshes.len());
        assert!(
            back.meshes.iter().zip(&desc.meshes).all(|(a, b)| a.positions == b.positions && a.indices == b.indices)
        );
        assert_same_image(&desc, &back);
    }
}

#[test]
fn meshes_that_are_not_whole_files_are_refused_with_a_reason() {
    let mut desc = default_scene();
    desc.meshes.push(glint_core::desc::MeshDesc {
        name: "tri".into(),
        positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
        indices: vec![0, 1, 2],
        ..Default::default()
    });
    let err = write_scene(&desc, &WriteOptions::default()).unwrap_err().to_string();
    assert!(err.contains("built in code"), "{err}");
}

#[test]
fn unlimited_path_depth_round_trips_and_too_deep_ones_are_reported() {
    let mut desc = default_scene();
    desc.settings.integrator = IntegratorDesc::Path(PathDesc::default());
    let back = round_trip(&desc);
    assert_eq!(back.settings.integrator, IntegratorDesc::Path(PathDesc { max_depth: u32::MAX, ..PathDesc::default() }));
    let written = write_scene(&desc, &WriteOptions::default()).unwrap();
    assert!(
        written.text.contains("integrator path { max_depth -1  rr_depth 5  sampler \"sobol\" }"),
        "{}",
        written.text
    );

    desc.settings.integrator = IntegratorDesc::Path(PathDesc { max_depth: 1 << 30, ..PathDesc::default() });
    let written = write_scene(&desc, &WriteOptions::default()).unwrap();
    assert_eq!(written.warnings.len(), 1, "{:?}", written.warnings);
    assert!(written.warnings[0].contains("written as unlimited"), "{:?}", written.warnings);
}

/// The Mitsuba 3 validation scenes (bench/mitsuba) convert to native files that render
/// the same path-traced image, meshes, environment map and all.
#[test]
fn mitsuba_scenes_convert_to_native_files_that_render_the_same() {
    let bench = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../bench/mitsuba");
    let dir = TempDir::new("mitsuba");
    for name in ["cornell", "glass-metal", "envmap", "emissive-mesh"] {
        let output = dir.0.join(format!("{name}.glint"));
        convert(&bench.join(format!("{name}.xml")), &output).unwrap_or_else(|e| panic!("{name}: {e}"));
        let original = load_any(&bench.join(format!("{name}.xml"))).unwrap().scene;
        let back = load_scene(&output).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (mut a, mut b) = (original, back);
        for d in [&mut a, &mut b] {
            d.settings.spp = Some(2);
        }
        let (x, y) = (draw(&a, 32, 24), draw(&b, 32, 24));
        assert_eq!(x.pixels, y.pixels, "{name}: the converted scene renders differently");
        assert!(x.pixels.iter().any(|p| p.max_element() > 0.0), "{name}: renders black");
    }
}
