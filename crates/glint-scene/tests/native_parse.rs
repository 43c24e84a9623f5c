//! The native `.glint` format: every node and property reaches the `SceneDesc` with the
//! value written, or with its documented default when it is left out.

use std::path::Path;

use glam::{Vec2, Vec3};
use glint_core::desc::{
    BsdfDesc, CameraDesc, ColorParam, EnvironmentDesc, Features, IntegratorDesc, LightDesc, MaterialDesc, NodeDesc,
    NodeKind, PathDesc, RenderSettings, SamplerKind, ScalarParam, SceneDesc, ShapeDesc, TextureDesc, Transfer,
    TransformOp,
};
use glint_scene::{default_scene, parse_scene};

fn parse(source: &str) -> SceneDesc {
    parse_scene(source, "test.glint", Path::new("")).unwrap_or_else(|e| panic!("scene should parse, got: {e}"))
}

/// The shape and material of a node that must be a shape.
fn shape_of(node: &NodeDesc) -> (ShapeDesc, usize) {
    match &node.kind {
        NodeKind::Shape { shape, material } => (*shape, *material),
        NodeKind::Group(_) => panic!("expected a shape, found a group at {}", node.origin),
        NodeKind::Solid(_) => panic!("expected a shape, found a solid at {}", node.origin),
        NodeKind::Moving { .. } => panic!("expected a shape, found a moving group at {}", node.origin),
    }
}

/// The children of a node that must be a group.
fn children_of(node: &NodeDesc) -> &[NodeDesc] {
    match &node.kind {
        NodeKind::Group(children) | NodeKind::Moving { children, .. } => children,
        NodeKind::Shape { .. } => panic!("expected a group, found a shape at {}", node.origin),
        NodeKind::Solid(_) => panic!("expected a group, found a solid at {}", node.origin),
    }
}

/// The same tree without origins, to compare nodes written in different places.
fn without_origins(nodes: &[NodeDesc]) -> Vec<NodeDesc> {
    nodes
        .iter()
        .map(|n| NodeDesc {
            transform: n.transform.clone(),
            kind: match &n.kind {
                NodeKind::Group(children) => NodeKind::Group(without_origins(children)),
                shape => shape.clone(),
            },
            origin: String::new(),
        })
        .collect()
}

#[test]
fn an_empty_file_is_the_default_scene_description() {
    let scene = parse("# nothing but a comment\n\n");
    assert_eq!(scene, SceneDesc::default());
    assert_eq!(scene.settings.width, 800);
    assert_eq!(scene.camera.fov_y_degrees, 45.0);
}

#[test]
fn settings_properties() {
    let scene = parse(
        "settings { width 320 height 2.4e2 samples 3 max_depth 7 min_contribution 0.01 \
         background [0.1, 0.2, 0.3] ambient 0.25 shadows false reflections true refractions false \
         textures false output_transfer \"identity\" }",
    );
    assert_eq!(
        scene.settings,
        RenderSettings {
            width: 320,
            height: 240,
            samples_per_axis: 3,
            max_depth: 7,
            min_contribution: 0.01,
            background: Vec3::new(0.1, 0.2, 0.3),
            ambient_light: Vec3::splat(0.25),
            features: Features {
                shadows: false,
                reflections: true,
                refractions: false,
                textures: false,
                transparent_shadows: true
            },
            output_transfer: Transfer::Identity,
            ..RenderSettings::default()
        }
    );
}

#[test]
fn settings_left_out_keep_their_defaults() {
    let scene = parse("settings { width 64 }");
    assert_eq!(scene.settings, RenderSettings { width: 64, ..RenderSettings::default() });
}

#[test]
fn camera_look_at_becomes_a_direction() {
    let scene = parse("camera { eye [0 2 8] look_at [0 1 0] up [0 1 0] fov 30 }");
    assert_eq!(
        scene.camera,
        CameraDesc {
            eye: Vec3::new(0.0, 2.0, 8.0),
            look: Vec3::new(0.0, -1.0, -8.0),
            up: Vec3::Y,
            fov_y_degrees: 30.0,
            fov_axis: glint_core::desc::FovAxis::Y,
            aperture_radius: 0.0,
            focal_distance: Vec3::new(0.0, -1.0, -8.0).length(),
        }
    );
}

