//! Mistakes in `.glint` files: each is reported at the right line and column, with a
//! message that says what is wrong and what is allowed, and no input makes the reader
//! panic.

use std::path::Path;

use glint_scene::{DEFAULT_SCENE_SOURCE, SceneError, SceneErrorKind, parse_scene};

fn error(source: &str) -> SceneError {
    match parse_scene(source, "scene.glint", Path::new("")) {
        Ok(scene) => panic!("expected an error for {source:?}, got {scene:?}"),
        Err(e) => e,
    }
}

/// Asserts the error's position and that its message contains `fragment`.
#[track_caller]
fn assert_error(source: &str, line: u32, column: u32, fragment: &str) -> SceneError {
    let e = error(source);
    assert_eq!((e.line(), e.column()), (line, column), "wrong position for: {e}");
    assert!(e.message.contains(fragment), "message {:?} lacks {fragment:?}", e.message);
    e
}

#[test]
fn display_is_file_line_column_message() {
    let e = error("material \"m\" {}\nsphere {\n    radus 2\n}");
    assert_eq!(
        e.to_string(),
        "scene.glint:3:5: unknown property 'radus' in 'sphere'; \
         expected one of: material, translate, rotate, scale, matrix"
    );
    assert_eq!(e.file, "scene.glint");
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert_eq!(e.location(), "scene.glint:3:5");
}

#[test]
fn unknown_property_lists_the_allowed_ones() {
    assert_error(
        "torus { radius 1 }",
        1,
        9,
        "expected one of: material, translate, rotate, scale, matrix, minor_radius",
    );
    assert_error("settings {\n  widht 5\n}", 2, 3, "unknown property 'widht' in 'settings'");
    assert_error(
        "light point { direction [0 1 0] }",
        1,
        15,
        "in 'light point'; expected one of: position, color, attenuation",
    );
}

#[test]
fn unknown_top_level_node_lists_the_allowed_ones() {
    let e = assert_error("\n\nspere {}", 3, 1, "unknown node 'spere' at the top level");
    assert!(
        e.message.contains("settings, camera, texture, material, light, define, use, include, group, moving, sphere")
    );
    assert_error("group { material \"x\" }", 1, 9, "unknown node 'material' in 'group'");
}

#[test]
fn wrong_arity_says_how_many_were_expected_and_found() {
    let e = assert_error("sphere {\n  translate [1 2]\n}", 2, 3, "");
    assert_eq!(e.message, "expected 3 numbers for 'translate', found 2");
    assert_error("sphere { scale [1 2] }", 1, 10, "expected 1 or 3 numbers for 'scale', found 2");
    assert_error("camera { fov }", 1, 10, "expected 1 number for 'fov', found none");
    assert_error("camera { eye 1 2 3 }", 1, 10, "found 3 separate numbers; write a vector in brackets");
    assert_error("camera { fov \"wide\" }", 1, 14, "found a string");
    assert_error("sphere { matrix [1 0 0 0] }", 1, 10, "expected 16 numbers for 'matrix', found 4");
    assert_error("cube { rotate 30 }", 1, 8, "expected an axis of 3 numbers and an angle");
    assert_error("cube { rotate [0 1 0] }", 1, 8, "found a vector of 3 numbers");
}

#[test]
fn unknown_material_names_the_known_ones() {
    let e = assert_error(
        "material \"red\" {}\nmaterial \"glass\" {}\ncube { material \"glas\" }",
        3,
        17,
        "unknown material 'glas'; known materials: glass, red",
    );
    assert!(e.message.contains("defined before they are used"));
    assert_error(
        "cube { material \"late\" }\nmaterial \"late\" {}",
        1,
        17,
        "no materials are defined before this line",
    );
    assert_error("material \"m\" { texture \"wood\" }", 1, 24, "unknown texture 'wood'; no textures are defined");
    assert_error("use \"tree\"", 1, 5, "unknown definition 'tree'");
}

