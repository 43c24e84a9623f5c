//! Ray Tracer Challenge YAML: every key reaches the `SceneDesc` with the value written or
//! the book's default, transforms keep their order, `define`/`extend` merge, and what
//! glint cannot draw is skipped or approximated with a located warning.

use glam::{Vec2, Vec3};
use glint_core::desc::{
    AreaShape, LightDesc, MaterialDesc, NodeDesc, NodeKind, SceneDesc, SetOp, ShapeDesc, SolidDesc, TextureDesc,
    Transfer, TransformOp,
};
use glint_scene::challenge::{MIRROR, parse_challenge};

const CAMERA: &str = "
- add: camera
  width: 100
  height: 50
  field-of-view: 1.2
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

fn parse(items: &str) -> (SceneDesc, Vec<String>) {
    let text = format!("{CAMERA}{items}");
    parse_challenge(&text, "scene.yml").unwrap_or_else(|e| panic!("scene should load: {e}"))
}

fn quiet(items: &str) -> SceneDesc {
    let (scene, warnings) = parse(items);
    assert!(warnings.is_empty(), "unexpected warnings: {warnings:?}");
    scene
}

/// The objects under the root group that mirrors the book's left-handed world.
fn objects(scene: &SceneDesc) -> &[NodeDesc] {
    assert_eq!(scene.objects.len(), 1, "one mirrored root group");
    let root = &scene.objects[0];
    assert_eq!(root.transform, vec![TransformOp::Scale(MIRROR)]);
    match &root.kind {
        NodeKind::Group(children) => children,
        _ => panic!("the root is a group"),
    }
}

fn shape(node: &NodeDesc) -> (ShapeDesc, usize) {
    match node.kind {
        NodeKind::Shape { shape, material } => (shape, material),
        _ => panic!("expected a shape at {}", node.origin),
    }
}

const CLOSE: f32 = 1e-5;

#[test]
fn camera_light_and_settings() {
    let scene = quiet(
        "
- add: light
  at: [1, 2, 3]
  intensity: [0.5, 0.4, 0.3]
- add: light
  at: [-1, 0, 0]
  intensity: [0.25, 0.25, 0.25]
",
    );
    let s = &scene.settings;
    assert_eq!((s.width, s.height), (100, 50));
    assert_eq!(s.output_transfer, Transfer::Identity);
    assert_eq!(s.background, Vec3::ZERO);
    // L_a is the sum of the intensities: the book adds an ambient term per light.
    assert!((s.ambient_light - Vec3::new(0.75, 0.65, 0.55)).length() < CLOSE);
    let c = &scene.camera;
    assert_eq!(c.eye, Vec3::new(0.0, 0.0, 5.0));
    assert_eq!(c.look, Vec3::new(0.0, 0.0, -5.0));
    assert_eq!(c.up, Vec3::Y);
    // 1.2 rad across the width of a 2:1 image: 2·atan(tan(0.6)/2) vertically.
    let expected = (2.0 * (0.6f32.tan() / 2.0).atan()).to_degrees();
    assert!((c.fov_y_degrees - expected).abs() < 1e-4, "{}", c.fov_y_degrees);
    assert_eq!(
        scene.lights[0],
        LightDesc::Point { position: Vec3::new(1.0, 2.0, -3.0), color: Vec3::new(0.5, 0.4, 0.3), attenuation: Vec3::X }
    );
    assert!(scene.objects.is_empty());
}

#[test]
fn portrait_images_keep_the_angle_vertical_and_oblique_up_widens_it() {
    let portrait = "- add: camera\n  width: 50\n  height: 100\n  field-of-view: 1.2\n  from: [0, 0, -5]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n";
    let (scene, _) = parse_challenge(portrait, "p.yml").unwrap();
    assert!((scene.camera.fov_y_degrees - 1.2f32.to_degrees()).abs() < 1e-4);
    // Looking down at 45°: the book's axes have length sin 45°, so it shows more.
    let oblique = portrait.replace("from: [0, 0, -5]", "from: [0, 5, -5]");
    let (scene, _) = parse_challenge(&oblique, "p.yml").unwrap();
    let expected = (2.0 * (0.6f32.tan() / std::f32::consts::FRAC_1_SQRT_2).atan()).to_degrees();
    assert!((scene.camera.fov_y_degrees - expected).abs() < 1e-3, "{}", scene.camera.fov_y_degrees);
}