#[test]
fn moving_groups_have_an_open_and_a_close_pose() {
    let scene = parse("moving { translate [1 0 0] close { translate [2 0 0] rotate [0 1 0] 90 } sphere { } }");
    let NodeKind::Moving { close, children } = &scene.objects[0].kind else { panic!("expected a moving group") };
    assert_eq!(scene.objects[0].transform, vec![TransformOp::Translate(Vec3::X)]);
    assert_eq!(
        close,
        &vec![TransformOp::Translate(Vec3::new(2.0, 0.0, 0.0)), TransformOp::Rotate { axis: Vec3::Y, degrees: 90.0 }]
    );
    assert_eq!(shape_of(&children[0]).0, ShapeDesc::Sphere);
    let err = parse_scene("moving { sphere { } }", "m.glint", Path::new(".")).unwrap_err();
    assert_eq!((err.line, err.column), (1, 1));
    assert!(err.message.contains("close"), "{err}");
}

#[test]
fn sampling_lens_and_area_light_properties() {
    let scene = parse(
        "settings { samples 3 pattern \"sobol\" filter \"mitchell\" filter_radius 2 adaptive [4 64 0.02] seed 7 }
         camera { eye [0 0 5] look_at [0 0 0] aperture 0.1 }
         light rectangle { corner [-1 4 -1] edge_u [2 0 0] edge_v [0 0 2] color 0.5 samples 3 }
         light disk { position [0 3 0] normal [0 -1 0] radius 0.25 }
         light sphere { position [1 3 0] radius 0.5 samples 2 }",
    );
    let s = &scene.settings;
    assert_eq!(s.pattern, glint_core::desc::SamplePattern::Sobol);
    assert_eq!(s.filter, glint_core::desc::FilterDesc { kind: glint_core::desc::FilterKind::Mitchell, radius: 2.0 });
    assert_eq!(s.adaptive, Some(glint_core::desc::AdaptiveDesc { min_samples: 4, max_samples: 64, threshold: 0.02 }));
    assert_eq!(s.seed, 7);
    assert_eq!((scene.camera.aperture_radius, scene.camera.focal_distance), (0.1, 5.0));
    use glint_core::desc::AreaShape;
    assert_eq!(
        scene.lights[0],
        LightDesc::Area {
            shape: AreaShape::Rectangle {
                corner: Vec3::new(-1.0, 4.0, -1.0),
                edge_u: 2.0 * Vec3::X,
                edge_v: 2.0 * Vec3::Z
            },
            color: Vec3::splat(0.5),
            attenuation: Vec3::X,
            samples: 3,
        }
    );
    assert!(matches!(scene.lights[1], LightDesc::Area { shape: AreaShape::Disk { radius: 0.25, .. }, samples: 4, .. }));
    assert!(matches!(
        scene.lights[2],
        LightDesc::Area { shape: AreaShape::Sphere { radius: 0.5, .. }, samples: 2, .. }
    ));
}

#[test]
fn camera_look_direction_and_defaults() {
    let scene = parse("camera { look [1 0 0] }");
    assert_eq!(scene.camera, CameraDesc { look: Vec3::X, ..CameraDesc::default() });
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 0.0, 5.0));
}

#[test]
fn checker_texture_with_values_and_defaults() {
    let scene = parse(
        "texture \"checks\" checker { even [0.9 0.9 0.9] odd [0.1 0.2 0.3] cells [8 4] filtered true }\n\
         texture \"plain\" checker",
    );
    assert_eq!(
        scene.textures,
        vec![
            TextureDesc::Checker {
                name: "checks".into(),
                even: Vec3::splat(0.9),
                odd: Vec3::new(0.1, 0.2, 0.3),
                cells: Vec2::new(8.0, 4.0),
                filtered: true,
            },
            TextureDesc::Checker {
                name: "plain".into(),
                even: Vec3::splat(0.9),
                odd: Vec3::splat(0.1),
                cells: Vec2::splat(8.0),
                filtered: false,
            },
        ]
    );
}