#[test]
fn duplicate_names_point_at_the_second_definition() {
    assert_error("material \"m\" {}\nmaterial \"m\" {}", 2, 10, "material 'm' is already defined at scene.glint:1:10");
    assert_error("texture \"t\" checker\ntexture \"t\" checker", 2, 9, "texture 't' is already defined");
    assert_error("define \"d\" {}\ndefine \"d\" {}", 2, 8, "definition 'd' is already defined");
    assert_error(
        "cube {}\nmaterial \"default\" {}",
        2,
        10,
        "the object at scene.glint:1:1 already uses the built-in default",
    );
    assert_error("material \"m\" { kd 1 kd 2 }", 1, 21, "'kd' is set twice");
    assert_error("camera {}\ncamera {}", 2, 1, "'camera' is given twice");
}

#[test]
fn unterminated_string_points_at_its_opening_quote() {
    let e = assert_error("material \"m\" {}\nsphere { material \"m }\ncube {}", 2, 19, "unterminated string");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
}

#[test]
fn missing_closing_brace_points_at_the_open_brace() {
    let e = assert_error("group {\n  sphere {}\n  cube {\n", 3, 8, "missing '}'");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
    // The inner block is closed by the last brace, so the outer one is reported.
    assert_error("group {\n  sphere {\n}\ncube {}\n", 1, 7, "still open at the end of the file");
    assert_error("sphere {}\n}", 2, 1, "unexpected '}'");
    assert_error("sphere { translate [1 2 3 }", 1, 27, "expected a number or ']'");
}

#[test]
fn nan_and_infinity_are_not_numbers() {
    let e = assert_error("camera {\n  fov nan\n}", 2, 7, "'nan' is not a number");
    assert!(e.message.contains("finite"));
    assert_error("sphere { translate [1 inf 0] }", 1, 23, "'inf' is not a number");
    assert_error("sphere { scale 1e39 }", 1, 16, "out of range");
    assert_error("sphere { scale 1.5.2 }", 1, 16, "'1.5.2' is not a number");
}

#[test]
fn values_out_of_range_are_refused_with_the_allowed_range() {
    assert_error("settings { width 0 }", 1, 18, "from 1 to 16384");
    assert_error("settings { height 16385 }", 1, 19, "from 1 to 16384");
    assert_error("settings { width 2.5 }", 1, 18, "whole number");
    assert_error("settings { samples 65 }", 1, 20, "from 1 to 64");
    assert_error("settings { samples 0 }", 1, 20, "from 1 to 64");
    assert_error("camera { fov 180 }", 1, 14, "between 0 and 180");
    assert_error("camera { fov 0 }", 1, 14, "between 0 and 180");
    assert_error("material \"g\" { ior 0 }", 1, 20, "'ior' must be greater than 0");
    assert_error("material \"g\" { diffuse [1 -0.5 0] }", 1, 24, "must not be negative");
    assert_error("settings { background -1 }", 1, 23, "must not be negative");
    assert_error("material \"g\" { blend 2 }", 1, 22, "from 0 to 1");
    assert_error("torus { minor_radius 1 }", 1, 22, "between 0 and 1");
    assert_error("light spot { angle 20 penumbra 25 }", 1, 23, "must not exceed 'angle'");
    assert_error("light point { attenuation [0 0 0] }", 1, 27, "use [1 0 0] for no falloff");
}

#[test]
fn degenerate_transforms_are_refused() {
    assert_error("sphere { scale [1 0 1] }", 1, 16, "zero component");
    assert_error("sphere { scale 0 }", 1, 16, "zero component");
    assert_error("sphere { rotate [0 0 0] 10 }", 1, 17, "axis must be non-zero");
    assert_error(
        "sphere { matrix [1 0 0 0  0 1 0 0  0 0 1 0  0 0 1 1] }",
        1,
        17,
        "last row of 'matrix' must be 0 0 0 1",
    );
    assert_error("sphere { matrix [1 0 0 0  0 1 0 0  0 0 0 0  0 0 0 1] }", 1, 17, "singular");
}

