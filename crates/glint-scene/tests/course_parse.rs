//! What the course formats mean: every element and field with its default, the order
//! of transforms, instancing, and how course materials and lights become glint's.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{LightDesc, MaterialDesc, NodeDesc, NodeKind, SceneDesc, ShapeDesc, Transfer, TransformOp};
use glint_scene::Loaded;
use glint_scene::course::{CourseOptions, DEPTH_OF_FIELD_SAMPLES_PER_AXIS, parse_json, parse_xml};

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/course").join(path)
}

#[track_caller]
fn xml(text: &str) -> Loaded {
    parse_xml(text, "scene.xml", Path::new("scenes"), CourseOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn json(text: &str) -> Loaded {
    parse_json(text, "scene.json", Path::new("scenes"), CourseOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

/// A minimal XML scene around the given elements of the root transblock.
fn xml_scene(head: &str, transblock: &str) -> String {
    format!(
        "<scenefile>{head}<object type=\"tree\" name=\"root\"><transblock>{transblock}</transblock></object></scenefile>"
    )
}

/// A minimal JSON scene with the given `groups` array.
fn json_scene(groups: &str) -> String {
    format!(
        r#"{{"globalData": {{"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5}},
            "cameraData": {{"position": [0, 0, 5], "up": [0, 1, 0], "look": [0, 0, -1], "heightAngle": 45}},
            "groups": {groups}}}"#
    )
}

fn op_matrix(op: &TransformOp) -> Mat4 {
    match *op {
        TransformOp::Translate(v) => Mat4::from_translation(v),
        TransformOp::Scale(s) => Mat4::from_scale(s),
        TransformOp::Rotate { axis, degrees } => Mat4::from_axis_angle(axis.normalize(), degrees.to_radians()),
        TransformOp::Matrix(rows) => Mat4::from_cols_array_2d(&rows).transpose(),
    }
}

/// Every shape with its world matrix and material, in tree order.
fn shapes(desc: &SceneDesc) -> Vec<(Mat4, ShapeDesc, MaterialDesc)> {
    fn walk(node: &NodeDesc, parent: Mat4, desc: &SceneDesc, out: &mut Vec<(Mat4, ShapeDesc, MaterialDesc)>) {
        let local = node.transform.iter().fold(Mat4::IDENTITY, |acc, op| op_matrix(op) * acc);
        let world = parent * local;
        // `if let` rather than `match`: the course readers make only these two kinds.
        if let NodeKind::Shape { shape, material } = &node.kind {
            out.push((world, *shape, desc.materials[*material].clone()));
        } else if let NodeKind::Group(children) = &node.kind {
            children.iter().for_each(|c| walk(c, world, desc, out));
        }
    }
    let mut out = Vec::new();
    desc.objects.iter().for_each(|n| walk(n, Mat4::IDENTITY, desc, &mut out));
    out
}

#[track_caller]
fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).length() < 1e-5, "{a} != {b}");
}

#[track_caller]
fn assert_same_matrix(a: Mat4, b: Mat4) {
    assert!(a.abs_diff_eq(b, 1e-5), "{a} != {b}");
}

