//! Mistakes in course scenefiles: malformed input is an error at its file, line and
//! column with a message that says what is wrong; harmless oddities are warnings that
//! say where they are; and no input makes the readers panic.

use std::path::Path;

use glint_scene::course::{CourseOptions, parse_json, parse_xml};
use glint_scene::{Loaded, SceneError, SceneErrorKind};

fn xml(text: &str) -> Result<Loaded, SceneError> {
    parse_xml(text, "scene.xml", Path::new("scenes"), CourseOptions::default())
}

fn json(text: &str) -> Result<Loaded, SceneError> {
    parse_json(text, "scene.json", Path::new("scenes"), CourseOptions::default())
}

/// Asserts an error at `line:column` whose message contains `fragment`.
#[track_caller]
fn assert_error(result: Result<Loaded, SceneError>, line: u32, column: u32, fragment: &str) -> SceneError {
    let e = match result {
        Ok(loaded) => panic!("expected an error, got a scene with warnings {:?}", loaded.warnings),
        Err(e) => e,
    };
    assert_eq!((e.line(), e.column()), (line, column), "wrong position for: {e}");
    assert!(e.message.contains(fragment), "message {:?} lacks {fragment:?}", e.message);
    e
}

const CAMERA: &str = r#""cameraData": {"position": [0, 0, 5], "up": [0, 1, 0], "look": [0, 0, -1], "heightAngle": 45}"#;
const GLOBAL: &str = r#""globalData": {"ambientCoeff": 0.5, "diffuseCoeff": 0.5, "specularCoeff": 0.5}"#;

fn json_with_groups(groups: &str) -> String {
    format!("{{{GLOBAL},\n{CAMERA},\n\"groups\": {groups}}}")
}

#[test]
fn malformed_xml_is_a_syntax_error_at_its_place() {
    let e = assert_error(xml("<scenefile>\n  <globaldata>\n</scenefile>"), 3, 1, "malformed XML");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
    assert_eq!(e.to_string(), "scene.xml:3:1: malformed XML: expected 'globaldata' tag, not 'scenefile'");
    assert_error(xml("<scenefile>\n<pos x=\"1\" x=\"2\"/></scenefile>"), 2, 12, "malformed XML");
}

#[test]
fn malformed_json_is_a_syntax_error_at_its_place() {
    let e = assert_error(json("{\n  \"globalData\": {\"ambientCoeff\": 0.5,}\n}"), 2, 38, "trailing comma");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
    assert_eq!(e.to_string(), "scene.json:2:38: a trailing comma is not allowed before '}'");
    assert_error(json("{\"a\": [1, 2\n"), 2, 1, "expected ',' or ']'");
}

