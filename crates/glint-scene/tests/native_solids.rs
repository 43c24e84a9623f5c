//! The solid nodes of `.glint`: CSG, blobs, implicit surfaces, quadrics and
//! superellipsoids — what they build, how materials are inherited, where mistakes are
//! reported — and the example scenes, rendered without a single NaN or infinite pixel.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::{BlobComponentShape, NodeDesc, NodeKind, SceneDesc, SetOp, SolidDesc, TransformOp};
use glint_core::render::render;
use glint_core::scene::compile;
use glint_scene::{SceneError, load_scene, parse_scene};

fn scene(source: &str) -> SceneDesc {
    parse_scene(source, "scene.glint", Path::new("")).unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn assert_error(source: &str, line: u32, column: u32, fragment: &str) -> SceneError {
    let e = match parse_scene(source, "scene.glint", Path::new("")) {
        Ok(s) => panic!("expected an error for {source:?}, got {s:?}"),
        Err(e) => e,
    };
    assert_eq!((e.line(), e.column()), (line, column), "wrong position for: {e}");
    assert!(e.message.contains(fragment), "message {:?} lacks {fragment:?}", e.message);
    e
}

fn solid(node: &NodeDesc) -> &SolidDesc {
    match &node.kind {
        NodeKind::Solid(s) => s,
        other => panic!("expected a solid at {}, found {other:?}", node.origin),
    }
}

fn material_name(scene: &SceneDesc, node: &NodeDesc) -> String {
    let index = match &node.kind {
        NodeKind::Shape { material, .. } => *material,
        NodeKind::Solid(SolidDesc::Blob { material, .. } | SolidDesc::Implicit { material, .. }) => *material,
        NodeKind::Solid(SolidDesc::Quadric { material, .. } | SolidDesc::Superellipsoid { material, .. }) => *material,
        other => panic!("no material on {other:?}"),
    };
    scene.materials[index].name.clone()
}

#[test]
fn csg_nodes_build_trees_and_children_inherit_the_material() {
    let s = scene(
        "material \"red\" {}\nmaterial \"blue\" {}\n\
         difference {\n  material \"red\"\n  cube { }\n  union { sphere { material \"blue\" } cylinder { } }\n  translate [1 0 0]\n}\n\
         sphere { }",
    );
    let top = &s.objects[0];
    assert_eq!(top.transform, vec![TransformOp::Translate(Vec3::X)]);
    assert_eq!(top.origin, "scene.glint:3:1");
    let SolidDesc::Csg { op: SetOp::Difference, children } = solid(top) else { panic!("{top:?}") };
    assert_eq!(children.len(), 2);
    assert_eq!(material_name(&s, &children[0]), "red");
    let SolidDesc::Csg { op: SetOp::Union, children: inner } = solid(&children[1]) else { panic!() };
    assert_eq!(material_name(&s, &inner[0]), "blue");
    assert_eq!(material_name(&s, &inner[1]), "red", "inherited through the nested union");
    // Outside the CSG the default applies again.
    assert_eq!(material_name(&s, &s.objects[1]), "default");
    // The whole thing compiles.
    compile(&s).expect("compiles");
}

#[test]
fn material_may_follow_the_children_it_applies_to() {
    let s = scene("material \"m\" {}\nintersection { sphere { } cube { } material \"m\" }");
    let SolidDesc::Csg { children, .. } = solid(&s.objects[0]) else { panic!() };
    assert!(children.iter().all(|c| material_name(&s, c) == "m"));
    assert!(s.materials.iter().all(|m| m.name != "default"), "no default material was needed");
}

#[test]
fn blob_implicit_quadric_and_superellipsoid_nodes() {
    let s = scene(
        "blob {\n  threshold 0.4\n  component sphere { center [1 0 0] radius 0.5 strength -2 }\n\
         component cylinder { from [0 0 0] to [0 2 0] radius 0.3 scale 2 }\n}\n\
         implicit { function \"x^2 + y^2 - z\" bounds [-1 -2 -3] [1 2 3] lipschitz 10 }\n\
         quadric { coefficients [1 1 1 0 0 0 0 0 0 -1] bounds [-1 -1 -1] [1 1 1] }\n\
         superellipsoid { exponents [0.5 2] }\n\
         blob { component sphere { } }",
    );
    let SolidDesc::Blob { blob, .. } = solid(&s.objects[0]) else { panic!() };
    assert_eq!(blob.threshold, 0.4);
    assert_eq!(blob.components[0].shape, BlobComponentShape::Sphere { center: Vec3::X, radius: 0.5 });
    assert_eq!(blob.components[0].strength, -2.0);
    assert_eq!(
        blob.components[1].shape,
        BlobComponentShape::Cylinder { from: Vec3::ZERO, to: 2.0 * Vec3::Y, radius: 0.3 }
    );
    assert_eq!(blob.components[1].transform, vec![TransformOp::Scale(Vec3::splat(2.0))]);
    let SolidDesc::Implicit { implicit, .. } = solid(&s.objects[1]) else { panic!() };
    assert_eq!(implicit.function, "x^2 + y^2 - z");
    assert_eq!(implicit.bounds, [Vec3::new(-1.0, -2.0, -3.0), Vec3::new(1.0, 2.0, 3.0)]);
    assert_eq!(implicit.lipschitz, Some(10.0));
    let SolidDesc::Quadric { coefficients, bounds, .. } = solid(&s.objects[2]) else { panic!() };
    assert_eq!(coefficients[9], -1.0);
    assert_eq!(*bounds, Some([Vec3::splat(-1.0), Vec3::ONE]));
    assert!(matches!(solid(&s.objects[3]), SolidDesc::Superellipsoid { e1: 0.5, e2: 2.0, .. }));
    // Defaults: threshold 0.5, a unit ball of strength 1.
    let SolidDesc::Blob { blob, .. } = solid(&s.objects[4]) else { panic!() };
    assert_eq!(blob.threshold, 0.5);
    assert_eq!(blob.components[0].shape, BlobComponentShape::Sphere { center: Vec3::ZERO, radius: 1.0 });
    compile(&s).expect("compiles");
}

#[test]
fn solids_can_be_defined_used_and_grouped() {
    let s = scene(
        "define \"d\" { difference { cube { } sphere { scale 1.2 } } }\n\
         group { use \"d\" { translate [2 0 0] } blob { component sphere { } } }",
    );
    let NodeKind::Group(children) = &s.objects[0].kind else { panic!() };
    let NodeKind::Group(used) = &children[0].kind else { panic!() };
    assert!(matches!(solid(&used[0]), SolidDesc::Csg { op: SetOp::Difference, .. }));
    compile(&s).expect("compiles");
}

#[test]
fn expression_errors_point_into_the_string() {
    // The string's quote is at column 12, so its end (offset 11) is column 24.
    let e = assert_error("implicit {\n  function \"x^2 + y^2 +\"\n}", 2, 24, "in the implicit function: expected");
    assert!(e.message.contains("end of the expression"), "{e}");
    assert_error("implicit { function \"x + w\" }", 1, 26, "unknown name 'w'");
    assert_error("implicit { function \"x ^ 1.5\" }", 1, 26, "whole number");
    assert_error("implicit { bounds [-1 -1 -1] [1 1 1] }", 1, 1, "needs a function");
    assert_error("implicit { function \"x\" bounds [1 1 1] [-1 -1 -1] }", 1, 32, "smaller corner first");
    assert_error("implicit { function \"x\" bounds [1 1 1] }", 1, 32, "expected two corners");
    assert_error("implicit { function \"x\" lipschitz 0 }", 1, 35, "greater than 0");
}

#[test]
fn csg_mistakes_are_located() {
    assert_error("union { }", 1, 1, "'union' needs at least one object");
    assert_error("difference {\n  cube { }\n  disk { }\n}", 3, 3, "a disk has no inside");
    assert_error("intersection { sphere { } radius 2 }", 1, 27, "unknown node 'radius' in 'intersection'");
    assert_error("union { material \"nope\" sphere { } }", 1, 18, "unknown material 'nope'");
    assert_error(
        "material \"a\" {}\nmaterial \"b\" {}\nunion { material \"a\" material \"b\" sphere { } }",
        3,
        22,
        "set twice",
    );
}

#[test]
fn blob_and_shape_mistakes_are_located() {
    assert_error("blob { }", 1, 1, "positive strength");
    assert_error("blob { component sphere { strength -1 } }", 1, 1, "positive strength");
    assert_error("blob { component cube { } }", 1, 18, "unknown component type 'cube'");
    assert_error("blob { component cylinder { radius 1 } }", 1, 18, "needs both ends");
    assert_error("blob { component sphere { center [0 0 0] from [1 0 0] } }", 1, 42, "unknown property 'from'");
    assert_error("blob { component sphere { strength 0 } }", 1, 36, "non-zero");
    assert_error("blob { threshold -1 component sphere { } }", 1, 18, "greater than 0");
    assert_error("quadric { }", 1, 1, "needs its coefficients");
    assert_error("quadric { coefficients [1 2 3] }", 1, 11, "expected 10 numbers");
    assert_error("quadric { coefficients [0 0 0 0 0 0 0 0 0 1] }", 1, 24, "non-zero coefficient");
    assert_error("superellipsoid { exponents [0 1] }", 1, 28, "must each be from");
    assert_error("superellipsoid { exponent [1 1] }", 1, 18, "expected one of: exponents");
}

#[test]
fn compile_errors_name_the_solid() {
    // A Lipschitz bound below the real slope is caught when the scene is compiled.
    let s = scene("\n\nimplicit { function \"10*x\" lipschitz 2 }");
    let e = compile(&s).expect_err("lipschitz too small");
    assert!(e.to_string().starts_with("scene.glint:3:1: lipschitz 2 is too small"), "{e}");
}

/// Every example scene (the gallery and the POV-Ray comparison masks) loads, compiles
/// and renders with every pixel finite.
#[test]
fn example_scenes_render_without_nan_or_infinity() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    for file in [
        "scenes/csg.glint",
        "scenes/blobs.glint",
        "scenes/implicit.glint",
        "bench/povray/csg.glint",
        "bench/povray/blobs.glint",
        "bench/povray/implicit.glint",
    ] {
        let mut desc = load_scene(&root.join(file)).unwrap_or_else(|e| panic!("{e}"));
        // Small but with every object in view.
        desc.settings.width = 80;
        desc.settings.height = 60;
        desc.settings.samples_per_axis = 1;
        let scene = compile(&desc).unwrap_or_else(|e| panic!("{file}: {e}"));
        let (image, _) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled");
        let mut lit = 0;
        for y in 0..60 {
            for x in 0..80 {
                let c = image.get(x, y);
                assert!(c.is_finite(), "{file}: pixel {x},{y} is {c}");
                lit += (c.max_element() > 0.0) as u32;
            }
        }
        assert!(lit > 400, "{file}: only {lit} pixels see anything");
        assert!(desc.objects.iter().any(|o| matches!(o.kind, NodeKind::Solid(_))), "{file} shows no solid");
    }
}