#[test]
fn material_with_every_property() {
    let scene = parse(
        "texture \"a\" checker {}\n\
         texture \"checks\" checker { cells 2 }\n\
         material \"floor\" { diffuse [1 0.5 0.25] specular 0.5 shininess 200 reflective [0.1 0.1 0.1] \
         transmissive [0.9 0.8 0.7] ior 1.5 ambient [0.2 0.2 0.2] ka 0.5 kd 0.6 ks 0.7 kt 0.8 \
         texture \"checks\" blend 0.75 repeat [4 2] highlight \"blinn\" textured_ambient true }",
    );
    assert_eq!(
        scene.materials,
        vec![MaterialDesc {
            name: "floor".into(),
            ka: 0.5,
            kd: 0.6,
            ks: 0.7,
            kt: 0.8,
            ambient: Some(Vec3::splat(0.2)),
            diffuse: Vec3::new(1.0, 0.5, 0.25),
            specular: Vec3::splat(0.5),
            reflective: Some(Vec3::splat(0.1)),
            transmissive: Vec3::new(0.9, 0.8, 0.7),
            shininess: 200.0,
            ior: 1.5,
            texture: Some(1),
            blend: 0.75,
            texture_repeat: Vec2::new(4.0, 2.0),
            highlight: glint_core::desc::Highlight::Blinn,
            textured_ambient: true,
            ..MaterialDesc::default()
        }]
    );
}

#[test]
fn material_left_empty_has_the_documented_defaults() {
    let scene = parse("material \"plain\" {}  material \"bare\"  material \"rep\" { repeat 3 }");
    let expected = |name: &str| MaterialDesc { name: name.into(), ..MaterialDesc::default() };
    assert_eq!(scene.materials[0], expected("plain"));
    assert_eq!(scene.materials[1], expected("bare"));
    assert_eq!(scene.materials[2].texture_repeat, Vec2::splat(3.0));
    assert_eq!(scene.materials[0].diffuse, Vec3::splat(0.8));
    assert_eq!(scene.materials[0].reflective, None);
}

#[test]
fn lights_of_every_kind() {
    let scene = parse(
        "light point { position [5 10 5] color [1 0.5 0.25] attenuation [1 0.1 0.01] }\n\
         light directional { direction [-1 -1 -1] color 0.5 }\n\
         light spot { position [0 4 0] direction [0 -1 0] color [1 1 1] attenuation [1 0 0] \
         angle 25 penumbra 4 }",
    );
    assert_eq!(
        scene.lights,
        vec![
            LightDesc::Point {
                position: Vec3::new(5.0, 10.0, 5.0),
                color: Vec3::new(1.0, 0.5, 0.25),
                attenuation: Vec3::new(1.0, 0.1, 0.01),
            },
            LightDesc::Directional { direction: Vec3::splat(-1.0), color: Vec3::splat(0.5) },
            LightDesc::Spot {
                position: Vec3::new(0.0, 4.0, 0.0),
                direction: Vec3::NEG_Y,
                color: Vec3::ONE,
                attenuation: Vec3::X,
                angle_degrees: 25.0,
                penumbra_degrees: 4.0,
                falloff: glint_core::desc::SpotFalloff::Smooth,
            },
        ]
    );
}

#[test]
fn light_defaults() {
    let scene = parse("light point {} light directional light spot {}");
    assert_eq!(
        scene.lights,
        vec![
            LightDesc::Point { position: Vec3::ZERO, color: Vec3::ONE, attenuation: Vec3::X },
            LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::ONE },
            LightDesc::Spot {
                position: Vec3::ZERO,
                direction: Vec3::NEG_Y,
                color: Vec3::ONE,
                attenuation: Vec3::X,
                angle_degrees: 30.0,
                penumbra_degrees: 5.0,
                falloff: glint_core::desc::SpotFalloff::Smooth,
            },
        ]
    );
}

#[test]
fn every_shape_maps_to_its_desc() {
    let scene = parse(
        "material \"m\" {}\n\
         sphere { material \"m\" } cube {} cylinder {} cone {} plane {} disk {} rectangle {}\n\
         torus { minor_radius 0.4 } torus",
    );
    let shapes: Vec<ShapeDesc> = scene.objects.iter().map(|n| shape_of(n).0).collect();
    assert_eq!(
        shapes,
        vec![
            ShapeDesc::Sphere,
            ShapeDesc::Cube,
            ShapeDesc::Cylinder,
            ShapeDesc::Cone,
            ShapeDesc::Plane,
            ShapeDesc::Disk,
            ShapeDesc::Rectangle,
            ShapeDesc::Torus { minor_radius: 0.4 },
            ShapeDesc::Torus { minor_radius: 0.25 },
        ]
    );
    assert!(scene.objects.iter().all(|n| n.transform.is_empty()));
}