#[test]
fn degenerate_cameras_and_lights_are_refused() {
    assert_error("camera { look [0 0 0] }", 1, 15, "non-zero");
    assert_error("camera { up [0 0 0] }", 1, 13, "non-zero");
    assert_error("camera { eye [1 2 3] look_at [1 2 3] }", 1, 30, "away from 'eye'");
    assert_error("camera { look [0 -1 0] up [0 2 0] }", 1, 24, "parallel");
    assert_error("camera { eye [0 5 0] look_at [0 0 0] }", 1, 22, "parallel");
    assert_error("camera { look [0 0 -1] look_at [0 0 0] }", 1, 24, "not both");
    assert_error("light directional { direction [0 0 0] }", 1, 31, "non-zero");
}

#[test]
fn light_and_texture_need_a_known_type() {
    assert_error("light { position [0 1 0] }", 1, 7, "needs its type before the block");
    assert_error("light\n", 1, 1, "expected a light type after 'light'; one of: point, directional, spot");
    assert_error("light area {}", 1, 7, "unknown light type 'area'");
    assert_error("light \"key\" point {}", 1, 7, "'light' takes no values");
    assert_error("texture \"t\" marble {}", 1, 13, "unknown texture type 'marble'; expected one of: checker, image");
    assert_error("texture checker {}", 1, 1, "expected a texture name in quotes");
    assert_error("texture \"t\" image {}", 1, 13, "needs its file");
}

#[test]
fn misplaced_values_and_blocks_are_refused() {
    assert_error("sphere 2 {}", 1, 8, "'sphere' takes no values");
    assert_error("sphere { translate [0 1 0] { } }", 1, 28, "does not take a block");
    assert_error("define \"d\" { translate [1 0 0] }", 1, 14, "transforms belong on the 'use'");
    assert_error("use \"x\" { cube {} }", 1, 5, "unknown definition");
    assert_error("define \"x\" {} use \"x\" { cube {} }", 1, 25, "unknown property 'cube' in 'use'");
    assert_error("sphere { flag true }", 1, 10, "unknown property 'flag'");
    assert_error("settings { width true }", 1, 18, "found a boolean");
    assert_error("a , b", 1, 3, "commas are only allowed");
    assert_error("cube {} @", 1, 9, "unexpected character '@'");
}

#[test]
fn no_input_makes_the_reader_panic() {
    // Every prefix of a real scene (cut anywhere), plus deterministic mutations of it.
    let source = DEFAULT_SCENE_SOURCE;
    for (cut, _) in source.char_indices().step_by(3) {
        let _ = parse_scene(&source[..cut], "cut.glint", Path::new(""));
    }
    let bytes = source.as_bytes();
    let alphabet = b" {}[]\"\\#,-.0123456789eE\nabcxyz";
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..2000 {
        let mut mutated = bytes.to_vec();
        for _ in 0..3 {
            let at = (next() % mutated.len() as u64) as usize;
            mutated[at] = alphabet[(next() % alphabet.len() as u64) as usize];
        }
        let text = String::from_utf8_lossy(&mutated);
        let _ = parse_scene(&text, "mutated.glint", Path::new(""));
    }
}

#[test]
fn exponential_use_is_bounded() {
    let mut source = String::from("define \"d0\" { sphere {} }\n");
    for i in 1..40 {
        source.push_str(&format!("define \"d{i}\" {{ use \"d{}\" use \"d{}\" }}\n", i - 1, i - 1));
    }
    source.push_str("use \"d39\"\n");
    let e = error(&source);
    assert!(e.message.contains("more than 1000000 objects"), "{e}");
}