#[test]
fn area_lights_become_rectangle_lights() {
    let scene = quiet(
        "
- add: light
  corner: [-1, 2, 4]
  uvec: [2, 0, 0]
  vvec: [0, 2, 0]
  usteps: 4
  vsteps: 4
  jitter: true
  intensity: [1.5, 1.5, 1.5]
",
    );
    let LightDesc::Area { shape, color, samples, .. } = scene.lights[0] else { panic!("{:?}", scene.lights[0]) };
    assert_eq!(
        shape,
        AreaShape::Rectangle {
            corner: Vec3::new(-1.0, 2.0, -4.0),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::Y * 2.0
        }
    );
    assert_eq!((color, samples), (Vec3::splat(1.5), 4));
}

#[test]
fn a_material_left_out_is_the_books_default() {
    let scene = quiet("- add: sphere\n");
    let (_, material) = shape(&objects(&scene)[0]);
    let m = &scene.materials[material];
    let expected = MaterialDesc {
        name: "default".into(),
        ka: 0.1,
        kd: 0.9,
        ks: 1.0,
        kt: 1.0,
        ambient: None,
        diffuse: Vec3::ONE,
        specular: Vec3::splat(0.9),
        reflective: Some(Vec3::ZERO),
        transmissive: Vec3::ZERO,
        shininess: 200.0,
        ior: 1.0,
        ..MaterialDesc::default()
    };
    assert_eq!(*m, expected);
}

#[test]
fn every_material_key() {
    let scene = quiet(
        "
- add: sphere
  material:
    color: [0.2, 0.4, 0.6]
    ambient: 0.3
    diffuse: 0.5
    specular: 0.7
    shininess: 50
    reflective: 0.25
    transparency: 0.8
    refractive-index: 1.33
",
    );
    let m = &scene.materials[shape(&objects(&scene)[0]).1];
    assert_eq!(m.name, "sphere at line 10");
    assert_eq!((m.ka, m.kd, m.ks, m.kt), (0.3, 0.5, 1.0, 1.0));
    assert_eq!(m.diffuse, Vec3::new(0.2, 0.4, 0.6));
    assert_eq!(m.specular, Vec3::splat(0.7));
    assert_eq!(m.reflective, Some(Vec3::splat(0.25)));
    assert_eq!(m.transmissive, Vec3::splat(0.8));
    assert_eq!((m.shininess, m.ior), (50.0, 1.33));
    assert_eq!((m.ambient, m.texture), (None, None));
}

