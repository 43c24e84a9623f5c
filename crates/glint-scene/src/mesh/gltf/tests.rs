//! The glTF reader on small documents written for each test: primitive modes, vertex
//! colours, texture transforms, materials and their extensions, lights, cameras, and
//! the errors and warnings a model glint cannot fully read gets.

use std::path::Path;

use glam::{Vec2, Vec3};
use glint_core::desc::{BsdfDesc, ImageSampling, LightDesc, TextureDesc, TextureWrap};

use crate::mesh::{MeshImport, model_scene, parse_mesh};

/// A glTF document under construction: one buffer, embedded as a data URI, that the
/// accessors read.
#[derive(Default)]
struct Model {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Model {
    /// Adds `values` as an accessor of `count` elements of `kind` (SCALAR, VEC2, …)
    /// with the extra members `extra` (`,"min":…`); returns its index.
    fn floats(&mut self, values: &[f32], kind: &str, count: usize, extra: &str) -> usize {
        let offset = self.bin.len();
        values.iter().for_each(|v| self.bin.extend(v.to_le_bytes()));
        self.views.push(format!(r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#, 4 * values.len()));
        let view = self.views.len() - 1;
        self.accessors
            .push(format!(r#"{{"bufferView":{view},"componentType":5126,"count":{count},"type":"{kind}"{extra}}}"#));
        self.accessors.len() - 1
    }

    /// Adds vertex positions with the bounds glTF requires of them.
    fn positions(&mut self, points: &[[f32; 3]]) -> usize {
        let min = points.iter().fold(Vec3::INFINITY, |m, p| m.min(Vec3::from(*p)));
        let max = points.iter().fold(Vec3::NEG_INFINITY, |m, p| m.max(Vec3::from(*p)));
        let extra = format!(r#","min":[{},{},{}],"max":[{},{},{}]"#, min.x, min.y, min.z, max.x, max.y, max.z);
        self.floats(&points.concat(), "VEC3", points.len(), &extra)
    }

    /// Adds u16 triangle indices; returns the accessor's index.
    fn indices(&mut self, indices: &[u16]) -> usize {
        let offset = self.bin.len();
        indices.iter().for_each(|i| self.bin.extend(i.to_le_bytes()));
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.views.push(format!(r#"{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#, 2 * indices.len()));
        let view = self.views.len() - 1;
        let count = indices.len();
        self.accessors.push(format!(r#"{{"bufferView":{view},"componentType":5123,"count":{count},"type":"SCALAR"}}"#));
        self.accessors.len() - 1
    }

    /// The document: the buffer and accessors, then `members` (meshes, nodes, …).
    fn document(&self, members: &str) -> Vec<u8> {
        let mut bin = self.bin.clone();
        bin.resize(bin.len().next_multiple_of(4), 0);
        format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
"bufferViews":[{}],"accessors":[{}],{members}}}"#,
            bin.len(),
            base64(&bin),
            self.views.join(","),
            self.accessors.join(","),
        )
        .into_bytes()
    }
}

fn base64(bytes: &[u8]) -> String {
    const DIGITS: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for k in 0..4 {
            let digit = if k <= chunk.len() { DIGITS[(n >> (18 - 6 * k) & 63) as usize] as char } else { '=' };
            out.push(digit);
        }
    }
    out
}

fn read(document: Vec<u8>) -> Result<MeshImport, crate::SceneError> {
    parse_mesh(Path::new("/no/such/folder/model.gltf"), document)
}

/// One node showing one primitive (`primitive`, JSON) with `more` top-level members.
fn one_primitive(primitive: &str, more: &str) -> String {
    format!(r#""scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{primitive}]}}]{more}"#)
}

/// A unit square in z = 0 as two triangles, with `attributes` beside its positions.
fn square(model: &mut Model) -> usize {
    model.positions(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]])
}

fn normal_of(import: &MeshImport, triangle: &[u32]) -> Vec3 {
    let p = |i: u32| import.meshes[0].positions[i as usize];
    (p(triangle[1]) - p(triangle[0])).cross(p(triangle[2]) - p(triangle[0]))
}

#[test]
fn strips_and_fans_give_their_triangles_with_one_winding() {
    // A strip zig-zagging along x: 0 1 2 3 4 → (0 1 2) (2 1 3) (2 3 4).
    let mut model = Model::default();
    let zigzag = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0]];
    model.positions(&zigzag);
    let strip = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"mode":5}"#, ""))).unwrap();
    assert_eq!(strip.meshes[0].indices, [0, 1, 2, 2, 1, 3, 2, 3, 4]);
    // A fan around vertex 0 of a pentagon: (0 1 2) (0 2 3) (0 3 4).
    let mut model = Model::default();
    let pentagon: Vec<[f32; 3]> = (0..5)
        .map(|k| {
            let a = k as f32 * std::f32::consts::TAU / 5.0;
            [a.cos(), a.sin(), 0.0]
        })
        .collect();
    model.positions(&pentagon);
    let fan = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"mode":6}"#, ""))).unwrap();
    assert_eq!(fan.meshes[0].indices, [0, 1, 2, 0, 2, 3, 0, 3, 4]);
    for import in [&strip, &fan] {
        for t in import.meshes[0].indices.chunks(3) {
            let n = normal_of(import, t);
            assert!(n.z.abs() > 0.0 && n.z.signum() == normal_of(import, &import.meshes[0].indices[..3]).z.signum());
        }
    }
    // The fan's triangles cover the pentagon: their areas sum to its area.
    let area: f32 = fan.meshes[0].indices.chunks(3).map(|t| 0.5 * normal_of(&fan, t).length()).sum();
    let pentagon_area = 2.5 * (std::f32::consts::TAU / 5.0).sin();
    assert!((area - pentagon_area).abs() < 1e-5, "{area} vs {pentagon_area}");
    // Points and lines are left out with one warning per mode.
    let mut model = Model::default();
    square(&mut model);
    let doc = one_primitive(r#"{"attributes":{"POSITION":0},"mode":1},{"attributes":{"POSITION":0},"mode":4}"#, "");
    let import = read(model.document(&doc)).unwrap();
    assert!(import.warnings.iter().any(|w| w.contains("skipped 1 primitives drawn as lines")), "{:?}", import.warnings);
}

#[test]
fn custom_attributes_are_ignored_and_vertex_colours_read() {
    let mut model = Model::default();
    square(&mut model);
    let colors = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.5, 0.2, 0.4, 0.6, 1.0];
    model.floats(&colors, "VEC4", 4, "");
    model.floats(&[7.0; 4], "SCALAR", 4, "");
    model.indices(&[0, 1, 2, 0, 2, 3]);
    let primitive = r#"{"attributes":{"POSITION":0,"COLOR_0":1,"_TEMPERATURE":2,"temperature":2},"indices":3}"#;
    let import = read(model.document(&one_primitive(primitive, ""))).unwrap();
    let ignored = "mesh 0: ignored 1 vertex attributes with names glTF does not define";
    assert!(import.warnings.iter().any(|w| w.contains(ignored)), "{:?}", import.warnings);
    let mesh = &import.meshes[0];
    assert_eq!(mesh.indices, [0, 1, 2, 0, 2, 3]);
    assert_eq!(mesh.colors, [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.2, 0.4, 0.6)]);
}

