//! `.glint` files on disk: loading, includes relative to the including file, include
//! cycles, and image textures (sRGB decoding, row order, errors that name the file).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Vec2, Vec3};
use glint_core::desc::{EnvironmentDesc, LightDesc, NodeKind, TextureDesc, TransformOp};
use glint_scene::texture_io::{MAX_TEXTURE_SIDE, srgb_to_linear};
use glint_scene::{SceneErrorKind, load_scene, parse_scene};

/// A fresh folder under the system temp dir, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(test: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let dir = std::env::temp_dir().join(format!("glint-native-{test}-{}-{n}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        Self(dir)
    }

    /// Writes `text` to `name` (which may contain sub-folders) and returns its path.
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).expect("create sub-folder");
        }
        std::fs::write(&path, text).expect("write temp file");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

#[test]
fn load_scene_reads_a_file_and_names_origins_after_it() {
    let dir = TempDir::new("load");
    let path = dir.write("a.glint", "settings { width 10 }\n\nsphere {}");
    let scene = load_scene(&path).expect("loads");
    assert_eq!(scene.settings.width, 10);
    assert_eq!(scene.objects[0].origin, format!("{}:3:1", path.display()));
}

#[test]
fn a_missing_scene_file_names_the_file() {
    let dir = TempDir::new("missing");
    let path = dir.0.join("nope.glint");
    let e = load_scene(&path).expect_err("missing");
    assert_eq!(e.kind, SceneErrorKind::Io);
    assert_eq!(e.file, path.display().to_string());
    assert_eq!(e.line(), 0);
    assert!(e.to_string().starts_with(&format!("{}: cannot read scene file", path.display())), "{e}");
}

#[test]
fn includes_are_relative_to_the_including_file() {
    let dir = TempDir::new("include");
    dir.write(
        "lib/materials.glint",
        "include \"colors/red.glint\"\nmaterial \"blue\" { diffuse [0 0 1] }\ndefine \"pair\" { sphere { material \"red\" } cube {} }",
    );
    dir.write("lib/colors/red.glint", "material \"red\" { diffuse [1 0 0] }");
    let main = dir
        .write("scenes/main.glint", "include \"../lib/materials.glint\"\nsphere { material \"blue\" }\nuse \"pair\"");
    let scene = load_scene(&main).expect("loads");
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["red", "blue", "default"]);
    assert_eq!(scene.materials[0].diffuse, Vec3::X);
    assert_eq!(scene.objects.len(), 2);
    let NodeKind::Group(pair) = &scene.objects[1].kind else {
        panic!("use gives a group");
    };
    assert_eq!(pair.len(), 2);
    assert!(pair[0].origin.ends_with("materials.glint:3:17"), "{}", pair[0].origin);
}

#[test]
fn parse_scene_resolves_includes_from_base_dir() {
    let dir = TempDir::new("base");
    dir.write("m.glint", "material \"m\" { kd 0.5 }");
    let scene = parse_scene("include \"m.glint\" cube { material \"m\" }", "inline", &dir.0).expect("parses");
    assert_eq!(scene.materials[0].kd, 0.5);
}

#[test]
fn errors_inside_an_included_file_name_that_file() {
    let dir = TempDir::new("inner-error");
    let inner = dir.write("inner.glint", "\nmaterial \"x\" { glow 1 }");
    let main = dir.write("main.glint", "include \"inner.glint\"");
    let e = load_scene(&main).expect_err("bad inner file");
    assert_eq!(e.file, inner.display().to_string());
    assert_eq!((e.line(), e.column()), (2, 16));
}

#[test]
fn a_missing_include_names_the_file_and_the_including_line() {
    let dir = TempDir::new("missing-include");
    let main = dir.write("main.glint", "sphere {}\ninclude \"gone.glint\"");
    let e = load_scene(&main).expect_err("missing include");
    assert_eq!(e.kind, SceneErrorKind::Io);
    assert_eq!(e.file, main.display().to_string());
    assert_eq!((e.line(), e.column()), (2, 9));
    assert!(e.message.contains("gone.glint"), "{e}");
}

#[test]
fn include_cycles_are_refused_naming_the_chain() {
    let dir = TempDir::new("cycle");
    dir.write("b.glint", "sphere {}\ninclude \"c.glint\"");
    dir.write("c.glint", "include \"b.glint\"");
    let main = dir.write("a.glint", "include \"b.glint\"");
    let e = load_scene(&main).expect_err("cycle");
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert!(e.file.ends_with("c.glint"), "{e}");
    assert_eq!((e.line(), e.column()), (1, 9));
    assert!(e.message.starts_with("include cycle: "), "{e}");
    let chain: Vec<&str> = e.message["include cycle: ".len()..].split(" -> ").collect();
    assert_eq!(chain.len(), 3, "{e}");
    assert!(chain[0].ends_with("b.glint") && chain[1].ends_with("c.glint") && chain[2].ends_with("b.glint"));

    let selfish = dir.write("self.glint", "include \"self.glint\"");
    let e = load_scene(&selfish).expect_err("self include");
    assert!(e.message.starts_with("include cycle: "), "{e}");
}