#[test]
fn transforms_apply_in_the_order_written() {
    let scene = quiet(
        "
- add: cube
  transform:
    - [translate, 1, 2, 3]
    - [scale, 2, 3, 4]
    - [rotate-x, 1.25]
    - [rotate-y, 0.5]
    - [rotate-z, -0.25]
    - [shear, 1, 0, 0, 0, 0, 0]
",
    );
    let node = &objects(&scene)[0];
    assert_eq!(shape(node).0, ShapeDesc::Cube);
    let t = &node.transform;
    assert_eq!(t[0], TransformOp::Translate(Vec3::new(1.0, 2.0, 3.0)));
    assert_eq!(t[1], TransformOp::Scale(Vec3::new(2.0, 3.0, 4.0)));
    let angle = |op: &TransformOp, axis: Vec3, radians: f32| match *op {
        TransformOp::Rotate { axis: a, degrees } => a == axis && (degrees - radians.to_degrees()).abs() < 1e-4,
        _ => false,
    };
    assert!(angle(&t[2], Vec3::X, 1.25) && angle(&t[3], Vec3::Y, 0.5) && angle(&t[4], Vec3::Z, -0.25));
    // The book's shearing(1, 0, …): x moves in proportion to y.
    assert_eq!(
        t[5],
        TransformOp::Matrix([[1.0, 1.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    );
}

#[test]
fn define_and_extend_merge_materials_and_transform_lists() {
    let scene = quiet(
        "
- define: white
  value:
    color: [1, 1, 1]
    diffuse: 0.7
    ambient: 0.1
    specular: 0.0
    reflective: 0.1
- define: blue
  extend: white
  value:
    color: [0.5, 0.8, 0.9]
- define: standard
  value:
    - [translate, 1, -1, 1]
    - [scale, 0.5, 0.5, 0.5]
- define: large
  value:
    - standard
    - [scale, 3.5, 3.5, 3.5]
- add: sphere
  material: blue
  transform:
    - large
    - [translate, 4, 0, 0]
- add: cube
  material: blue
",
    );
    let objects = objects(&scene);
    assert_eq!(
        objects[0].transform,
        vec![
            TransformOp::Translate(Vec3::new(1.0, -1.0, 1.0)),
            TransformOp::Scale(Vec3::splat(0.5)),
            TransformOp::Scale(Vec3::splat(3.5)),
            TransformOp::Translate(Vec3::new(4.0, 0.0, 0.0)),
        ]
    );
    // Both objects share one material, named after the definition.
    assert_eq!(shape(&objects[0]).1, shape(&objects[1]).1);
    assert_eq!(scene.materials.len(), 1);
    let m = &scene.materials[0];
    assert_eq!(m.name, "blue");
    assert_eq!((m.diffuse, m.kd, m.ka), (Vec3::new(0.5, 0.8, 0.9), 0.7, 0.1));
    assert_eq!((m.specular, m.reflective), (Vec3::ZERO, Some(Vec3::splat(0.1))));
}

#[test]
fn closed_cylinders_are_scaled_and_moved_onto_min_max() {
    let scene = quiet("- add: cylinder\n  min: 1\n  max: 4\n  closed: true\n  transform: [[scale, 2, 1, 2]]\n");
    let node = &objects(&scene)[0];
    assert_eq!(shape(node).0, ShapeDesc::Cylinder);
    assert_eq!(
        node.transform,
        vec![
            TransformOp::Scale(Vec3::new(1.0, 1.5, 1.0)),
            TransformOp::Translate(Vec3::new(0.0, 2.5, 0.0)),
            TransformOp::Scale(Vec3::new(2.0, 1.0, 2.0)),
        ]
    );
}

#[test]
fn cones_become_one_or_two_glint_cones() {
    // One nappe above the apex: glint's cone flipped so its apex is at y = 0.
    let scene = quiet("- add: cone\n  min: 0\n  max: 2\n  closed: true\n");
    let node = &objects(&scene)[0];
    assert_eq!(shape(node).0, ShapeDesc::Cone);
    assert_eq!(
        node.transform,
        vec![TransformOp::Scale(Vec3::new(2.0, -1.0, 2.0)), TransformOp::Translate(Vec3::new(0.0, 1.0, 0.0))]
    );
    // Both nappes: a group of two cones apex to apex.
    let scene = quiet("- add: cone\n  min: -1\n  max: 1\n  closed: true\n  transform: [[translate, 0, 1, 0]]\n");
    let node = &objects(&scene)[0];
    assert_eq!(node.transform, vec![TransformOp::Translate(Vec3::Y)]);
    let NodeKind::Group(nappes) = &node.kind else { panic!("two nappes") };
    assert_eq!(nappes.len(), 2);
    assert_eq!(nappes[1].transform[1], TransformOp::Translate(Vec3::new(0.0, -0.5, 0.0)));
}

#[test]
fn open_unbounded_and_truncated_shapes_are_approximated_with_warnings() {
    let (scene, warnings) = parse("- add: cylinder\n- add: cone\n  min: 0.5\n  max: 1\n  closed: true\n");
    let cylinder = &objects(&scene)[0];
    assert_eq!(cylinder.transform[0], TransformOp::Scale(Vec3::new(1.0, 1000.0, 1.0)));
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(warnings[0].starts_with("scene.yml:9:3: ") && warnings[0].contains("infinite cylinder"), "{warnings:?}");
    assert!(warnings[1].contains("open cylinder"), "{warnings:?}");
    assert!(warnings[2].starts_with("scene.yml:10:3: ") && warnings[2].contains("apex"), "{warnings:?}");
}

#[test]
fn groups_nest_and_pass_their_material_on() {
    let scene = quiet(
        "
- add: group
  material: { color: [1, 0, 0] }
  transform: [[translate, 0, 1, 0]]
  children:
    - add: sphere
    - add: group
      children:
        - add: plane
          material: { color: [0, 0, 1] }
",
    );
    let group = &objects(&scene)[0];
    assert_eq!(group.transform, vec![TransformOp::Translate(Vec3::Y)]);
    let NodeKind::Group(children) = &group.kind else { panic!("a group") };
    let sphere = shape(&children[0]);
    assert_eq!(scene.materials[sphere.1].diffuse, Vec3::X);
    let NodeKind::Group(inner) = &children[1].kind else { panic!("a group") };
    let plane = shape(&inner[0]);
    assert_eq!((plane.0, scene.materials[plane.1].diffuse), (ShapeDesc::Plane, Vec3::Z));
}

#[test]
fn defined_objects_are_templates() {
    let scene = quiet(
        "
- define: ball
  value:
    add: sphere
    material: { color: [0, 1, 0] }
    transform: [[scale, 0.5, 0.5, 0.5]]
- add: ball
  transform: [[translate, 1, 0, 0]]
",
    );
    let node = &objects(&scene)[0];
    assert_eq!(node.transform, vec![TransformOp::Scale(Vec3::splat(0.5)), TransformOp::Translate(Vec3::X)]);
    assert_eq!(scene.materials[shape(node).1].diffuse, Vec3::Y);
}

#[test]
fn checkers_on_a_plane_become_a_checker_texture() {
    let scene = quiet(
        "
- add: plane
  material:
    pattern:
      type: checkers
      colors: [[1, 1, 1], [0, 0, 0]]
      transform: [[scale, 0.25, 0.25, 0.25]]
",
    );
    let m = &scene.materials[shape(&objects(&scene)[0]).1];
    assert_eq!((m.texture, m.blend, m.texture_repeat), (Some(0), 1.0, Vec2::splat(4.0)));
    // glint's ambient term does not see textures: the mean colour stands in.
    assert_eq!(m.ambient, Some(Vec3::splat(0.5)));
    let TextureDesc::Checker { cells, .. } = &scene.textures[0] else { panic!("a checker") };
    assert_eq!(*cells, Vec2::ONE);
}

#[test]
fn patterns_glint_cannot_draw_fall_back_to_their_first_colour() {
    let (scene, warnings) = parse(
        "
- add: sphere
  material:
    pattern:
      type: stripes
      colors: [[1, 0, 0], [0, 0, 1]]
- add: sphere
  material:
    pattern:
      type: checkers
      colors: [[0, 1, 0], [0, 0, 1]]
",
    );
    let objects = objects(&scene);
    assert_eq!(scene.materials[shape(&objects[0]).1].diffuse, Vec3::X);
    assert_eq!(scene.materials[shape(&objects[1]).1].diffuse, Vec3::Y);
    assert!(scene.textures.is_empty());
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].starts_with("scene.yml:13:7: ") && warnings[0].contains("stripes"), "{warnings:?}");
}

#[test]
fn triangles_and_unknown_keys_are_skipped_with_located_warnings() {
    let (scene, warnings) = parse(
        "
- add: triangle
  p1: [0, 0, 0]
- add: sphere
  shadow: false
  colour: [1, 0, 0]
",
    );
    assert_eq!(objects(&scene).len(), 1);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(warnings[0].starts_with("scene.yml:10:8: ") && warnings[0].contains("triangle"), "{warnings:?}");
    assert!(warnings.iter().any(|w| w.starts_with("scene.yml:14:3: ") && w.contains("'colour'")), "{warnings:?}");
}

#[test]
fn csg_becomes_a_glint_solid_with_the_books_operands() {
    let scene = quiet(
        "
- add: csg
  operation: difference
  left: { add: cube }
  right: { add: sphere, transform: [[scale, 1.3, 1.3, 1.3]] }
  transform: [[translate, 0, 1, 0]]
",
    );
    let nodes = objects(&scene);
    assert_eq!(nodes.len(), 1);
    let node = &nodes[0];
    assert_eq!(node.transform, vec![TransformOp::Translate(Vec3::new(0.0, 1.0, 0.0))]);
    let NodeKind::Solid(SolidDesc::Csg { op, children }) = &node.kind else { panic!("{:?}", node.kind) };
    assert_eq!(op, &SetOp::Difference);
    assert!(matches!(children[0].kind, NodeKind::Shape { shape: ShapeDesc::Cube, .. }));
    assert!(matches!(children[1].kind, NodeKind::Shape { shape: ShapeDesc::Sphere, .. }));
    let err = parse_challenge(
        &format!("{CAMERA}- add: csg\n  operation: xor\n  left: {{ add: cube }}\n  right: {{ add: cube }}\n"),
        "scene.yml",
    )
    .unwrap_err();
    assert_eq!(err.line, 10, "{err}");
}

#[test]
fn obj_files_load_relative_to_the_scene_and_a_missing_one_is_located() {
    let dir = std::env::temp_dir().join(format!("glint-yaml-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene_path = dir.join("scene.yml");
    let text = format!("{CAMERA}- add: obj\n  file: tri.obj\n");
    let (scene, warnings) = parse_challenge(&text, &scene_path.display().to_string()).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.meshes[0].indices.len(), 3);
    let err = parse_challenge(&format!("{CAMERA}- add: obj\n  file: teapot.obj\n"), &scene_path.display().to_string())
        .unwrap_err();
    assert_eq!((err.line, err.column), (10, 9), "{err}");
    assert!(err.message.contains("teapot.obj"), "{err}");
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn csg_operands_may_name_their_kind_with_type() {
    let scene = quiet(
        "
- add: csg
  operation: intersection
  left:
    type: cube
  right:
    type: sphere
    transform: [[scale, 1.3, 1.3, 1.3]]
",
    );
    let NodeKind::Solid(SolidDesc::Csg { op, children }) = &objects(&scene)[0].kind else { panic!("a csg") };
    assert_eq!(op, &SetOp::Intersection);
    assert!(matches!(children[0].kind, NodeKind::Shape { shape: ShapeDesc::Cube, .. }));
    assert!(matches!(children[1].kind, NodeKind::Shape { shape: ShapeDesc::Sphere, .. }));
    assert_eq!(children[1].transform, vec![TransformOp::Scale(Vec3::splat(1.3))]);
}

#[test]
fn shadow_false_makes_everything_under_it_cast_no_shadow() {
    let (scene, warnings) = parse(
        "
- add: group
  children:
    - add: csg
      shadow: false
      operation: union
      left: { add: cube }
      right: { add: sphere }
    - add: sphere
- add: plane
  shadow: true
- add: cube
  shadow: false
",
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    let casts = |node: &NodeDesc| match &node.kind {
        NodeKind::Shape { material, .. } => scene.materials[*material].casts_shadows,
        other => panic!("{other:?}"),
    };
    let objects = objects(&scene);
    let NodeKind::Group(group) = &objects[0].kind else { panic!() };
    let NodeKind::Solid(SolidDesc::Csg { children, .. }) = &group[0].kind else { panic!() };
    assert!(children.iter().all(|c| !casts(c)), "both operands of the csg cast no shadow");
    assert!(casts(&group[1]), "a sibling of the csg still casts one");
    assert!(casts(&objects[1]) && !casts(&objects[2]));
    // The shadowless copy is the same material otherwise.
    let NodeKind::Shape { material, .. } = &objects[2].kind else { panic!() };
    let NodeKind::Shape { material: plain, .. } = &group[1].kind else { panic!() };
    let copy = MaterialDesc { casts_shadows: true, name: String::new(), ..scene.materials[*material].clone() };
    assert_eq!(copy, MaterialDesc { name: String::new(), ..scene.materials[*plain].clone() });
}

#[test]
fn unknown_keys_suggest_the_nearest_known_one() {
    let text = "
- add: camera
  width: 10
  height: 10
  field_of_view: 1
  field-of-view: 1
  from: [0, 0, -5]
  to: [0, 0, 0]
- add: sphere
  material: { colour: [1, 0, 0], reflectve: 0.5, glitter: 1 }
";
    let (_, warnings) = parse_challenge(text, "scene.yml").unwrap();
    let about =
        |key: &str| warnings.iter().find(|w| w.contains(&format!("'{key}'"))).unwrap_or_else(|| panic!("{warnings:?}"));
    assert!(about("field_of_view").contains("did you mean 'field-of-view'?"), "{warnings:?}");
    assert!(about("field_of_view").contains("known keys: "), "{warnings:?}");
    assert!(about("colour").contains("did you mean 'color'?"), "{warnings:?}");
    assert!(about("reflectve").contains("did you mean 'reflective'?"), "{warnings:?}");
    assert!(!about("glitter").contains("did you mean"), "{warnings:?}");
}

#[test]
fn patterns_without_colors_take_the_first_colour_of_a_nested_pattern() {
    let (scene, warnings) = parse(
        "
- add: sphere
  material:
    color: [0, 0, 1]
    pattern:
      type: blended
      a: { type: stripes, colors: [[0, 1, 0], [1, 1, 1]] }
      b: { type: stripes, colors: [[1, 0, 0], [1, 1, 1]] }
- add: sphere
  material:
    color: [0, 0, 1]
    pattern:
      type: perturbed
      pattern: { type: rings }
",
    );
    let objects = objects(&scene);
    assert_eq!(scene.materials[shape(&objects[0]).1].diffuse, Vec3::Y);
    // No colour anywhere: the material's own.
    assert_eq!(scene.materials[shape(&objects[1]).1].diffuse, Vec3::Z);
    assert_eq!(warnings.len(), 2, "{warnings:?}");
}