#[test]
fn objects_without_material_share_one_lazily_created_default() {
    let scene = parse("material \"m\" { diffuse [1 0 0] }\nsphere { material \"m\" }\ncube {}\ndisk {}");
    assert_eq!(scene.materials.len(), 2);
    assert_eq!(scene.materials[1], MaterialDesc { name: "default".into(), ..MaterialDesc::default() });
    let materials: Vec<usize> = scene.objects.iter().map(|n| shape_of(n).1).collect();
    assert_eq!(materials, vec![0, 1, 1]);

    // No object without a material: no default material at all.
    assert_eq!(parse("material \"m\" {} sphere { material \"m\" }").materials.len(), 1);
}

#[test]
fn a_material_named_default_replaces_the_built_in_one() {
    let scene = parse("material \"default\" { diffuse [0 0 1] }\ncube {}");
    assert_eq!(scene.materials.len(), 1);
    assert_eq!(scene.materials[0].diffuse, Vec3::Z);
    assert_eq!(shape_of(&scene.objects[0]).1, 0);
}

#[test]
fn transforms_keep_their_written_order() {
    let scene = parse(
        "sphere { scale [1 2 3] rotate [0 1 0] 30 translate [0 1 0] scale 2 \
         matrix [1 0 0 4  0 1 0 5  0 0 1 6  0 0 0 1] rotate [1, 0, 0] -90 }",
    );
    assert_eq!(
        scene.objects[0].transform,
        vec![
            TransformOp::Scale(Vec3::new(1.0, 2.0, 3.0)),
            TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 },
            TransformOp::Translate(Vec3::Y),
            TransformOp::Scale(Vec3::splat(2.0)),
            TransformOp::Matrix([
                [1.0, 0.0, 0.0, 4.0],
                [0.0, 1.0, 0.0, 5.0],
                [0.0, 0.0, 1.0, 6.0],
                [0.0, 0.0, 0.0, 1.0],
            ]),
            TransformOp::Rotate { axis: Vec3::X, degrees: -90.0 },
        ]
    );
}

#[test]
fn groups_nest_and_carry_their_own_transforms() {
    let scene = parse(
        "material \"red\" {}\n\
         group { rotate [0 1 0] 30  scale [1 2 1]  cube { material \"red\" }  sphere { }\n\
           group { translate [1 0 0] disk {} } }",
    );
    assert_eq!(scene.objects.len(), 1);
    let group = &scene.objects[0];
    assert_eq!(
        group.transform,
        vec![TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 }, TransformOp::Scale(Vec3::new(1.0, 2.0, 1.0)),]
    );
    let children = children_of(group);
    assert_eq!(children.len(), 3);
    assert_eq!(shape_of(&children[0]), (ShapeDesc::Cube, 0));
    assert_eq!(shape_of(&children[1]), (ShapeDesc::Sphere, 1));
    assert_eq!(children[2].transform, vec![TransformOp::Translate(Vec3::X)]);
    assert_eq!(shape_of(&children_of(&children[2])[0]).0, ShapeDesc::Disk);
}

#[test]
fn use_of_a_define_equals_writing_the_objects_out() {
    let defined = parse(
        "material \"bark\" {}\n\
         define \"tree\" { cylinder { material \"bark\" scale [0.1 1 0.1] } cone { translate [0 2 0] } }\n\
         use \"tree\" { translate [3 0 0] }\n\
         use \"tree\" { rotate [0 1 0] 90 translate [-3 0 0] }\n\
         use \"tree\"",
    );
    let written = parse(
        "material \"bark\" {}\n\
         group { translate [3 0 0] cylinder { material \"bark\" scale [0.1 1 0.1] } cone { translate [0 2 0] } }\n\
         group { rotate [0 1 0] 90 translate [-3 0 0] \
           cylinder { material \"bark\" scale [0.1 1 0.1] } cone { translate [0 2 0] } }\n\
         group { cylinder { material \"bark\" scale [0.1 1 0.1] } cone { translate [0 2 0] } }",
    );
    assert_eq!(defined.objects.len(), 3);
    assert_eq!(defined.materials, written.materials);
    assert_eq!(without_origins(&defined.objects), without_origins(&written.objects));
    // The copies point back at the definition, the use node at itself.
    assert_eq!(defined.objects[1].origin, "test.glint:4:1");
    assert_eq!(children_of(&defined.objects[1])[0].origin, "test.glint:2:17");
}