/// A textured square whose base-colour texture reference carries `transform` (JSON).
fn textured_square(transform: &str) -> MeshImport {
    let mut model = Model::default();
    square(&mut model);
    model.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2", 4, "");
    let mut png = Vec::new();
    let image = image::RgbImage::from_raw(2, 2, vec![255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255]).unwrap();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    let more = format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0{transform}}}}}}}],
"textures":[{{"source":0,"sampler":0}}],"images":[{{"uri":"data:image/png;base64,{}"}}],
"samplers":[{{"wrapS":33071,"wrapT":33648,"magFilter":9728}}]"#,
        base64(&png)
    );
    let primitive = r#"{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}"#;
    read(model.document(&one_primitive(primitive, &more))).unwrap()
}

#[test]
fn a_texture_transform_is_baked_into_the_uvs() {
    let plain = textured_square("");
    // glTF (0, 0) is the image's top left, glint's v runs up: uv (0, 0) → (0, 1).
    assert_eq!(plain.meshes[0].uvs[0], Vec2::new(0.0, 1.0));
    // The sampler: u clamps to the edge, v mirrors, magnified texels stay square.
    let TextureDesc::Image { sampling, .. } = &plain.textures[0] else { panic!() };
    let expected = ImageSampling { wrap: [TextureWrap::Clamp, TextureWrap::Mirror], nearest: true };
    assert_eq!(*sampling, expected);
    let moved = textured_square(r#","extensions":{"KHR_texture_transform":{"offset":[0.5,0.25],"scale":[2,3]}}"#);
    // Corner (1, 1): scaled to (2, 3), offset to (2.5, 3.25), v flipped to −2.25.
    let corner = moved.meshes[0].uvs[2];
    assert!((corner - Vec2::new(2.5, -2.25)).length() < 1e-6, "{corner}");
    // A quarter turn takes glTF's (1, 0) to (0, −1), counter-clockwise in a v-down
    // space (KhronosGroup/glTF#1563): glint's v = 1 − (−1) = 2.
    let turned = textured_square(r#","extensions":{"KHR_texture_transform":{"rotation":1.5707964}}"#);
    let u_corner = turned.meshes[0].uvs[1];
    assert!((u_corner - Vec2::new(0.0, 2.0)).length() < 1e-6, "{u_corner}");
}

/// The square with one material (`material`, JSON) and the extensions it uses.
fn with_material(material: &str) -> MeshImport {
    let mut model = Model::default();
    square(&mut model);
    let more = format!(r#","materials":[{material}]"#);
    read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"material":0}"#, &more))).unwrap()
}

#[test]
fn metallic_roughness_materials_map_onto_the_metallic_roughness_bsdf() {
    let metal = with_material(r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.9,0.6,0.2,1],"roughnessFactor":0.5}}"#);
    let m = &metal.materials[0];
    let Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, ior }) = m.bsdf else { panic!("{:?}", m.bsdf) };
    assert_eq!((base.value, metallic.value, alpha.value, ior), (Vec3::new(0.9, 0.6, 0.2), 1.0, 0.25, 1.5));
    assert!(!m.two_sided, "glTF materials are single-sided unless they say otherwise");
    let plastic = with_material(
        r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.1,0.5,0.2,1],"metallicFactor":0,"roughnessFactor":0},
