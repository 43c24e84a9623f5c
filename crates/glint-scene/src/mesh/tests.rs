use std::path::PathBuf;

use glam::{Vec2, Vec3};

use super::*;

/// A fresh folder for one test's files (the mesh tests' names are all different).
pub(super) fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-mesh-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a test file into `dir`.
pub(super) fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn obj_with_uvs_normals_negative_indices_and_mtl() {
    let dir = folder("obj");
    write(&dir, "m.mtl", b"newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 10\n");
    let obj =
        b"mtllib m.mtl\n# a unit quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n\
usemtl red\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4/-4/-1 -2/-2/-1 -1/-1/-1\nl 1 2\n";
    let path = write(&dir, "quad.obj", obj);
    let import = load_mesh(&path).unwrap();
    assert_eq!(import.meshes.len(), 1);
    let mesh = &import.meshes[0];
    assert_eq!(mesh.indices.len(), 9);
    assert_eq!(mesh.positions.len(), 4, "corners with the same v/vt/vn share a vertex");
    assert_eq!(mesh.uvs[2], Vec2::ONE);
    assert!(mesh.normals.iter().all(|&n| n == Vec3::Z));
    assert_eq!(import.materials[0].diffuse, Vec3::X);
    assert_eq!(import.materials[0].shininess, 10.0);
    assert_eq!(import.placements[0].material, Some(0));
    assert!(import.warnings.iter().any(|w| w.contains("1 'l'")), "{:?}", import.warnings);
}

#[test]
fn bad_obj_files_name_file_and_line() {
    let dir = folder("bad-obj");
    let out_of_range = write(&dir, "range.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    let e = load_mesh(&out_of_range).unwrap_err();
    assert_eq!(e.line, 4);
    assert!(e.to_string().contains("range.obj:4") && e.message.contains("vertex index 4"), "{e}");
    let nan = write(&dir, "nan.obj", b"v 0 0 0\nv nan 0 0\n");
    let e = load_mesh(&nan).unwrap_err();
    assert_eq!(e.line, 2, "{e}");
    let binary = write(&dir, "bin.obj", &[0u8, 1, 2, 3, 0, 0]);
    assert!(load_mesh(&binary).unwrap_err().message.contains("binary"));
    let missing = load_mesh(&dir.join("missing.obj")).unwrap_err();
    assert!(missing.to_string().contains("missing.obj"), "{missing}");
    let empty = write(&dir, "empty.obj", b"v 0 0 0\n");
    assert!(load_mesh(&empty).unwrap_err().message.contains("no triangles"));
}

const PLY_HEADER: &str = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\n\
element face 1\nproperty list uchar int vertex_indices\nend_header\n";

#[test]
fn ply_ascii_and_binary_read_the_same() {
    let dir = folder("ply");
    let ascii =
        format!("ply\nformat ascii 1.0\ncomment quad\n{PLY_HEADER}0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n4 0 1 2 3\n");
    let a = load_mesh(&write(&dir, "a.ply", ascii.as_bytes())).unwrap();
    let mut binary = format!("ply\nformat binary_little_endian 1.0\n{PLY_HEADER}").into_bytes();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|x| binary.extend(x.to_le_bytes()));
        binary.push(9);
    }
    binary.push(4);
    [0i32, 1, 2, 3].iter().for_each(|i| binary.extend(i.to_le_bytes()));
    let b = load_mesh(&write(&dir, "b.ply", &binary)).unwrap();
    assert_eq!(a.meshes[0].positions, b.meshes[0].positions);
    assert_eq!(a.meshes[0].indices, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(a.meshes[0].indices, b.meshes[0].indices);
}