#[test]
fn xml_meaning_errors_point_at_the_attribute_or_element() {
    let root = |body: &str| {
        format!(
            "<scenefile>\n<object type=\"tree\" name=\"root\"><transblock>\n{body}\n</transblock></object></scenefile>"
        )
    };
    assert_error(
        xml(&root(r#"<object type="primitive" name="sphre"/>"#)),
        3,
        32,
        "unknown primitive 'sphre'; expected one of: cube",
    );
    assert_error(xml(&root(r#"<translate x="1" y="two" z="3"/>"#)), 3, 21, "y=\"two\" of <translate> is not a number");
    assert_error(xml(&root(r#"<scale x="1" y="1"/>"#)), 3, 1, "<scale> needs the attribute z=");
    assert_error(xml(&root(r#"<scale x="1" y="0" z="1"/>"#)), 3, 1, "zero component");
    assert_error(xml(&root(r#"<rotate x="0" y="0" z="0" angle="10"/>"#)), 3, 1, "axis is (0, 0, 0)");
    assert_error(xml(&root(r#"<object type="master" name="chair"/>"#)), 3, 29, "unknown master object 'chair'");
    assert_error(xml(&root(r#"<object type="thing"/>"#)), 3, 15, "unknown type \"thing\"");
    assert_error(xml(&root(r#"<matrix><row a="1" b="0" c="0" d="0"/></matrix>"#)), 3, 1, "needs 4 rows");
    assert_error(xml(&root(r#"<object type="master" name="root"/>"#)), 3, 1, "'root' contains itself: root -> root");
    assert_error(xml("<scene/>"), 1, 1, "starts with <scenefile>");
    assert_error(
        xml("<scenefile>\n<object type=\"tree\" name=\"x\"/></scenefile>"),
        1,
        1,
        "no <object type=\"tree\" name=\"root\">",
    );
    assert_error(
        xml("<scenefile><lightdata>\n<type v=\"laser\"/></lightdata></scenefile>"),
        2,
        10,
        "unknown light type 'laser'; expected one of: point, directional, spot, area",
    );
    assert_error(
        xml(
            "<scenefile>\n<cameradata><look x=\"0\" y=\"0\" z=\"-1\"/>\n<focus x=\"0\" y=\"0\" z=\"0\"/></cameradata></scenefile>",
        ),
        3,
        1,
        "both <look> and <focus>",
    );
}

#[test]
fn json_meaning_errors_point_at_the_value() {
    assert_error(json(&json_with_groups("[{\"translate\": [1, 2]}]")), 3, 26, "\"translate\" needs 3 numbers");
    assert_error(
        json(&json_with_groups("[{\"primitives\": [{\"type\": \"sphre\"}]}]")),
        3,
        37,
        "unknown primitive type \"sphre\"; expected one of: cube, sphere",
    );
    assert_error(
        json(&json_with_groups("[{\"scale\": [1, \"2\", 1]}]")),
        3,
        26,
        "\"scale\" must be a number, found a string",
    );
    assert_error(
        json(&json_with_groups("[{\"lights\": [{\"type\": \"point\", \"color\": [1, 1, 1]}]}]")),
        3,
        24,
        "a point light needs \"attenuationCoeff\"",
    );
    assert_error(json(&json_with_groups("{}")), 3, 11, "\"groups\" must be an array");
    assert_error(json(&format!("{{{GLOBAL}}}")), 1, 1, "the scene needs the field \"cameraData\"");
    assert_error(
        json(&format!(
            "{{{GLOBAL},\n\"cameraData\": {{\"position\": [0, 0, 5], \"up\": [0, 1, 0], \"heightAngle\": 45}}}}"
        )),
        2,
        15,
        "needs \"look\" (a direction) or \"focus\"",
    );
    assert_error(
        json(&format!(
            "{{{GLOBAL},\n\"cameraData\": {{\"position\": [0, 0, 5], \"up\": [0, 0, -1], \"look\": [0, 0, -2], \"heightAngle\": 45}}}}"
        )),
        2,
        15,
        "parallel to its look vector",
    );
    let cycle = format!(
        "{{{GLOBAL},\n{CAMERA},\n\"templateGroups\": [{{\"name\": \"a\", \"groups\": [{{\"name\": \"a\"}}]}}],\n\"groups\": [{{\"name\": \"a\"}}]}}"
    );
    assert_error(json(&cycle), 3, 45, "'a' contains itself: a -> a");
}

#[test]
fn a_missing_texture_is_an_error_naming_file_and_line_or_a_warning_when_lenient() {
    let text =
        json_with_groups("[{\"primitives\": [{\"type\": \"cube\",\n  \"textureFile\": \"textures/none.png\"}]}]");
    let e = assert_error(json(&text), 4, 18, "texture file 'textures/none.png' not found");
    assert_eq!(e.kind, SceneErrorKind::Io);
    assert!(e.to_string().starts_with("scene.json:4:18: "), "{e}");
    let lenient =
        parse_json(&text, "scene.json", Path::new("scenes"), CourseOptions { strict_textures: false }).unwrap();
    assert_eq!(lenient.scene.materials[0].texture, None);
    assert_eq!(lenient.warnings.len(), 1);
    assert!(lenient.warnings[0].starts_with("scene.json:4:18: texture file"), "{:?}", lenient.warnings);
    assert!(lenient.warnings[0].ends_with("rendered without its texture"), "{:?}", lenient.warnings);

    let xml_text = "<scenefile><object type=\"tree\" name=\"root\"><transblock>\n<object type=\"primitive\" name=\"cube\">\n  <texture file=\"image/none.png\"/></object></transblock></object></scenefile>";
    let e = assert_error(xml(xml_text), 3, 3, "texture file 'image/none.png' not found");
    assert_eq!(e.kind, SceneErrorKind::Io);
}

#[test]
fn unknown_elements_and_fields_are_warnings_at_their_place() {
    let loaded = xml("<scenefile>\n  <fog v=\"1\"/>\n<object type=\"tree\" name=\"root\"><transblock>\n<object type=\"primitive\" name=\"cube\"><sparkle v=\"2\"/><bumpmap file=\"b.png\"/></object>\n</transblock></object></scenefile>")
        .unwrap();
    assert_eq!(
        loaded.warnings,
        vec![
            "scene.xml:2:3: unknown element <fog> in <scenefile> is ignored; expected one of: globaldata, cameradata, lightdata, object",
            "scene.xml:4:38: unknown element <sparkle> in a primitive is ignored; expected one of: diffuse, ambient, specular, reflective, transparent, emissive, shininess, ior, blend, texture, bumpmap",
            "scene.xml:4:54: bump maps are not supported; <bumpmap> is ignored",
        ]
    );
    assert_eq!(loaded.scene.objects.len(), 1);

    let loaded =
        json(&json_with_groups("[{\"colour\": [1, 0, 0],\n \"primitives\": [{\"type\": \"cube\", \"glow\": 1}]}]"))
            .unwrap();
    assert_eq!(loaded.warnings.len(), 2, "{:?}", loaded.warnings);
    assert!(
        loaded.warnings[0].starts_with("scene.json:3:13: unknown field \"colour\" in a group is ignored"),
        "{:?}",
        loaded.warnings
    );
    assert!(
        loaded.warnings[1].starts_with("scene.json:4:34: unknown field \"glow\" in a primitive"),
        "{:?}",
        loaded.warnings
    );
}

#[test]
fn no_input_makes_the_readers_panic() {
    let xml_text = include_str!("course/xml/test_feature/attenuation.xml");
    let json_text = include_str!("course/json/illuminate/required/spot_light/spot_light_1.json");
    // Every prefix of a real file: each is either read or refused, never a panic.
    for end in (0..xml_text.len()).filter(|&i| xml_text.is_char_boundary(i)) {
        let _ = xml(&xml_text[..end]);
    }
    for end in (0..json_text.len()).filter(|&i| json_text.is_char_boundary(i)) {
        let _ = json(&json_text[..end]);
    }
    for text in ["", "{", "[]", "null", "{\"globalData\": 1}", "\u{feff}{}", &"[".repeat(100_000)] {
        let _ = json(text);
    }
    for text in ["", "<", "<scenefile", "<scenefile/>", "<!DOCTYPE x [<!ENTITY a \"b\">]><scenefile/>"] {
        let _ = xml(text);
    }
}