"doubleSided":true,"emissiveFactor":[1,0.5,0],"extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}}}"#,
    );
    let m = &plastic.materials[0];
    let Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, .. }) = m.bsdf else { panic!("{:?}", m.bsdf) };
    assert_eq!((base.value, metallic.value, alpha.value), (Vec3::new(0.1, 0.5, 0.2), 0.0, 0.0));
    assert!(m.two_sided);
    assert_eq!(m.emission, Vec3::new(4.0, 2.0, 0.0));
    let glass = with_material(
        r#"{"pbrMetallicRoughness":{"metallicFactor":0},
"extensions":{"KHR_materials_transmission":{"transmissionFactor":1},"KHR_materials_ior":{"ior":1.33}}}"#,
    );
    let m = &glass.materials[0];
    let Some(BsdfDesc::Dielectric { int_ior, .. }) = m.bsdf else { panic!("{:?}", m.bsdf) };
    assert_eq!(int_ior, 1.33);
    assert!(m.transmissive.max_element() > 0.5 && m.ior == 1.33, "Whitted refracts too: {m:?}");
    let unlit = with_material(
        r#"{"pbrMetallicRoughness":{"baseColorFactor":[0.3,0.6,0.9,1]},"extensions":{"KHR_materials_unlit":{}}}"#,
    );
    assert_eq!(unlit.materials[0].emission, Vec3::new(0.3, 0.6, 0.9));
    // A material between metal and plastic is blended, not rounded to either.
    let half = with_material(r#"{"pbrMetallicRoughness":{"metallicFactor":0.4}}"#);
    let Some(BsdfDesc::MetallicRoughness { metallic, .. }) = half.materials[0].bsdf else { panic!() };
    assert_eq!(metallic.value, 0.4);
    assert!(half.warnings.is_empty(), "{:?}", half.warnings);
}