#[test]
fn bad_ply_files_are_refused() {
    let dir = folder("bad-ply");
    let huge = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nend_header\n";
    assert!(load_mesh(&write(&dir, "huge.ply", huge.as_bytes())).unwrap_err().message.contains("more data"));
    let range = format!("ply\nformat ascii 1.0\n{PLY_HEADER}0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n3 0 1 7\n");
    let e = load_mesh(&write(&dir, "range.ply", range.as_bytes())).unwrap_err();
    assert!(e.message.contains("out of range"), "{e}");
    let word = format!("ply\nformat ascii 1.0\n{PLY_HEADER}0 0 0 9\n1 zero 0 9\n");
    let e = load_mesh(&write(&dir, "word.ply", word.as_bytes())).unwrap_err();
    assert_eq!(e.line, 12, "{e}");
    assert!(load_mesh(&write(&dir, "not.ply", b"hello")).unwrap_err().message.contains("not a PLY"));
}

/// A GLB with one triangle mesh used by two nodes, and a red material.
fn tiny_glb() -> Vec<u8> {
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    [0u16, 1, 2, 0].iter().for_each(|i| bin.extend(i.to_le_bytes()));
    let json = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],
"nodes":[{"mesh":0},{"mesh":0,"translation":[3,0,0]}],
"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]}],
"materials":[{"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}}],
"buffers":[{"byteLength":44}],
"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}]}"#;
    let mut json = json.as_bytes().to_vec();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend((total as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(bin);
    glb
}

#[test]
fn glb_meshes_are_stored_once_and_placed_by_nodes() {
    let dir = folder("glb");
    let path = write(&dir, "tri.glb", &tiny_glb());
    let import = load_mesh(&path).unwrap();
    assert_eq!(import.meshes.len(), 1);
    assert_eq!(import.placements.len(), 2);
    assert_eq!(import.placements[1].world_from_object.transform_point3(Vec3::ZERO), Vec3::new(3.0, 0.0, 0.0));
    // glTF's metallic factor defaults to 1: a red metal, red in its highlights.
    assert_eq!(import.materials[0].specular, Vec3::X);
    let flat = merged(&import, "tri", "tri.glb");
    assert_eq!((flat.positions.len(), flat.indices.len()), (6, 6));
    assert!(load_mesh(&write(&dir, "junk.glb", b"PK\x03\x04 not gltf")).unwrap_err().message.contains("not a glTF"));
}

/// Standard base64 (RFC 4648), for data URIs.
fn base64(bytes: &[u8]) -> String {
    const DIGITS: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().enumerate().fold(0u32, |n, (i, &b)| n | u32::from(b) << (16 - 8 * i));
        for i in 0..4 {
            out.push(if i <= chunk.len() { DIGITS[(n >> (18 - 6 * i) & 63) as usize] as char } else { '=' });
        }
    }
    out
}

/// A `.gltf` whose triangle lies in `buffer_uri` and whose material's texture is `image_uri`.
fn gltf_json(buffer_uri: &str, image_uri: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"material":0}}]}}],
"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
"textures":[{{"source":0}}],"images":[{{"uri":"{image_uri}"}}],
"buffers":[{{"byteLength":44,"uri":"{buffer_uri}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":36}},{{"buffer":0,"byteOffset":36,"byteLength":6}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}}]}}"#
    )
}

