//! Ray Tracer Challenge YAML errors name the file, line and column, and say what would
//! have been accepted.

use glint_scene::SceneErrorKind;
use glint_scene::challenge::parse_challenge;

const CAMERA: &str = "- add: camera
  width: 100
  height: 50
  field-of-view: 1.2
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
";

/// The error for `text`, checked to point at `line:column` and to mention `needle`.
fn error_at(text: &str, line: u32, column: u32, needle: &str) -> glint_scene::SceneError {
    let err = parse_challenge(text, "bad.yml").expect_err("the scene should be refused");
    assert_eq!((err.line, err.column), (line, column), "{err}");
    assert!(err.to_string().starts_with(&format!("bad.yml:{line}:{column}: ")), "{err}");
    assert!(err.message.contains(needle), "expected '{needle}' in: {err}");
    err
}

#[test]
fn malformed_yaml_is_a_syntax_error_at_its_line() {
    let err = error_at(&format!("{CAMERA}- add: sphere\n  transform: [[scale, 1, 1, 1]\n"), 10, 1, "invalid YAML");
    assert_eq!(err.kind, SceneErrorKind::Syntax);
    error_at(&format!("{CAMERA}- add: sphere\n  add: cube\n"), 9, 3, "twice");
}

#[test]
fn unknown_objects_transforms_and_patterns_list_the_alternatives() {
    error_at(
        &format!("{CAMERA}- add: sphre\n"),
        8,
        8,
        "unknown object 'sphre' (did you mean 'sphere'?); expected one of: camera, light, sphere",
    );
    error_at(
        &format!("{CAMERA}- add: cube\n  transform:\n    - [rotate, 1]\n"),
        10,
        8,
        "expected one of: translate, scale",
    );
    error_at(
        &format!("{CAMERA}- add: plane\n  material:\n    pattern:\n      type: checker\n"),
        11,
        13,
        "unknown pattern type 'checker' (did you mean 'checkers'?)",
    );
    error_at(&format!("{CAMERA}- remove: cube\n"), 8, 3, "starts with 'add: KIND'");
}

#[test]
fn wrong_values_point_at_the_value() {
    error_at(&format!("{CAMERA}- add: light\n  at: [1, 2]\n  intensity: [1, 1, 1]\n"), 9, 7, "list of 3 numbers");
    error_at(
        &format!("{CAMERA}- add: sphere\n  material:\n    diffuse: lots\n"),
        10,
        14,
        "'diffuse' must be a finite number",
    );
    error_at(&format!("{CAMERA}- add: sphere\n  material:\n    ambient: -1\n"), 10, 14, "0 or more");
    error_at(&format!("{CAMERA}- add: cube\n  transform:\n    - [scale, 1, 0, 1]\n"), 10, 7, "zero factor");
    error_at(&format!("{CAMERA}- add: cube\n  transform:\n    - [translate, 1, 2]\n"), 10, 7, "takes 3 numbers");
    error_at(&format!("{CAMERA}- add: cylinder\n  min: 2\n  max: 1\n"), 10, 8, "must be below 'max'");
    error_at(&CAMERA.replace("field-of-view: 1.2", "field-of-view: 4"), 4, 18, "between 0 and π");
    error_at(&CAMERA.replace("to: [0, 0, 0]", "to: [0, 0, -5]"), 6, 7, "must differ from 'from'");
}

#[test]
fn undefined_names_and_missing_keys_are_named() {
    error_at(
        &format!("{CAMERA}- add: sphere\n  material: glass\n"),
        9,
        13,
        "unknown material 'glass'; nothing is defined",
    );
    error_at(
        &format!("{CAMERA}- define: a\n  value: [[scale, 2, 2, 2]]\n- add: sphere\n  transform: [b]\n"),
        11,
        15,
        "unknown transform list 'b'; defined names: a",
    );
    error_at(&format!("{CAMERA}- define: m\n  extend: base\n  value: {{}}\n"), 9, 11, "unknown definition 'base'");
    error_at(&format!("{CAMERA}- add: light\n  intensity: [1, 1, 1]\n"), 8, 3, "needs 'at'");
    error_at("- add: sphere\n", 1, 1, "no camera");
    error_at(&CAMERA.replace("  width: 100\n", ""), 1, 3, "needs 'width'");
}

#[test]
fn a_file_that_is_not_a_list_of_items_is_refused() {
    error_at("camera: {}\n", 1, 1, "a list of '- add: …'");
    let err = parse_challenge("# nothing\n", "bad.yml").expect_err("empty");
    assert_eq!(err.line, 0);
    assert!(err.message.contains("holds no scene"), "{err}");
}