/// Writes a 2×2 RGB PNG: top row red, white; bottom row mid-grey (128), black.
fn write_png(dir: &TempDir, name: &str) -> PathBuf {
    let path = dir.0.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).expect("create sub-folder");
    }
    let pixels = [255, 0, 0, 255, 255, 255, 128, 128, 128, 0, 0, 0];
    image::save_buffer(&path, &pixels, 2, 2, image::ExtendedColorType::Rgb8).expect("save png");
    path
}

#[test]
fn image_textures_are_decoded_to_linear_rgb_top_row_first() {
    let dir = TempDir::new("png");
    write_png(&dir, "textures/tex.png");
    let main = dir.write(
        "main.glint",
        "texture \"wood\" image { file \"textures/tex.png\" }\n\
         material \"m\" { texture \"wood\" repeat [2 3] }",
    );
    let scene = load_scene(&main).expect("loads");
    let TextureDesc::Image { name, width, height, texels, .. } = &scene.textures[0] else {
        panic!("expected an image texture");
    };
    assert_eq!((name.as_str(), *width, *height), ("wood", 2, 2));
    let grey = srgb_to_linear(128.0 / 255.0);
    assert!((grey - 0.2158605).abs() < 1e-5, "{grey}");
    assert_eq!(texels, &vec![Vec3::X, Vec3::ONE, Vec3::splat(grey), Vec3::ZERO]);
    assert_eq!(scene.materials[0].texture, Some(0));
    assert_eq!(scene.materials[0].texture_repeat, Vec2::new(2.0, 3.0));
}

#[test]
fn image_textures_wrap_and_filter_as_written_and_are_written_back() {
    use glint_core::desc::{ImageSampling, TextureWrap};
    let dir = TempDir::new("wrap");
    write_png(&dir, "tex.png");
    let source = "texture \"a\" image { file \"tex.png\" wrap \"clamp\" filter \"nearest\" }\n\
                  texture \"b\" image { file \"tex.png\" wrap_v \"mirror\" }\n\
                  texture \"c\" image { file \"tex.png\" }";
    let scene = parse_scene(source, "inline", &dir.0).expect("parses");
    let sampling = |i: usize| match &scene.textures[i] {
        TextureDesc::Image { sampling, .. } => *sampling,
        other => panic!("{other:?}"),
    };
    assert_eq!(sampling(0), ImageSampling { wrap: [TextureWrap::Clamp; 2], nearest: true });
    assert_eq!(sampling(1), ImageSampling { wrap: [TextureWrap::Repeat, TextureWrap::Mirror], nearest: false });
    assert_eq!(sampling(2), ImageSampling::default());
    let options = glint_scene::native::writer::WriteOptions { base_dir: Some(dir.0.clone()), comment: None };
    let written = glint_scene::native::writer::write_scene(&scene, &options).expect("writes").text;
    assert!(written.contains("wrap \"clamp\" filter \"nearest\""), "{written}");
    assert!(written.contains("wrap_u \"repeat\" wrap_v \"mirror\""), "{written}");
    // Data (a normal map) is kept as stored: the grey texel 128 is 128/255, not 0.216.
    let linear = "texture \"n\" image { file \"tex.png\" encoding \"linear\" }\n\
                  material \"m\" { normal_map \"n\" normal_scale 0.5 }";
    let scene = parse_scene(linear, "inline", &dir.0).expect("parses");
    let TextureDesc::Image { texels, .. } = &scene.textures[0] else { panic!() };
    assert!((texels[2] - Vec3::splat(128.0 / 255.0)).length() < 1e-6, "{}", texels[2]);
    let normal_map = scene.materials[0].normal_map.expect("a normal map");
    assert_eq!((normal_map.texture, normal_map.scale), (0, 0.5));
    let e = parse_scene("material \"m\" { normal_scale 2 }", "inline", &dir.0).unwrap_err();
    assert!(e.message.contains("needs a 'normal_map'"), "{e}");
    let e = parse_scene("texture \"a\" image { file \"tex.png\" wrap \"tile\" }", "inline", &dir.0).unwrap_err();
    assert!(e.message.contains("\"repeat\"") && e.message.contains("\"mirror\""), "{e}");
}