#[test]
fn gltf_buffers_and_images_are_read_from_files_and_data_uris_within_the_limits() {
    let dir = folder("gltf-uris");
    // The GLB's binary chunk is the triangle's buffer.
    let glb = tiny_glb();
    let bin = glb[glb.len() - 44..].to_vec();
    write(&dir, "tri data.bin", &bin);
    let png = dir.join("two.png");
    image::RgbImage::from_raw(2, 1, vec![255, 0, 0, 0, 0, 255]).unwrap().save(&png).unwrap();
    let png_uri = format!("data:image/png;base64,{}", base64(&std::fs::read(&png).unwrap()));
    let bin_uri = format!("data:application/octet-stream;base64,{}", base64(&bin));
    for (buffer, image) in [("tri%20data.bin", "two.png"), (bin_uri.as_str(), png_uri.as_str())] {
        let path = write(&dir, "model.gltf", gltf_json(buffer, image).as_bytes());
        let import = load_mesh(&path).unwrap_or_else(|e| panic!("{buffer}: {e}"));
        assert_eq!(import.meshes[0].positions[1], Vec3::X);
        let TextureDesc::Image { width: 2, height: 1, texels, .. } = &import.textures[0] else {
            panic!("{:?}", import.textures)
        };
        assert_eq!((texels[0], texels[1]), (Vec3::X, Vec3::Z));
        assert_eq!(import.materials[0].texture, Some(0));
    }
    // Files a model names are refused as any file is: here a folder and a missing file.
    std::fs::create_dir_all(dir.join("folder.bin")).unwrap();
    let path = write(&dir, "model.gltf", gltf_json("folder.bin", "two.png").as_bytes());
    let e = load_mesh(&path).unwrap_err();
    assert!(e.message.contains("buffer 0: cannot read mesh file") && e.message.contains("is a directory"), "{e}");
    let path = write(&dir, "model.gltf", gltf_json("tri%20data.bin", "missing.png").as_bytes());
    let e = load_mesh(&path).unwrap_err();
    assert!(e.message.contains("image 0: cannot read image file") && e.message.contains("missing.png"), "{e}");
    let path = write(&dir, "model.gltf", gltf_json("https://example.com/tri.bin", "two.png").as_bytes());
    assert!(load_mesh(&path).unwrap_err().message.contains("unsupported URI"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_model_alone_becomes_a_framed_scene() {
    let dir = folder("model");
    let path = write(&dir, "tri.glb", &tiny_glb());
    let loaded = crate::load_any(&path).unwrap();
    assert_eq!(loaded.format, crate::SceneFormat::Mesh);
    let mut desc = loaded.scene;
    assert_eq!(desc.lights.len(), 2);
    desc.settings.width = 32;
    desc.settings.height = 24;
    let scene = glint_core::scene::compile(&desc).unwrap();
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let image = glint_core::render::render(&scene, &|_, _| {}, &cancel).unwrap().0;
    let red = image.pixels.iter().filter(|p| p.x > 0.2 && p.y < 0.05).count();
    assert!(red > 10, "the model is in the frame: {red} red pixels");
}

#[test]
fn native_mesh_definitions_are_stored_once_and_instanced() {
    let dir = folder("native");
    write(&dir, "tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let text = "material \"red\" { diffuse [1 0 0] }\nmesh \"tri\" { file \"tri.obj\" }\n\
mesh_instance \"tri\" { material \"red\" }\ngroup { translate [2 0 0] mesh_instance \"tri\" { scale 2 } }\n";
    let desc = crate::parse_scene(text, "s.glint", &dir).unwrap();
    assert_eq!(desc.meshes.len(), 1);
    assert_eq!(desc.meshes[0].indices, vec![0, 1, 2]);
    assert_eq!(desc.objects.len(), 2);
    assert!(glint_core::scene::compile(&desc).is_ok());
    let e = crate::parse_scene("mesh_instance \"nope\" {}", "s.glint", &dir).unwrap_err();
    assert!(e.message.contains("unknown mesh 'nope'"), "{e}");
    let e = crate::parse_scene("mesh \"m\" { file \"missing.ply\" }", "s.glint", &dir).unwrap_err();
    assert!(e.to_string().contains("missing.ply"), "{e}");
}

/// Mutated copies of valid files (bytes changed, cut short, pieces repeated) must give a
/// mesh or an error, never a panic or a hang.
#[test]
fn mangled_files_never_panic() {
    let dir = folder("fuzz");
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf -3 -2 -1\n".to_vec();
    let ply =
        format!("ply\nformat ascii 1.0\n{PLY_HEADER}0 0 0 9\n1 0 0 9\n1 1 0 9\n0 1 0 9\n4 0 1 2 3\n").into_bytes();
    let mut bply = format!("ply\nformat binary_little_endian 1.0\n{PLY_HEADER}").into_bytes();
    bply.extend([0u8; 13 * 4]);
    bply.push(3);
    [0i32, 1, 2].iter().for_each(|i| bply.extend(i.to_le_bytes()));
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    for (name, original) in [("a.obj", obj), ("a.ply", ply), ("b.ply", bply), ("a.glb", tiny_glb())] {
        for round in 0..150 {
            let mut bytes = original.clone();
            match round % 3 {
                0 => {
                    for _ in 0..1 + next(4) {
                        let at = next(bytes.len());
                        bytes[at] = next(256) as u8;
                    }
                }
                1 => bytes.truncate(next(bytes.len())),
                _ => {
                    let at = next(bytes.len());
                    let piece = bytes[at..(at + 1 + next(16)).min(bytes.len())].to_vec();
                    let to = next(bytes.len());
                    bytes.splice(to..to, piece);
                }
            }
            let path = write(&dir, name, &bytes);
            // Whatever loads must also compile or be refused by compile, not crash it.
            if let Ok(import) = load_mesh(&path) {
                let _ = glint_core::scene::compile(&model_scene(import));
            }
        }
    }
}

/// A `.gltf` with one mesh whose primitives are `primitives` (JSON), reading through
/// `views` and `accessors` from one embedded 44-byte buffer: three corners of a unit
/// right triangle (bytes 0..36), then the u16 indices 0, 1, 2 (36..42).
fn embedded_gltf(primitives: &str, views: &str, accessors: &str) -> Vec<u8> {
    let mut bin = Vec::new();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        p.iter().for_each(|x| bin.extend(x.to_le_bytes()));
    }
    [0u16, 1, 2, 0].iter().for_each(|i| bin.extend(i.to_le_bytes()));
    let uri = format!("data:application/octet-stream;base64,{}", base64(&bin));
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{primitives}]}}],"buffers":[{{"byteLength":44,"uri":"{uri}"}}],
"bufferViews":[{views}],"accessors":[{accessors}]}}"#
    )
    .into_bytes()
}