#[test]
fn integrator_needs_a_known_type_and_its_own_properties() {
    assert_error(
        "settings { integrator bdpt { } }",
        1,
        23,
        "unknown integrator type 'bdpt'; expected one of: whitted, path",
    );
    assert_error(
        "settings { integrator }",
        1,
        12,
        "expected an integrator type after 'integrator'; one of: whitted, path",
    );
    assert_error("settings { integrator { max_depth 3 } }", 1, 23, "needs its type before the block");
    assert_error("settings { integrator whitted { max_depth 3 } }", 1, 31, "'integrator whitted' takes no properties");
    assert_error(
        "settings { integrator path { depth 3 } }",
        1,
        30,
        "unknown property 'depth' in 'integrator path'; expected one of: max_depth, rr_depth, sampler",
    );
    assert_error(
        "settings { integrator path { sampler \"halton\" } }",
        1,
        38,
        "'sampler' must be \"sobol\" or \"independent\"",
    );
    assert_error("settings { integrator path { sampler } }", 1, 30, "(in quotes), found nothing");
    assert_error("settings { integrator path { rr_depth 0 } }", 1, 39, "'rr_depth' must be a whole number from 1 to");
    assert_error("settings { integrator path { max_depth 2 max_depth 3 } }", 1, 42, "'max_depth' is set twice");
    assert_error("settings { integrator whitted integrator path }", 1, 31, "'integrator' is set twice");
}

#[test]
fn path_depth_and_spp_out_of_range_name_what_is_allowed() {
    for (value, column) in [("-2", 40), ("2.5", 40), ("16777217", 40), ("\"forever\"", 40), ("true", 40)] {
        let source = format!("settings {{ integrator path {{ max_depth {value} }} }}");
        assert_error(&source, 1, column, "or -1 or \"unlimited\" for no limit");
    }
    assert_error("settings { integrator path { max_depth } }", 1, 30, "found nothing");
    assert_error("settings { spp 0 }", 1, 16, "'spp' must be a whole number from 1 to 1048576");
    assert_error("settings { spp 1048577 }", 1, 16, "from 1 to 1048576");
    assert_error("settings { spp 2.5 }", 1, 16, "whole number");
}

#[test]
fn bsdf_needs_a_known_type_and_lists_the_kinds() {
    assert_error(
        "material \"m\" { bsdf lambert { } }",
        1,
        21,
        "unknown bsdf type 'lambert'; expected one of: diffuse, conductor, dielectric, thin_dielectric, plastic, \
         metallic_roughness",
    );
    assert_error("material \"m\" { bsdf }", 1, 16, "expected a bsdf type after 'bsdf'; one of: diffuse, conductor");
    assert_error("material \"m\" { bsdf { reflectance 1 } }", 1, 21, "needs its type before the block");
    assert_error("material \"m\" { bsdf \"diffuse\" }", 1, 21, "'bsdf' takes no values");
    assert_error("material \"m\" { bsdf diffuse 0.5 }", 1, 29, "'diffuse' takes no values");
    assert_error("material \"m\" { bsdf diffuse bsdf plastic }", 1, 29, "'bsdf' is set twice");
}

#[test]
fn bsdf_properties_are_checked_per_kind() {
    assert_error(
        "material \"m\" { bsdf diffuse { roughness 0.1 } }",
        1,
        31,
        "unknown property 'roughness' in 'bsdf diffuse'; expected one of: reflectance, texture",
    );
    assert_error(
        "material \"m\" { bsdf thin_dielectric { roughness 0.1 } }",
        1,
        39,
        "in 'bsdf thin_dielectric'; expected one of: ior, ext_ior, reflectance, transmittance",
    );
    assert_error(
        "material \"m\" { bsdf conductor { ior 1.5 } }",
        1,
        33,
        "expected one of: eta, k, specular, specular_texture, roughness, roughness_texture",
    );
    assert_error("material \"m\" { bsdf plastic { ior 1.5 ior 1.4 } }", 1, 39, "'ior' is set twice in 'bsdf plastic'");
}