#[test]
fn the_files_lights_and_first_camera_are_used() {
    let mut model = Model::default();
    square(&mut model);
    let nodes = r#""scenes":[{"nodes":[0,1,2,3,4]}],
"nodes":[{"mesh":0},{"camera":0,"translation":[0,0,5]},{"camera":0,"translation":[9,9,9]},
{"extensions":{"KHR_lights_punctual":{"light":0}},"translation":[1,2,3]},
{"extensions":{"KHR_lights_punctual":{"light":1}},"rotation":[-0.7071068,0,0,0.7071068]}],
"cameras":[{"type":"perspective","perspective":{"yfov":0.8,"aspectRatio":2,"znear":0.1}}],
"extensionsUsed":["KHR_lights_punctual"],
"extensions":{"KHR_lights_punctual":{"lights":[{"type":"point","color":[1,0.5,0.5],"intensity":20},
{"type":"spot","intensity":3,"spot":{"innerConeAngle":0.2,"outerConeAngle":0.5}}]}},
"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]"#;
    let import = read(model.document(nodes)).unwrap();
    assert!(import.warnings.iter().any(|w| w.contains("the first of 2 cameras is used")), "{:?}", import.warnings);
    let scene = model_scene(import);
    // The second camera can be picked; a third cannot.
    let mut second = scene.clone();
    let pick = |index| crate::overrides::Overrides { camera: Some(index), ..Default::default() };
    pick(1).apply(&mut second).unwrap();
    assert_eq!(second.camera.eye, Vec3::splat(9.0));
    let e = pick(2).apply(&mut second.clone()).unwrap_err();
    assert_eq!(e.to_string(), "camera 2 was asked for, but the scene has 2 cameras (0 to 1)");
    assert_eq!(scene.camera.eye, Vec3::new(0.0, 0.0, 5.0));
    assert!((scene.camera.look.normalize() - Vec3::NEG_Z).length() < 1e-6);
    assert!((scene.camera.fov_y_degrees - 0.8f32.to_degrees()).abs() < 1e-4);
    assert_eq!(scene.settings.height * 2, scene.settings.width);
    assert_eq!(scene.lights.len(), 2, "the file's lights replace the default ones");
    let LightDesc::Point { position, color, attenuation } = scene.lights[0] else { panic!("{:?}", scene.lights[0]) };
    assert_eq!((position, color, attenuation), (Vec3::new(1.0, 2.0, 3.0), Vec3::new(20.0, 10.0, 10.0), Vec3::Z));
    // Turned −90° about x, the spot looks down −y.
    let LightDesc::Spot { direction, angle_degrees, penumbra_degrees, .. } = scene.lights[1] else { panic!() };
    assert!((direction - Vec3::NEG_Y).length() < 1e-5, "{direction}");
    assert!((angle_degrees - 0.5f32.to_degrees()).abs() < 1e-4);
    assert!((penumbra_degrees - 0.3f32.to_degrees()).abs() < 1e-4);
}

#[test]
fn an_undecodable_image_is_a_warning_and_a_required_extension_one_sentence() {
    let mut model = Model::default();
    square(&mut model);
    let ktx2 = base64(b"\xabKTX 20\xbb\r\n\x1a\n not decodable here");
    let more = format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}},"baseColorFactor":[0.5,0.5,0.5,1],"metallicFactor":0}}}}],
"textures":[{{"source":0}},{{"extensions":{{"KHR_texture_basisu":{{"source":0}}}}}}],
"images":[{{"uri":"data:image/ktx2;base64,{ktx2}"}}],"extensionsUsed":["KHR_texture_basisu"]"#
    );
    let import = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"material":0}"#, &more))).unwrap();
    assert!(import.warnings.iter().any(|w| w.contains("image 0 is left out")), "{:?}", import.warnings);
    let Some(BsdfDesc::MetallicRoughness { base, .. }) = import.materials[0].bsdf else { panic!() };
    assert_eq!((base.value, base.texture), (Vec3::splat(0.5), None));

    let required =
        r#","extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]"#;
    let e = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0}}"#, required))).unwrap_err();
    assert!(
        e.message == "the model requires the glTF extension KHR_draco_mesh_compression, which glint does not implement",
        "{e}"
    );
    // A broken document names its first problems once, not "invalid glTF: invalid glTF:".
    let e = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"material":7}"#, ""))).unwrap_err();
    assert_eq!(e.message.matches("invalid glTF").count(), 1, "{e}");
    assert!(e.message.contains("material"), "{e}");
}

/// The textured square with one material (`material`, JSON, naming texture 0) whose
/// texture is a 1×1 PNG of `rgb`.
fn with_texture(material: &str, rgb: [u8; 3]) -> MeshImport {
    let mut model = Model::default();
    square(&mut model);
    model.floats(&[0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0], "VEC2", 4, "");
    let mut png = Vec::new();
    let image = image::RgbImage::from_raw(1, 1, rgb.to_vec()).unwrap();
    image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
    let more = format!(
        r#","materials":[{material}],"textures":[{{"source":0}}],"images":[{{"uri":"data:image/png;base64,{}"}}]"#,
        base64(&png)
    );
    let primitive = r#"{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}"#;
    read(model.document(&one_primitive(primitive, &more))).unwrap()
}