#[test]
fn a_define_alone_places_nothing() {
    let scene = parse("define \"tree\" { cube {} }");
    assert!(scene.objects.is_empty());
}

#[test]
fn defines_can_use_earlier_defines() {
    let scene = parse("define \"a\" { sphere {} }\ndefine \"b\" { use \"a\" { scale 2 } cube {} }\nuse \"b\"");
    let b = children_of(&scene.objects[0]);
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].transform, vec![TransformOp::Scale(Vec3::splat(2.0))]);
    assert_eq!(shape_of(&children_of(&b[0])[0]).0, ShapeDesc::Sphere);
}

#[test]
fn origins_name_file_line_and_column() {
    let scene = parse("\n  sphere {}\n\tgroup { cube {} }");
    assert_eq!(scene.objects[0].origin, "test.glint:2:3");
    assert_eq!(scene.objects[1].origin, "test.glint:3:2");
    assert_eq!(children_of(&scene.objects[1])[0].origin, "test.glint:3:10");
}

#[test]
fn comments_commas_and_layout_do_not_matter() {
    let compact = parse("sphere{translate[1,2,3]scale 2}");
    let spread = parse("# a sphere\nsphere # here\n{\n  translate [ 1 2 3 ] # moved\n  scale\n 2\n}\n");
    assert_eq!(without_origins(&compact.objects), without_origins(&spread.objects));
    assert_eq!(
        compact.objects[0].transform,
        vec![TransformOp::Translate(Vec3::new(1.0, 2.0, 3.0)), TransformOp::Scale(Vec3::splat(2.0))]
    );
}