#[test]
fn xml_defaults_are_the_course_readers() {
    let loaded = xml(&xml_scene("", r#"<object type="primitive" name="sphere"/>"#));
    let d = &loaded.scene;
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // Camera: at (5, 5, 5) looking along (−1, −1, −1), 45°.
    assert_eq!((d.camera.eye, d.camera.look, d.camera.up), (Vec3::splat(5.0), Vec3::splat(-1.0), Vec3::Y));
    assert_eq!((d.camera.fov_y_degrees, d.camera.aperture_radius), (45.0, 0.0));
    // Display-referred settings at the course's size and depth.
    let s = &d.settings;
    assert_eq!((s.width, s.height, s.samples_per_axis, s.max_depth), (1024, 768, 1, 4));
    assert_eq!((s.ambient_light, s.background, s.output_transfer), (Vec3::ONE, Vec3::ZERO, Transfer::Identity));
    // A white diffuse material times k_d = 0.5, nothing else (k_t defaults to 0).
    let [(world, shape, m)] = shapes(d).try_into().unwrap();
    assert_eq!(shape, ShapeDesc::Sphere);
    assert_same_matrix(world, Mat4::from_scale(Vec3::splat(0.5)));
    assert_eq!((m.ka, m.kd, m.ks, m.kt), (1.0, 1.0, 1.0, 1.0));
    assert_eq!(m.diffuse, Vec3::splat(0.5));
    assert_eq!((m.ambient, m.reflective), (Some(Vec3::ZERO), Some(Vec3::ZERO)));
    assert_eq!((m.specular, m.transmissive, m.shininess, m.ior), (Vec3::ZERO, Vec3::ZERO, 0.0, 1.0));
    assert_eq!((m.texture, m.blend), (None, 0.0));
    assert!(d.lights.is_empty());
}

#[test]
fn xml_every_element_and_attribute() {
    let head = r#"
        <globaldata>
            <ambientcoeff v="0.2"/><diffusecoeff v="0.4"/><specularcoeff v="0.6"/><transparentcoeff v="0.8"/>
        </globaldata>
        <cameradata>
            <pos x="1" y="2" z="3"/><focus x="1" y="2" z="0"/><up x="0" y="1" z="0"/><heightangle v="30"/>
        </cameradata>
        <lightdata><id v="0"/><type v="point"/><color r="1" g="0.5" b="0.25"/>
            <position x="1" y="2" z="3"/><function v1="1" v2="0.1" v3="0.01"/></lightdata>
        <lightdata><id v="1"/><type v="directional"/><color x="0.1" y="0.2" z="0.3"/>
            <direction x="0" y="-1" z="0"/></lightdata>
        <lightdata><id v="2"/><type v="spot"/><position x="0" y="5" z="0"/><direction x="0" y="-1" z="0"/>
            <angle v="30"/><penumbra v="5"/><function a="1" b="0" c="0"/></lightdata>
        <lightdata><id v="3"/><function x="2" y="0" z="0"/></lightdata>"#;
    let prim = r#"<object type="primitive" name="cube">
            <ambient r="1" g="0" b="0"/><diffuse r="0" g="1" b="0"/><specular r="0" g="0" b="1"/>
            <reflective r="1" g="1" b="0"/><transparent r="0" g="1" b="1"/><emissive r="0.1" g="0.1" b="0.1"/>
            <shininess v="12"/><ior v="1.5"/><blend v="0.25"/>
            <texture file="json/illuminate/required/textures/board.png" u="2" v="3"/>
        </object>"#;
    // The scene lives in tests/course/xml: textures are found relative to tests/course.
    let text = xml_scene(head, prim);
    let loaded = parse_xml(&text, "scene.xml", &data("xml"), CourseOptions::default()).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.scene;
    assert_eq!(
        (d.camera.eye, d.camera.look, d.camera.fov_y_degrees),
        (Vec3::new(1.0, 2.0, 3.0), Vec3::NEG_Z * 3.0, 30.0)
    );
    assert_eq!(
        d.lights,
        vec![
            LightDesc::Point {
                position: Vec3::new(1.0, 2.0, 3.0),
                color: Vec3::new(1.0, 0.5, 0.25),
                attenuation: Vec3::new(1.0, 0.1, 0.01)
            },
            LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::new(0.1, 0.2, 0.3) },
            LightDesc::Spot {
                position: Vec3::new(0.0, 5.0, 0.0),
                direction: Vec3::NEG_Y,
                color: Vec3::ONE,
                attenuation: Vec3::X,
                angle_degrees: 30.0,
                penumbra_degrees: 5.0,
                falloff: glint_core::desc::SpotFalloff::Smooth,
            },
            // No <type>: a point light, at the reader's default position.
            LightDesc::Point { position: Vec3::splat(3.0), color: Vec3::ONE, attenuation: Vec3::new(2.0, 0.0, 0.0) },
        ]
    );
    let [(_, shape, m)] = shapes(d).try_into().unwrap();
    assert_eq!(shape, ShapeDesc::Cube);
    // Global coefficients folded into the colours; the emissive colour joins the ambient.
    assert_close(m.ambient.unwrap(), Vec3::new(0.3, 0.1, 0.1));
    assert_close(m.diffuse, Vec3::new(0.0, 0.4, 0.0));
    assert_close(m.specular, Vec3::new(0.0, 0.0, 0.6));
    assert_close(m.reflective.unwrap(), Vec3::new(0.6, 0.6, 0.0));
    assert_close(m.transmissive, Vec3::new(0.0, 0.8, 0.8));
    assert_eq!((m.shininess, m.ior, m.blend, m.texture_repeat), (12.0, 1.5, 0.25, Vec2::new(2.0, 3.0)));
    assert_eq!(m.texture, Some(0));
    assert_eq!(d.textures.len(), 1);
}

#[test]
fn xml_transforms_apply_the_first_written_outermost() {
    let d = xml(&xml_scene(
        "",
        r#"<translate x="1" y="2" z="3"/><rotate x="0" y="1" z="0" angle="90"/><scale x="2" y="2" z="2"/>
           <object type="primitive" name="cube"/>"#,
    ))
    .scene;
    let [(world, _, _)] = shapes(&d).try_into().unwrap();
    // CTM = T·R·S, times the unit scale 0.5: the corner (1, 0, 0) of glint's cube is the
    // course's (0.5, 0, 0), scaled to (1, 0, 0), rotated to (0, 0, −1), moved by (1, 2, 3).
    assert_close(world.transform_point3(Vec3::X), Vec3::new(1.0, 2.0, 2.0));
}

#[test]
fn xml_matrix_rows_are_rows() {
    let d = xml(&xml_scene(
        "",
        r#"<matrix><row a="2" b="0" c="0" d="1"/><row a="0" b="2" c="0" d="2"/>
                   <row v1="0" v2="0" v3="2" v4="3"/><row a="0" b="0" c="0" d="1"/></matrix>
           <object type="primitive" name="sphere"/>"#,
    ))
    .scene;
    let [(world, _, _)] = shapes(&d).try_into().unwrap();
    assert_close(world.transform_point3(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0));
    assert_close(world.transform_point3(Vec3::X), Vec3::new(2.0, 2.0, 3.0));
}

#[test]
fn xml_master_objects_equal_writing_the_objects_out() {
    let with_master = r#"<scenefile>
        <object type="tree" name="leg"><transblock><scale x="1" y="3" z="1"/>
            <object type="primitive" name="cylinder"><diffuse r="1" g="0" b="0"/></object></transblock></object>
        <object type="tree" name="root">
            <transblock><translate x="-1" y="0" z="0"/><object type="master" name="leg"/></transblock>
            <transblock><translate x="1" y="0" z="0"/><object type="master" name="leg"/></transblock>
        </object></scenefile>"#;
    let written_out = r#"<scenefile><object type="tree" name="root">
            <transblock><translate x="-1" y="0" z="0"/><object type="tree"><transblock><scale x="1" y="3" z="1"/>
                <object type="primitive" name="cylinder"><diffuse r="1" g="0" b="0"/></object></transblock></object></transblock>
            <transblock><translate x="1" y="0" z="0"/><scale x="1" y="3" z="1"/>
                <object type="primitive" name="cylinder"><diffuse r="1" g="0" b="0"/></object></transblock>
        </object></scenefile>"#;
    let a = shapes(&xml(with_master).scene);
    let b = shapes(&xml(written_out).scene);
    assert_eq!(a.len(), 2);
    for ((ma, sa, ka), (mb, sb, kb)) in a.iter().zip(&b) {
        assert_same_matrix(*ma, *mb);
        assert_eq!((sa, &ka.diffuse), (sb, &kb.diffuse));
    }
}

#[test]
fn xml_torus() {
    let loaded = xml(&xml_scene("", r#"<object type="primitive" name="torus"/>"#));
    let [(world, shape, _)] = shapes(&loaded.scene).try_into().unwrap();
    // A ring inside the unit cube: outer radius 0.5.
    let ShapeDesc::Torus { minor_radius } = shape else { panic!("{shape:?}") };
    assert_close(world.transform_point3(Vec3::new(1.0 + minor_radius, 0.0, 0.0)), Vec3::new(0.5, 0.0, 0.0));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}

#[test]
fn xml_mesh_is_loaded_in_its_own_coordinates_and_a_missing_one_is_located() {
    // The course resolves mesh paths against the parent of the scene's folder.
    let root = std::env::temp_dir().join(format!("glint-course-mesh-{}", std::process::id()));
    std::fs::create_dir_all(root.join("mesh")).unwrap();
    std::fs::create_dir_all(root.join("scenes")).unwrap();
    std::fs::write(root.join("mesh/tri.obj"), "v 0 0 0\nv 2 0 0\nv 0 2 0\nf 1 2 3\n").unwrap();
    let text = xml_scene("", r#"<object type="primitive" name="mesh" meshfile="mesh/tri.obj"/>"#);
    let loaded = parse_xml(&text, "scene.xml", &root.join("scenes"), CourseOptions::default()).unwrap();
    assert_eq!(loaded.scene.meshes.len(), 1);
    assert_eq!(loaded.scene.meshes[0].positions[1], Vec3::new(2.0, 0.0, 0.0), "no unit-size scaling for meshes");
    let [(_, shape, _)] = shapes(&loaded.scene).try_into().unwrap();
    assert_eq!(shape, ShapeDesc::Mesh { index: 0 });

    let missing = xml_scene(
        "",
        r#"
<object type="primitive" name="mesh" meshfile="mesh/dragon.obj"/>"#,
    );
    let err = parse_xml(&missing, "scene.xml", &root.join("scenes"), CourseOptions::default()).unwrap_err();
    assert_eq!(err.line, 2, "{err}");
    assert!(err.message.contains("mesh/dragon.obj"), "{err}");
    let lenient = CourseOptions { strict_textures: false };
    let loaded = parse_xml(&missing, "scene.xml", &root.join("scenes"), lenient).unwrap();
    assert!(shapes(&loaded.scene).is_empty() && loaded.warnings.len() == 1, "{:?}", loaded.warnings);
    std::fs::remove_dir_all(root).unwrap();
}

#[test]
fn json_defaults_and_fields() {
    let loaded = json(&json_scene(r#"[{"primitives": [{"type": "cone"}]}]"#));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let [(world, shape, m)] = shapes(&loaded.scene).try_into().unwrap();
    assert_eq!(shape, ShapeDesc::Cone);
    // glint's cone has its apex at y = 1 and a base of radius 1; the course's at 0.5.
    assert_close(world.transform_point3(Vec3::Y), Vec3::new(0.0, 0.5, 0.0));
    assert_close(world.transform_point3(Vec3::new(1.0, -1.0, 0.0)), Vec3::new(0.5, -0.5, 0.0));
    assert_eq!(m.diffuse, Vec3::splat(0.5));
    assert_eq!((m.ambient, m.specular, m.transmissive), (Some(Vec3::ZERO), Vec3::ZERO, Vec3::ZERO));

    let text = r#"{"name": "root",
        "globalData": {"ambientCoeff": 0.1, "diffuseCoeff": 0.2, "specularCoeff": 0.3, "transparentCoeff": 0.4},
        "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "focus": [0, 0, 1], "heightAngle": 60,
                       "aperture": 0.1, "focalLength": 4},
        "groups": [{"primitives": [{"type": "sphere", "ambient": [1, 1, 1], "diffuse": [1, 0, 0],
            "specular": [0, 1, 0], "reflective": [0, 0, 1], "transparent": [1, 1, 0], "shininess": 7,
            "ior": 1.33, "blend": 0.5, "textureFile": "textures/board.png", "textureU": 4, "textureV": 2}]}]}"#;
    let loaded =
        parse_json(text, "s.json", &data("json/illuminate/required/texture_tests"), CourseOptions::default()).unwrap();
    let d = &loaded.scene;
    assert_eq!((d.camera.look, d.camera.fov_y_degrees), (Vec3::new(0.0, 0.0, -4.0), 60.0));
    // Depth of field: the aperture is the lens radius, the focal length the distance in
    // focus; more samples per pixel so the lens does not show as noise.
    assert_eq!((d.camera.aperture_radius, d.camera.focal_distance), (0.1, 4.0));
    assert_eq!(d.settings.samples_per_axis, DEPTH_OF_FIELD_SAMPLES_PER_AXIS);
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let [(_, _, m)] = shapes(d).try_into().unwrap();
    assert_close(m.ambient.unwrap(), Vec3::splat(0.1));
    assert_close(m.diffuse, Vec3::new(0.2, 0.0, 0.0));
    assert_close(m.specular, Vec3::new(0.0, 0.3, 0.0));
    assert_close(m.reflective.unwrap(), Vec3::new(0.0, 0.0, 0.3));
    assert_close(m.transmissive, Vec3::new(0.4, 0.4, 0.0));
    assert_eq!((m.shininess, m.ior, m.blend, m.texture_repeat), (7.0, 1.33, 0.5, Vec2::new(4.0, 2.0)));
    assert_eq!(m.texture, Some(0));
}

#[test]
fn json_transforms_are_translate_rotate_scale_matrix() {
    let d = json(&json_scene(
        r#"[{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 4], [0, 0, 0, 1]],
             "scale": [2, 2, 2], "translate": [1, 0, 0], "rotate": [0, 0, 1, 90],
             "primitives": [{"type": "cube"}]}]"#,
    ))
    .scene;
    let [(world, _, _)] = shapes(&d).try_into().unwrap();
    let expected = Mat4::from_translation(Vec3::X)
        * Mat4::from_axis_angle(Vec3::Z, 90f32.to_radians())
        * Mat4::from_scale(Vec3::splat(2.0))
        * Mat4::from_translation(Vec3::new(0.0, 0.0, 4.0))
        * Mat4::from_scale(Vec3::splat(0.5));
    assert_same_matrix(world, expected);
}

#[test]
fn json_lights_are_placed_by_their_group() {
    let d = json(&json_scene(
        r#"[{"translate": [1, 2, 3], "rotate": [0, 1, 0, 90], "lights": [
              {"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]},
              {"type": "directional", "color": [0.5, 0.5, 0.5], "direction": [1, 0, 0]},
              {"type": "spot", "color": [1, 0, 0], "direction": [1, 0, 0], "attenuationCoeff": [1, 0.5, 0],
               "angle": 20, "penumbra": 4}]}]"#,
    ))
    .scene;
    let LightDesc::Point { position, .. } = d.lights[0] else { panic!() };
    assert_close(position, Vec3::new(1.0, 2.0, 3.0));
    let LightDesc::Directional { direction, color } = d.lights[1] else { panic!() };
    assert_close(direction, Vec3::NEG_Z);
    assert_eq!(color, Vec3::splat(0.5));
    let LightDesc::Spot { position, direction, attenuation, angle_degrees, penumbra_degrees, .. } = d.lights[2] else {
        panic!()
    };
    assert_close(position, Vec3::new(1.0, 2.0, 3.0));
    assert_close(direction, Vec3::NEG_Z);
    assert_eq!((attenuation, angle_degrees, penumbra_degrees), (Vec3::new(1.0, 0.5, 0.0), 20.0, 4.0));
}