#[test]
fn bsdf_values_out_of_range_are_refused() {
    assert_error("material \"m\" { bsdf conductor { roughness -0.1 } }", 1, 43, "'roughness' must be 0 or more");
    assert_error("material \"m\" { bsdf dielectric { roughness -1 } }", 1, 44, "'roughness' must be 0 or more");
    assert_error("material \"m\" { bsdf dielectric { ior 0 } }", 1, 38, "'ior' must be greater than 0");
    assert_error("material \"m\" { bsdf plastic { ext_ior -1 } }", 1, 39, "'ext_ior' must be greater than 0");
    assert_error("material \"m\" { bsdf conductor { eta [0.2 -1 1] } }", 1, 37, "'eta' must not be negative");
    assert_error("material \"m\" { bsdf conductor { k -1 } }", 1, 35, "'k' must not be negative");
    assert_error("material \"m\" { bsdf diffuse { reflectance -0.5 } }", 1, 43, "must not be negative");
    assert_error("material \"m\" { bsdf conductor { eta [1 2] } }", 1, 33, "expected 1 or 3 numbers for 'eta'");
    assert_error("material \"m\" { bsdf plastic { nonlinear 1 } }", 1, 41, "expected true or false after 'nonlinear'");
    assert_error(
        "material \"m\" { bsdf metallic_roughness { metallic 1.5 } }",
        1,
        51,
        "'metallic' must be from 0 (plastic) to 1 (metal)",
    );
    assert_error(
        "material \"m\" { bsdf diffuse { texture \"wood\" } }",
        1,
        39,
        "unknown texture 'wood'; no textures are defined",
    );
    assert_error(
        "texture \"t\" checker\nmaterial \"m\" { bsdf conductor { roughness_texture \"r\" } }",
        2,
        51,
        "unknown texture 'r'; known textures: t",
    );
}

#[test]
fn emission_and_two_sided_take_their_types() {
    assert_error("material \"m\" { emission [1 -1 1] }", 1, 25, "colour 'emission' must not be negative");
    assert_error("material \"m\" { emission [1 1] }", 1, 16, "expected 1 or 3 numbers for 'emission'");
    assert_error("material \"m\" { two_sided 0 }", 1, 26, "expected true or false after 'two_sided'");
}

#[test]
fn environment_lights_are_checked() {
    assert_error(
        "light environment { color 1 }",
        1,
        21,
        "unknown property 'color' in 'light environment'; expected one of: radiance, texture, translate, rotate",
    );
    assert_error("light environment { radiance -1 }", 1, 30, "must not be negative");
    assert_error("light environment { texture \"sky\" }", 1, 29, "unknown texture 'sky'");
    assert_error(
        "texture \"c\" checker\nlight environment { texture \"c\" }",
        2,
        29,
        "texture 'c' is not an image; an environment needs an image texture",
    );
    assert_error("light environment { rotate [0 0 0] 10 }", 1, 28, "axis must be non-zero");
    assert_error(
        "light environment\nlight environment { radiance 2 }",
        2,
        1,
        "at most one environment light; the first is at scene.glint:1:1",
    );
}

#[test]
fn rectangle_is_a_shape_without_an_inside() {
    assert_error("rectangle 2", 1, 11, "'rectangle' takes no values");
    assert_error("rectangle { minor_radius 0.3 }", 1, 13, "unknown property 'minor_radius' in 'rectangle'");
    assert_error("union { rectangle { } sphere { } }", 1, 9, "a rectangle has no inside");
}

#[test]
fn a_highlight_is_phong_or_blinn() {
    let e = error("material \"m\" {\n  highlight \"cook-torrance\"\n}");
    let text = e.to_string();
    assert!(text.starts_with("scene.glint:2:"), "{text}");
    assert!(text.contains("phong") && text.contains("blinn"), "{text}");
    assert_error("material \"m\" { textured_ambient 1 }", 1, 33, "expected true or false after 'textured_ambient'");
}