#[test]
fn strings_with_escapes_name_things() {
    let scene = parse(r#"material "a \"quoted\" \\ name" {} sphere { material "a \"quoted\" \\ name" }"#);
    assert_eq!(scene.materials[0].name, r#"a "quoted" \ name"#);
    assert_eq!(shape_of(&scene.objects[0]).1, 0);
}

#[test]
fn the_default_scene_is_a_whitted_composition() {
    // The values below are read off scenes/default.glint by hand, so that the test checks
    // the parsed scene against the text rather than against another call of the parser.
    let scene = default_scene();
    assert_eq!(scene.objects.len(), 6, "{} objects", scene.objects.len());
    let (eye, look_at) = (Vec3::new(0.0, 3.2, 10.0), Vec3::new(0.0, 0.9, 0.0));
    assert_eq!(
        scene.camera,
        CameraDesc {
            eye,
            look: look_at - eye,
            up: Vec3::Y,
            fov_y_degrees: 40.0,
            // With `look_at` and no `focal_distance`, the target is in focus.
            focal_distance: (look_at - eye).length(),
            ..CameraDesc::default()
        }
    );
    assert_eq!(
        scene.lights,
        vec![
            LightDesc::Point {
                position: Vec3::new(5.0, 9.0, 6.0),
                color: Vec3::new(0.85, 0.85, 0.8),
                attenuation: Vec3::new(1.0, 0.0, 0.0),
            },
            LightDesc::Directional { direction: Vec3::new(1.0, -1.5, -0.6), color: Vec3::new(0.35, 0.38, 0.45) },
        ]
    );
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    for wanted in ["floor", "mirror", "glass", "red", "green", "yellow"] {
        assert!(names.contains(&wanted), "no material {wanted:?} in {names:?}");
    }
    assert_eq!(scene.settings.background, Vec3::new(0.05, 0.08, 0.22));
    assert_eq!(scene.settings.ambient_light, Vec3::splat(0.1));
    let cube = scene.objects.iter().find(|n| shape_of(n).0 == ShapeDesc::Cube).expect("a cube");
    assert_eq!(
        cube.transform,
        vec![
            TransformOp::Scale(Vec3::splat(0.6)),
            TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 },
            TransformOp::Translate(Vec3::new(1.0, 0.6, -2.8)),
        ]
    );
    assert_eq!(scene.materials[shape_of(cube).1].name, "red");
    assert_eq!((scene.settings.width, scene.settings.height), (800, 600));
    assert_eq!(scene.settings.max_depth, 5);
    let bg = scene.settings.background;
    assert!(bg.z > bg.x && bg.z > bg.y && bg.z < 0.5, "background {bg} is not dark blue");
    assert!(scene.camera.look.y < 0.0, "the camera should look slightly down");

    let shapes: Vec<ShapeDesc> = scene
        .objects
        .iter()
        .filter_map(|n| match n.kind {
            NodeKind::Shape { shape, .. } => Some(shape),
            NodeKind::Group(_) | NodeKind::Solid(_) | NodeKind::Moving { .. } => None,
        })
        .collect();
    for wanted in [ShapeDesc::Plane, ShapeDesc::Cylinder, ShapeDesc::Cone, ShapeDesc::Cube] {
        assert!(shapes.contains(&wanted), "no {wanted:?} in the default scene");
    }
    assert_eq!(shapes.iter().filter(|s| **s == ShapeDesc::Sphere).count(), 2);

    let glass = scene.materials.iter().find(|m| m.name == "glass").expect("glass");
    assert_eq!(glass.ior, 1.5);
    assert!(glass.transmissive.min_element() > 0.5);
    let mirror = scene.materials.iter().find(|m| m.name == "mirror").expect("mirror");
    assert!(mirror.reflective.unwrap_or(mirror.specular).min_element() > 0.5);
    let floor = scene.materials.iter().find(|m| m.name == "floor").expect("floor");
    let texture = floor.texture.expect("the floor is textured");
    assert!(matches!(scene.textures[texture], TextureDesc::Checker { .. }));
    assert_ne!(floor.texture_repeat, Vec2::ONE, "the floor texture uses repeat");
}

#[test]
fn integrator_whitted_and_path_with_every_property() {
    assert_eq!(parse("settings { integrator whitted }").settings.integrator, IntegratorDesc::Whitted);
    assert_eq!(RenderSettings::default().integrator, IntegratorDesc::Whitted);
    let scene = parse("settings { integrator path { max_depth 12 rr_depth 3 sampler \"independent\" } spp 37 }");
    assert_eq!(
        scene.settings,
        RenderSettings {
            integrator: IntegratorDesc::Path(PathDesc {
                max_depth: 12,
                rr_depth: 3,
                sampler: SamplerKind::Independent
            }),
            spp: Some(37),
            ..RenderSettings::default()
        }
    );
    // Other settings may follow the integrator's block.
    let scene = parse("settings { integrator path { sampler \"sobol\" } width 64 }");
    assert_eq!(scene.settings.width, 64);
    assert_eq!(scene.settings.spp, None);
}

#[test]
fn integrator_path_defaults_are_mitsubas() {
    for source in ["settings { integrator path }", "settings { integrator path { } }"] {
        let scene = parse(source);
        assert_eq!(scene.settings.integrator, IntegratorDesc::Path(PathDesc::default()), "{source}");
    }
    assert_eq!(PathDesc::default(), PathDesc { max_depth: u32::MAX, rr_depth: 5, sampler: SamplerKind::Sobol });
}

#[test]
fn path_max_depth_unlimited_is_minus_one_or_the_word() {
    let depth = |source: &str| match parse(source).settings.integrator {
        IntegratorDesc::Path(path) => path.max_depth,
        IntegratorDesc::Whitted => panic!("expected a path integrator"),
    };
    assert_eq!(depth("settings { integrator path { max_depth -1 } }"), u32::MAX);
    assert_eq!(depth("settings { integrator path { max_depth \"unlimited\" } }"), u32::MAX);
    assert_eq!(depth("settings { integrator path { max_depth 0 } }"), 0);
    assert_eq!(depth("settings { integrator path { max_depth 16777216 } }"), 1 << 24);
}

#[test]
fn spp_takes_its_whole_range() {
    assert_eq!(parse("settings { spp 1 }").settings.spp, Some(1));
    assert_eq!(parse("settings { spp 1048576 }").settings.spp, Some(1 << 20));
    // `samples` is kept as written; spp overrides it when rendering.
    let s = parse("settings { samples 4 spp 5 }").settings;
    assert_eq!((s.samples_per_axis, s.spp), (4, Some(5)));
}

/// The BSDF of the only material of `source`.
fn bsdf_of(source: &str) -> BsdfDesc {
    parse(source).materials[0].bsdf.unwrap_or_else(|| panic!("no bsdf in {source}"))
}

#[test]
fn bsdfs_of_every_kind_with_every_property() {
    let textures = "texture \"a\" checker {} texture \"b\" checker { cells 2 }\n";
    let with = |material: &str| bsdf_of(&format!("{textures}material \"m\" {{ {material} }}"));
    assert_eq!(
        with("bsdf diffuse { reflectance [0.1 0.2 0.3] texture \"b\" }"),
        BsdfDesc::Diffuse { reflectance: ColorParam { value: Vec3::new(0.1, 0.2, 0.3), texture: Some(1) } }
    );
    assert_eq!(
        with(
            "bsdf conductor { eta [0.2 0.4 1.4] k [3.9 2.4 1.6] specular 0.9 specular_texture \"a\" \
             roughness 0.3 roughness_texture \"b\" }"
        ),
        BsdfDesc::Conductor {
            eta: Vec3::new(0.2, 0.4, 1.4),
            k: Vec3::new(3.9, 2.4, 1.6),
            specular: ColorParam { value: Vec3::splat(0.9), texture: Some(0) },
            alpha: ScalarParam { value: 0.3, texture: Some(1) },
        }
    );
    assert_eq!(
        with("bsdf dielectric { ior 1.33 ext_ior 1.0003 reflectance 0.9 transmittance [0.8 0.9 1] roughness 0.05 }"),
        BsdfDesc::Dielectric {
            int_ior: 1.33,
            ext_ior: 1.0003,
            reflectance: Vec3::splat(0.9),
            transmittance: Vec3::new(0.8, 0.9, 1.0),
            alpha: ScalarParam::constant(0.05),
        }
    );
    assert_eq!(
        with("bsdf thin_dielectric { ior 1.6 ext_ior 1.1 reflectance 0.5 transmittance [1 0.5 0.25] }"),
        BsdfDesc::ThinDielectric {
            int_ior: 1.6,
            ext_ior: 1.1,
            reflectance: Vec3::splat(0.5),
            transmittance: Vec3::new(1.0, 0.5, 0.25),
        }
    );
    assert_eq!(
        with(
            "bsdf plastic { diffuse [0.7 0.1 0.1] texture \"a\" ior 1.49 ext_ior 1.2 specular 0.8 roughness 0.1 \
             roughness_texture \"a\" nonlinear true }"
        ),
        BsdfDesc::Plastic {
            diffuse: ColorParam { value: Vec3::new(0.7, 0.1, 0.1), texture: Some(0) },
            int_ior: 1.49,
            ext_ior: 1.2,
            specular: Vec3::splat(0.8),
            alpha: ScalarParam { value: 0.1, texture: Some(0) },
            nonlinear: true,
        }
    );
    assert_eq!(
        with(
            "bsdf metallic_roughness { base [0.9 0.5 0.1] texture \"a\" metallic 0.3 metallic_texture \"a\" \
             roughness 0.2 roughness_texture \"a\" ior 1.4 }"
        ),
        BsdfDesc::MetallicRoughness {
            base: ColorParam { value: Vec3::new(0.9, 0.5, 0.1), texture: Some(0) },
            metallic: ScalarParam { value: 0.3, texture: Some(0) },
            alpha: ScalarParam { value: 0.2, texture: Some(0) },
            ior: 1.4,
        }
    );
}

#[test]
fn bsdf_defaults_of_every_kind() {
    let grey = ColorParam::constant(Vec3::splat(0.5));
    let smooth = ScalarParam::constant(0.0);
    assert_eq!(bsdf_of("material \"m\" { bsdf diffuse }"), BsdfDesc::Diffuse { reflectance: grey });
    assert_eq!(
        bsdf_of("material \"m\" { bsdf conductor { } }"),
        BsdfDesc::Conductor { eta: Vec3::ZERO, k: Vec3::ONE, specular: ColorParam::constant(Vec3::ONE), alpha: smooth }
    );
    assert_eq!(
        bsdf_of("material \"m\" { bsdf dielectric }"),
        BsdfDesc::Dielectric {
            int_ior: 1.5,
            ext_ior: 1.0,
            reflectance: Vec3::ONE,
            transmittance: Vec3::ONE,
            alpha: smooth
        }
    );
    assert_eq!(
        bsdf_of("material \"m\" { bsdf thin_dielectric }"),
        BsdfDesc::ThinDielectric { int_ior: 1.5, ext_ior: 1.0, reflectance: Vec3::ONE, transmittance: Vec3::ONE }
    );
    assert_eq!(
        bsdf_of("material \"m\" { bsdf plastic }"),
        BsdfDesc::Plastic {
            diffuse: grey,
            int_ior: 1.5,
            ext_ior: 1.0,
            specular: Vec3::ONE,
            alpha: smooth,
            nonlinear: false
        }
    );
    assert_eq!(
        bsdf_of("material \"m\" { bsdf metallic_roughness }"),
        BsdfDesc::MetallicRoughness { base: grey, metallic: smooth, alpha: smooth, ior: 1.5 }
    );
    assert_eq!(parse("material \"m\"").materials[0].bsdf, None);
}

#[test]
fn a_texture_without_a_value_is_used_as_it_is() {
    let textures = "texture \"t\" checker {}\n";
    let with = |material: &str| bsdf_of(&format!("{textures}material \"m\" {{ {material} }}"));
    let textured = ColorParam { value: Vec3::ONE, texture: Some(0) };
    assert_eq!(with("bsdf diffuse { texture \"t\" }"), BsdfDesc::Diffuse { reflectance: textured });
    let BsdfDesc::Plastic { diffuse, alpha, .. } = with("bsdf plastic { texture \"t\" roughness_texture \"t\" }")
    else {
        panic!("expected plastic");
    };
    assert_eq!((diffuse, alpha), (textured, ScalarParam { value: 1.0, texture: Some(0) }));
    let BsdfDesc::Conductor { specular, .. } = with("bsdf conductor { specular_texture \"t\" }") else {
        panic!("expected a conductor");
    };
    assert_eq!(specular, textured);
}

#[test]
fn emission_and_two_sidedness() {
    let scene = parse("material \"lamp\" { emission [17 12 4] two_sided false bsdf diffuse { reflectance 0 } kd 0.5 }");
    let lamp = &scene.materials[0];
    assert_eq!(lamp.emission, Vec3::new(17.0, 12.0, 4.0));
    assert!(!lamp.two_sided);
    assert_eq!(lamp.kd, 0.5, "properties after the bsdf block still apply");
    assert_eq!(lamp.bsdf, Some(BsdfDesc::Diffuse { reflectance: ColorParam::constant(Vec3::ZERO) }));
    let plain = &parse("material \"m\" { emission 2 }").materials[0];
    assert_eq!(plain.emission, Vec3::splat(2.0));
    assert!(plain.two_sided, "two-sided by default");
    assert_eq!(MaterialDesc::default().emission, Vec3::ZERO);
}

#[test]
fn environment_light_with_radiance_and_rotations() {
    let scene = parse(
        "light environment { radiance [0.5 0.6 0.7] rotate [0 1 0] 90 rotate [1 0 0] -10 }\n\
         light point {}",
    );
    assert_eq!(
        scene.lights[0],
        LightDesc::Environment(EnvironmentDesc {
            radiance: Vec3::new(0.5, 0.6, 0.7),
            texture: None,
            transform: vec![
                TransformOp::Rotate { axis: Vec3::Y, degrees: 90.0 },
                TransformOp::Rotate { axis: Vec3::X, degrees: -10.0 },
            ],
        })
    );
    assert_eq!(
        parse("light environment").lights,
        vec![LightDesc::Environment(EnvironmentDesc { radiance: Vec3::ONE, texture: None, transform: vec![] })]
    );
}

#[test]
fn the_path_traced_cornell_example_parses() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-path.glint");
    let scene = glint_scene::load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let s = &scene.settings;
    assert_eq!((s.width, s.height, s.spp), (256, 256, Some(64)));
    assert!(matches!(s.integrator, IntegratorDesc::Path(_)), "{:?}", s.integrator);
    let lamps: Vec<&MaterialDesc> = scene.materials.iter().filter(|m| m.emission != Vec3::ZERO).collect();
    assert_eq!(lamps.len(), 1);
    assert!(scene.materials.iter().all(|m| m.bsdf.is_some()));
    assert!(scene.lights.is_empty(), "lit by its emissive rectangle alone");
    let shapes: Vec<ShapeDesc> = scene
        .objects
        .iter()
        .filter_map(|n| match &n.kind {
            NodeKind::Shape { shape, .. } => Some(*shape),
            _ => None,
        })
        .collect();
    assert_eq!(shapes, [ShapeDesc::Rectangle, ShapeDesc::Sphere, ShapeDesc::Sphere]);
}