#[test]
fn jpeg_textures_load_too() {
    let dir = TempDir::new("jpeg");
    let path = dir.0.join("flat.jpg");
    let pixels = vec![200u8; 8 * 8 * 3];
    image::save_buffer(&path, &pixels, 8, 8, image::ExtendedColorType::Rgb8).expect("save jpeg");
    let scene = parse_scene("texture \"t\" image { file \"flat.jpg\" }", "inline", &dir.0).expect("parses");
    let TextureDesc::Image { texels, width, .. } = &scene.textures[0] else {
        panic!("expected an image texture");
    };
    assert_eq!(*width, 8);
    let expected = srgb_to_linear(200.0 / 255.0);
    assert!(texels.iter().all(|t| (t.x - expected).abs() < 0.02), "{:?}", texels[0]);
}

#[test]
fn a_missing_texture_names_the_file_and_the_scene_line() {
    let dir = TempDir::new("missing-texture");
    let main = dir.write("main.glint", "# wood\ntexture \"wood\" image {\n  file \"textures/wood.png\"\n}");
    let e = load_scene(&main).expect_err("missing texture");
    assert_eq!(e.kind, SceneErrorKind::Io);
    assert_eq!(e.file, main.display().to_string());
    assert_eq!((e.line(), e.column()), (3, 3));
    assert!(e.message.contains("textures/wood.png"), "{e}");
    assert!(e.message.contains("cannot read texture file"), "{e}");
}

#[test]
fn textures_that_are_not_images_or_too_large_are_refused() {
    let dir = TempDir::new("bad-texture");
    dir.write("notes.txt", "not an image");
    let e = parse_scene("texture \"t\" image { file \"notes.txt\" }", "inline", &dir.0).expect_err("not an image");
    assert!(e.message.contains("must be PNG, JPEG, OpenEXR or Radiance HDR"), "{e}");
    assert_eq!((e.line(), e.column()), (1, 21));

    let wide = dir.0.join("wide.png");
    let side = MAX_TEXTURE_SIDE + 1;
    let pixels = vec![0u8; side as usize];
    image::save_buffer(&wide, &pixels, side, 1, image::ExtendedColorType::L8).expect("save png");
    let e = parse_scene("texture \"t\" image { file \"wide.png\" }", "inline", &dir.0).expect_err("too wide");
    assert!(e.message.contains(&format!("{side}x1 pixels; at most 16384")), "{e}");
}

#[test]
fn every_example_scene_in_the_repository_loads() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut loaded = 0;
    for entry in std::fs::read_dir(&scenes).expect("scenes/ exists") {
        let path = entry.expect("dir entry").path();
        if path.extension().is_some_and(|e| e == "glint") {
            let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
            // Lit by lights, or (path traced) by emissive surfaces alone.
            let lit = !scene.lights.is_empty() || scene.materials.iter().any(|m| m.emission.max_element() > 0.0);
            assert!(!scene.objects.is_empty() && lit, "{}", path.display());
            loaded += 1;
        }
    }
    assert!(loaded >= 2, "only {loaded} example scenes");
}

#[test]
fn the_full_example_in_the_format_documentation_parses() {
    let doc_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-format.md");
    let doc = std::fs::read_to_string(&doc_path).expect("docs/scene-format.md exists");
    let section = &doc[doc.find("## Full example").expect("has a full example")..];
    let start = section.find("```glint\n").expect("example block") + "```glint\n".len();
    let example = &section[start..start + section[start..].find("\n```").expect("block ends")];

    let dir = TempDir::new("doc-example");
    dir.write("materials.glint", "material \"red\" { diffuse [0.8 0.1 0.1] }");
    write_png(&dir, "textures/wood.png");
    let scene = parse_scene(example, "example.glint", &dir.0).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.settings.samples_per_axis, 2);
    assert_eq!(scene.lights.len(), 3);
    assert_eq!(scene.textures.len(), 2);
    let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["red", "glass", "floor", "table", "default"]);
    assert_eq!(scene.objects.len(), 6);
    let NodeKind::Group(legs) = &scene.objects[4].kind else {
        panic!("the legs are a group");
    };
    assert_eq!(legs.len(), 4);
}

#[test]
fn an_environment_light_takes_an_image_texture_and_transform_statements() {
    let dir = TempDir::new("environment");
    write_png(&dir, "sky.png");
    let scene = parse_scene(
        "texture \"sky\" image { file \"sky.png\" }\n\
         light environment { texture \"sky\" radiance 2.5 rotate [0 1 0] 30 scale [-1 1 1] }",
        "inline",
        &dir.0,
    )
    .expect("parses");
    assert_eq!(
        scene.lights,
        vec![LightDesc::Environment(EnvironmentDesc {
            radiance: Vec3::splat(2.5),
            texture: Some(0),
            transform: vec![
                TransformOp::Rotate { axis: Vec3::Y, degrees: 30.0 },
                TransformOp::Scale(Vec3::new(-1.0, 1.0, 1.0)),
            ],
        })]
    );
}
