//! Keyframed properties in `.glint` scenes: linear and smooth interpolation, frames and
//! seconds, any property of any node, and located errors for broken tracks.

use std::path::Path;

use glam::Vec3;
use glint_core::desc::{SceneDesc, TransformOp};
use glint_scene::parse_scene_at;

fn at(text: &str, frame: f64) -> SceneDesc {
    parse_scene_at(text, "anim.glint", Path::new("."), frame).unwrap_or_else(|e| panic!("{e}"))
}

fn error(text: &str, frame: f64) -> String {
    parse_scene_at(text, "anim.glint", Path::new("."), frame).expect_err("a broken track").to_string()
}

/// The first transform of the first object.
fn first_translate(scene: &SceneDesc) -> Vec3 {
    match scene.objects[0].transform[0] {
        TransformOp::Translate(t) => t,
        ref other => panic!("not a translation: {other:?}"),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn linear_keys_interpolate_and_hold_outside() {
    let text = "sphere { translate { frame 10 [0 0 0]  frame 20 [4 2 -6] } }";
    for (frame, want) in [
        (0.0, Vec3::ZERO),
        (10.0, Vec3::ZERO),
        (12.5, Vec3::new(1.0, 0.5, -1.5)),
        (15.0, Vec3::new(2.0, 1.0, -3.0)),
        (20.0, Vec3::new(4.0, 2.0, -6.0)),
        (99.0, Vec3::new(4.0, 2.0, -6.0)),
    ] {
        let got = first_translate(&at(text, frame));
        assert!(close(got, want), "frame {frame}: {got} != {want}");
    }
}

#[test]
fn seconds_are_read_at_the_scenes_frame_rate() {
    let text = "settings { fps 30 frames [0 60] }\nsphere { translate { second 0 [0 0 0]  second 2 [6 0 0] } }";
    let scene = at(text, 15.0);
    assert!(close(first_translate(&scene), Vec3::new(1.5, 0.0, 0.0)));
    assert_eq!((scene.settings.fps, scene.settings.frames), (30.0, Some([0, 60])));
    // At the default 24 fps, second 2 is frame 48.
    let default_rate = "sphere { translate { second 0 [0 0 0]  second 2 [6 0 0] } }";
    assert!(close(first_translate(&at(default_rate, 24.0)), Vec3::new(3.0, 0.0, 0.0)));
}

#[test]
fn smooth_keys_ease_in_and_out_and_pass_every_key_without_a_corner() {
    let two = "sphere { translate { ease \"smooth\"  frame 0 [0 0 0]  frame 4 [1 0 0] } }";
    let x = |text: &str, frame: f64| first_translate(&at(text, frame)).x as f64;
    // Hermite with flat ends: h01(s) = 3s² − 2s³.
    assert!((x(two, 1.0) - 0.156_25).abs() < 1e-6);
    assert!((x(two, 2.0) - 0.5).abs() < 1e-6);
    assert!((x(two, 3.0) - 0.843_75).abs() < 1e-6);
    let three = "sphere { translate { ease \"smooth\" frame 0 [0 0 0] frame 10 [1 0 0] frame 30 [5 0 0] } }";
    assert!((x(three, 10.0) - 1.0).abs() < 1e-6, "passes through the middle key");
    // The slope is the same on both sides of the middle key: (5 − 0)/30 per frame.
    let h = 1e-3;
    let left = (x(three, 10.0) - x(three, 10.0 - h)) / h;
    let right = (x(three, 10.0 + h) - x(three, 10.0)) / h;
    assert!((left - 1.0 / 6.0).abs() < 1e-3 && (right - 1.0 / 6.0).abs() < 1e-3, "{left} {right}");
}

#[test]
fn any_property_animates_and_strings_hold_until_the_next_key() {
    let text = r#"
        camera { eye { frame 0 [0 1 10]  frame 10 [10 1 0] }  look_at [0 0 0] }
        light point { position [0 5 0] color { frame 0 [1 1 1]  frame 10 [0 0 0] } }
        material "a" { diffuse [1 0 0] }
        material "b" { diffuse [0 0 1] }
        material "glow" { diffuse { frame 0 0.2  frame 10 0.8 } }
        sphere { material { frame 0 "a"  frame 5 "b" } }
        cube { rotate { frame 0 [0 1 0] 0  frame 10 [0 1 0] 90 } }
    "#;
    let scene = at(text, 2.5);
    assert!(close(scene.camera.eye, Vec3::new(2.5, 1.0, 7.5)));
    let glint_core::desc::LightDesc::Point { color, .. } = scene.lights[0] else { panic!() };
    assert!(close(color, Vec3::splat(0.75)));
    assert!(close(scene.materials[2].diffuse, Vec3::splat(0.35)));
    let material = |scene: &SceneDesc| match scene.objects[0].kind {
        glint_core::desc::NodeKind::Shape { material, .. } => material,
        _ => panic!(),
    };
    assert_eq!(material(&scene), 0, "still 'a' before frame 5");
    assert_eq!(material(&at(text, 5.0)), 1, "'b' from frame 5");
    let TransformOp::Rotate { degrees, .. } = scene.objects[1].transform[0] else { panic!() };
    assert!((degrees - 22.5).abs() < 1e-4);
}

#[test]
fn broken_tracks_are_located_errors() {
    let cases = [
        ("sphere { translate { frame 5 [0 0 0] frame 2 [1 1 1] } }", "1:38", "increasing time order"),
        ("sphere { translate { frame 0 [0 0 0] frame 2 1 } }", "1:38", "other kinds of values"),
        ("sphere { translate { frame 0 [0 0] frame 2 [1 1] } }", "1:10", "3 numbers"),
        ("sphere { translate { ease \"bouncy\" frame 0 [0 0 0] } }", "1:22", "\"linear\" or \"smooth\""),
        ("sphere { translate { frame \"x\" [0 0 0] } }", "1:22", "starts with its time"),
        ("settings { frames [5 2] }", "1:19", "first <= last"),
    ];
    for (text, at_pos, message) in cases {
        let e = error(text, 1.0);
        assert!(e.contains(&format!("anim.glint:{at_pos}")) && e.contains(message), "{text}\n→ {e}");
    }
}

#[test]
fn fps_belongs_to_the_main_file() {
    let dir = std::env::temp_dir().join(format!("glint-anim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("inc.glint"), "settings { fps 30 }\n").unwrap();
    let e = parse_scene_at("include \"inc.glint\"", "main.glint", &dir, 0.0).expect_err("fps in an include");
    assert!(e.to_string().contains("inc.glint:1:12") && e.to_string().contains("main scene file"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
