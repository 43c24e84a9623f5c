//! Course scenes rendered small and compared with the course's own reference renders,
//! reduced to 128×96 (see `tests/course/SOURCES.md`).
//!
//! A 128×96 render with an 8×8 grid of samples per pixel traces exactly the pixel
//! centres of the 1024×768 reference and averages each 8×8 block, which is how the
//! references were reduced; so the tolerance only has to absorb the course renderer's
//! texture filtering and rounding, not a difference of resolution.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use glint_core::desc::{Features, LightDesc, Transfer};
use glint_core::render::render;
use glint_core::scene::compile;
use glint_scene::course::{CourseOptions, load_json, load_xml};
use glint_scene::{SceneFormat, load_any};

/// Mean absolute difference allowed, on the 0–255 scale, and the share of pixels that
/// may differ by more than 32 in some channel.
const MAX_MAE: f64 = 1.0;
const MAX_WRONG_SHARE: f64 = 0.01;

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/course").join(path)
}

const ILLUMINATE: Features =
    Features { shadows: true, reflections: true, refractions: false, textures: true, transparent_shadows: false };

/// Renders `scene` at 128×96 (8×8 samples per pixel) with `features` and compares it
/// with `reference-128x96.png`.
#[track_caller]
fn check(scene: &str, reference: &str, features: Features, directional_only: bool) {
    let path = data(scene);
    let options = CourseOptions::default();
    let loaded = if scene.ends_with(".xml") { load_xml(&path, options) } else { load_json(&path, options) }
        .unwrap_or_else(|e| panic!("{e}"));
    let mut desc = loaded.scene;
    desc.settings.width = 128;
    desc.settings.height = 96;
    desc.settings.samples_per_axis = 8;
    desc.settings.features = features;
    if directional_only {
        desc.lights.retain(|l| matches!(l, LightDesc::Directional { .. }));
    }
    assert_eq!(desc.settings.output_transfer, Transfer::Identity);
    let compiled = compile(&desc).expect("compiles");
    let (image, _) = render(&compiled, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    let ours = image.encode8(Transfer::Identity);
    let reference = image::open(data(&format!("reference/{reference}-128x96.png"))).expect("reference").to_rgb8();
    assert_eq!((reference.width(), reference.height()), (128, 96));
    let theirs = reference.as_raw();
    let mut sum = 0u64;
    let mut wrong = 0;
    for (p, q) in ours.chunks(3).zip(theirs.chunks(3)) {
        let d: Vec<u8> = p.iter().zip(q).map(|(a, b)| a.abs_diff(*b)).collect();
        sum += d.iter().map(|&x| u64::from(x)).sum::<u64>();
        wrong += usize::from(d.iter().any(|&x| x > 32));
    }
    let mae = sum as f64 / ours.len() as f64;
    let share = wrong as f64 / (128.0 * 96.0);
    assert!(
        mae <= MAX_MAE && share <= MAX_WRONG_SHARE,
        "{scene}: mean difference {mae:.2}/255 and {:.2} % wrong pixels against the course's reference",
        share * 100.0
    );
}

#[test]
fn unit_cone_matches_the_intersect_reference() {
    let off = Features {
        shadows: false,
        reflections: false,
        refractions: false,
        textures: false,
        transparent_shadows: false,
    };
    check("json/intersect/required/unit_cone.json", "unit_cone", off, true);
}

#[test]
fn texture_cube_matches_texture_blend_and_reflection() {
    check("json/illuminate/required/texture_tests/texture_cube.json", "texture_cube", ILLUMINATE, false);
}

#[test]
fn spot_light_matches_angle_and_penumbra() {
    check("json/illuminate/required/spot_light/spot_light_1.json", "spot_light_1", ILLUMINATE, false);
}

#[test]
fn shadow_special_case_matches() {
    check("json/illuminate/required/shadow/shadow_special_case.json", "shadow_special_case", ILLUMINATE, false);
}

#[test]
fn xml_attenuation_with_untyped_lights_matches() {
    check("xml/test_feature/attenuation.xml", "attenuation", ILLUMINATE, false);
}

#[test]
fn xml_chess_with_master_objects_matches() {
    check("xml/test_fun/chess_master.xml", "chess_master", ILLUMINATE, false);
}

#[test]
fn load_any_recognises_both_course_formats() {
    let xml = load_any(&data("xml/test_feature/attenuation.xml")).expect("loads");
    assert_eq!(xml.format, SceneFormat::CourseXml);
    assert_eq!(xml.scene.lights.len(), 1);
    let json = load_any(&data("json/illuminate/required/texture_tests/texture_cube.json")).expect("loads");
    assert_eq!(json.format, SceneFormat::CourseJson);
    assert_eq!(json.scene.textures.len(), 1);
    assert!(json.warnings.is_empty(), "{:?}", json.warnings);
}