#[test]
fn json_template_groups_equal_writing_the_objects_out() {
    let templated = r#"{"globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
        "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "look": [0, 0, -1], "heightAngle": 45},
        "templateGroups": [
            {"name": "ball", "scale": [0.5, 0.5, 0.5], "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}],
             "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]},
            {"name": "pair", "groups": [{"translate": [0, 1, 0], "groups": [{"name": "ball"}]}, {"name": "ball"}]}
        ],
        "groups": [{"translate": [5, 0, 0], "groups": [{"name": "pair"}]}, {"name": "ball"}]}"#;
    let written = json_scene(
        r#"[{"translate": [5, 0, 0], "groups": [{"groups": [
                {"translate": [0, 1, 0], "groups": [{"scale": [0.5, 0.5, 0.5],
                    "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}],
                    "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]}]},
                {"scale": [0.5, 0.5, 0.5], "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}],
                 "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]}]}]},
            {"scale": [0.5, 0.5, 0.5], "primitives": [{"type": "sphere", "diffuse": [1, 0, 0]}],
             "lights": [{"type": "point", "color": [1, 1, 1], "attenuationCoeff": [1, 0, 0]}]}]"#,
    );
    let a = json(templated).scene;
    let b = json(&written).scene;
    let (sa, sb) = (shapes(&a), shapes(&b));
    assert_eq!(sa.len(), 3);
    for ((ma, _, ka), (mb, _, kb)) in sa.iter().zip(&sb) {
        assert_same_matrix(*ma, *mb);
        assert_eq!(ka.diffuse, kb.diffuse);
    }
    // Each use of a template brings its lights, placed where it is used.
    assert_eq!(a.lights, b.lights);
    assert_eq!(a.lights.len(), 3);
    let LightDesc::Point { position, .. } = a.lights[0] else { panic!() };
    assert_close(position, Vec3::new(5.0, 1.0, 0.0));
}

#[test]
fn equal_materials_are_shared_and_textures_loaded_once() {
    let text = r#"{"globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5},
        "cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "look": [0, 0, -1], "heightAngle": 45},
        "groups": [{"primitives": [
            {"type": "cube", "textureFile": "textures/board.png", "blend": 1},
            {"type": "cube", "textureFile": "textures/board.png", "blend": 1},
            {"type": "cube", "textureFile": "textures/board.png", "blend": 0.5},
            {"type": "sphere"}, {"type": "cylinder"}]}]}"#;
    let d = parse_json(text, "s.json", &data("json/illuminate/required/texture_tests"), CourseOptions::default())
        .unwrap()
        .scene;
    assert_eq!(d.textures.len(), 1);
    assert_eq!(d.materials.len(), 3);
}

#[test]
fn misplaced_textures_are_found_with_a_warning() {
    // The course resolves "board.png" to tests/course/json/illuminate/required/board.png,
    // which does not exist; the file is in the textures folder beside the scenes.
    let text = json_scene(r#"[{"primitives": [{"type": "cube", "textureFile": "file:../../board.png"}]}]"#);
    let loaded =
        parse_json(&text, "s.json", &data("json/illuminate/required/texture_tests"), CourseOptions::default()).unwrap();
    assert_eq!(loaded.scene.textures.len(), 1);
    assert_eq!(loaded.warnings.len(), 1);
    assert!(loaded.warnings[0].contains("is not at"), "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("board.png"), "{:?}", loaded.warnings);
}