#[test]
fn an_emissive_texture_textures_the_emission() {
    let import = with_texture(r#"{"emissiveFactor":[1,1,0.5],"emissiveTexture":{"index":0}}"#, [255, 128, 0]);
    let m = &import.materials[0];
    assert_eq!(m.emission, Vec3::new(1.0, 1.0, 0.5));
    let TextureDesc::Image { texels, .. } = &import.textures[m.emission_texture.expect("textured")] else { panic!() };
    assert_eq!(texels[0].x, 1.0, "an sRGB colour texture, decoded: {}", texels[0]);
}

#[test]
fn a_normal_texture_is_a_normal_map_read_as_data() {
    let import = with_texture(r#"{"normalTexture":{"index":0,"scale":0.7}}"#, [128, 128, 255]);
    let normal_map = import.materials[0].normal_map.expect("a normal map");
    assert_eq!(normal_map.scale, 0.7);
    let TextureDesc::Image { texels, .. } = &import.textures[normal_map.texture] else { panic!() };
    assert!((texels[0] - Vec3::new(128.0, 128.0, 255.0) / 255.0).length() < 1e-6, "not sRGB-decoded: {}", texels[0]);
}

/// The metallic-roughness image serves two textures (roughness from green, metallic
/// from blue) but is decoded once: an undecodable one is named in one warning.
#[test]
fn a_metallic_roughness_image_is_decoded_once_for_both_channels() {
    let mut model = Model::default();
    square(&mut model);
    let ktx2 = base64(b"\xabKTX 20\xbb\r\n\x1a\n not decodable here");
    let more = format!(
        r#","materials":[{{"pbrMetallicRoughness":{{"metallicFactor":0.5,"metallicRoughnessTexture":{{"index":0}}}}}}],
"textures":[{{"source":0}}],"images":[{{"uri":"data:image/ktx2;base64,{ktx2}"}}]"#
    );
    let import = read(model.document(&one_primitive(r#"{"attributes":{"POSITION":0},"material":0}"#, &more))).unwrap();
    let warned = import.warnings.iter().filter(|w| w.contains("image 0 is left out")).count();
    assert_eq!(warned, 1, "{:?}", import.warnings);
    let Some(BsdfDesc::MetallicRoughness { metallic, alpha, .. }) = import.materials[0].bsdf else { panic!() };
    assert_eq!((metallic.texture, alpha.texture), (None, None));
}

#[test]
fn a_metallic_roughness_texture_gives_roughness_from_green_and_metallic_from_blue() {
    let import = with_texture(
        r#"{"pbrMetallicRoughness":{"metallicFactor":0.5,"roughnessFactor":1,"metallicRoughnessTexture":{"index":0}}}"#,
        [10, 128, 204],
    );
    let m = &import.materials[0];
    let Some(BsdfDesc::MetallicRoughness { metallic, alpha, .. }) = m.bsdf else { panic!("{:?}", m.bsdf) };
    assert_eq!((metallic.value, alpha.value), (0.5, 1.0));
    let texel = |t: Option<usize>| match &import.textures[t.expect("textured")] {
        TextureDesc::Image { texels, .. } => texels[0],
        other => panic!("{other:?}"),
    };
    let green = 128.0 / 255.0;
    assert!((texel(alpha.texture) - Vec3::splat(green * green)).length() < 1e-6, "alpha = roughness²");
    assert!((texel(metallic.texture) - Vec3::splat(0.8)).length() < 1e-6, "metallic, stored as data");
    // The Whitted reading takes the mean metallic share, 0.5 × 0.8: a part of the base
    // colour goes to the highlight.
    assert!((m.specular - Vec3::splat(0.04).lerp(Vec3::ONE, 0.4)).length() < 1e-5, "{}", m.specular);
    // A zero metallic factor needs no metallic texture.
    let plastic = with_texture(
        r#"{"pbrMetallicRoughness":{"metallicFactor":0,"metallicRoughnessTexture":{"index":0}}}"#,
        [10, 128, 204],
    );
    let Some(BsdfDesc::MetallicRoughness { metallic, alpha, .. }) = plastic.materials[0].bsdf else { panic!() };
    assert_eq!((metallic.texture, plastic.textures.len()), (None, 1));
    assert!(alpha.texture.is_some());
}