/// The triangle's corners (view 0, accessor 0) and indices (view 1, accessor 1).
const CORNERS_VIEW: &str = r#"{"buffer":0,"byteLength":36}"#;
const INDEX_VIEW: &str = r#"{"buffer":0,"byteOffset":36,"byteLength":6}"#;
const EMPTY_VIEW: &str = r#"{"buffer":0,"byteOffset":36,"byteLength":0}"#;
const CORNERS: &str = r#"{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}"#;

/// A zero-length buffer view gives an empty primitive (skipped, with a warning) where its
/// accessor has no elements, a clear error where it claims some, and never a panic (the
/// `gltf` crate's readers underflow on an empty accessor).
#[test]
fn gltf_zero_length_buffer_views_give_an_empty_mesh_or_an_error() {
    let dir = folder("gltf-empty");
    let load = |name: &str, primitives: &str, views: String, accessors: String| {
        load_mesh(&write(&dir, name, &embedded_gltf(primitives, &views, &accessors)))
    };
    let empty = |ty: u32, kind: &str| format!(r#"{{"bufferView":1,"componentType":{ty},"count":0,"type":"{kind}"}}"#);
    let triangle = r#"{"attributes":{"POSITION":0}}"#;
    let empty_corners = r#"{"bufferView":1,"componentType":5126,"count":0,"type":"VEC3","min":[0,0,0],"max":[0,0,0]}"#;

    // No corners: nothing to render, said so; beside a real triangle, skipped.
    let views = format!("{CORNERS_VIEW},{EMPTY_VIEW}");
    let e =
        load("corners.gltf", r#"{"attributes":{"POSITION":1}}"#, views.clone(), format!("{CORNERS},{empty_corners}"));
    assert!(e.unwrap_err().message.contains("no triangles"));
    let both = format!(r#"{triangle},{{"attributes":{{"POSITION":1}}}}"#);
    let import = load("beside.gltf", &both, views.clone(), format!("{CORNERS},{empty_corners}")).unwrap();
    assert_eq!((import.meshes.len(), import.meshes[0].indices.len()), (1, 3));
    assert!(import.warnings.iter().any(|w| w.contains("empty primitive")), "{:?}", import.warnings);
    // No indices: no triangles.
    let indexed = r#"{"attributes":{"POSITION":0},"indices":1}"#;
    let e = load("indices.gltf", indexed, views.clone(), format!("{CORNERS},{}", empty(5123, "SCALAR")));
    assert!(e.unwrap_err().message.contains("no triangles"));
    // No normals or uvs: the triangle without them.
    for (name, attribute, accessor) in
        [("normals", "NORMAL", empty(5126, "VEC3")), ("uvs", "TEXCOORD_0", empty(5126, "VEC2"))]
    {
        let primitive = format!(r#"{{"attributes":{{"POSITION":0,"{attribute}":1}}}}"#);
        let import = load(&format!("{name}.gltf"), &primitive, views.clone(), format!("{CORNERS},{accessor}")).unwrap();
        let mesh = &import.meshes[0];
        assert_eq!((mesh.indices.len(), mesh.normals.len(), mesh.uvs.len()), (3, 0, 0), "{name}");
    }
    // Elements claimed in a view of no bytes: an error naming the accessor.
    let claimed = r#"{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}"#;
    let e = load("claimed.gltf", indexed, views.clone(), format!("{CORNERS},{claimed}")).unwrap_err();
    assert!(e.message.contains("indices accessor (1) runs past its 0-byte buffer view"), "{e}");
    // From a native scene too: an error, not a panic.
    let e = crate::parse_scene("mesh \"m\" { file \"corners.gltf\" }", "s.glint", &dir).unwrap_err();
    assert!(e.to_string().contains("no triangles"), "{e}");
    // The valid file the cases above were cut from loads.
    let import = load("valid.gltf", indexed, format!("{CORNERS_VIEW},{INDEX_VIEW}"), format!("{CORNERS},{claimed}"));
    assert_eq!(import.unwrap().meshes[0].indices, vec![0, 1, 2]);
}

/// Accessors the `gltf` crate's readers would panic on (a component type they do not
/// expect, a stride shorter than an element, an empty sparse part) are refused, each
/// with a message that names the accessor.
#[test]
fn gltf_accessors_the_readers_cannot_take_are_refused() {
    let dir = folder("gltf-bad-accessor");
    let indexed = r#"{"attributes":{"POSITION":0},"indices":1}"#;
    let with_uvs = r#"{"attributes":{"POSITION":0,"TEXCOORD_0":1}}"#;
    let views = format!("{CORNERS_VIEW},{INDEX_VIEW}");
    let cases = [
        ("uv-bytes", with_uvs, views.clone(), r#"{"bufferView":1,"componentType":5120,"count":3,"type":"VEC2"}"#.to_string(), "TEXCOORD_0 accessor (1) holds Vec2 of I8"),
        ("float-indices", indexed, views.clone(), r#"{"bufferView":0,"componentType":5126,"count":3,"type":"SCALAR"}"#.to_string(), "indices accessor (1) holds Scalar of F32"),
        ("short-corners", indexed, r#"{"buffer":0,"byteLength":36,"byteStride":4},{"buffer":0,"byteOffset":36,"byteLength":6}"#.to_string(), r#"{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}"#.to_string(), "POSITION accessor (0) has 12-byte elements only 4 bytes apart"),
        ("empty-sparse", indexed, views.clone(), r#"{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR","sparse":{"count":0,"indices":{"bufferView":1,"componentType":5123},"values":{"bufferView":1}}}"#.to_string(), "sparse part of 0 elements"),
    ];
    for (name, primitive, views, second, expected) in cases {
        let bytes = embedded_gltf(primitive, &views, &format!("{CORNERS},{second}"));
        let e = load_mesh(&write(&dir, &format!("{name}.gltf"), &bytes)).unwrap_err();
        assert!(e.message.contains(expected), "{name}: {e}");
    }
    let u16_corners = r#"{"bufferView":0,"componentType":5123,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}"#;
    let bytes = embedded_gltf(r#"{"attributes":{"POSITION":0}}"#, CORNERS_VIEW, u16_corners);
    let e = load_mesh(&write(&dir, "u16-corners.gltf", &bytes)).unwrap_err();
    assert!(e.message.contains("POSITION accessor (0) holds Vec3 of U16"), "{e}");
}
