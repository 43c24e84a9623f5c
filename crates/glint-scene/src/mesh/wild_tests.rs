//! Mesh files as other tools write them: concave and non-planar polygons, strips, CR line
//! ends, either byte order, attributes under their many names, Latin-1 text, Windows
//! texture paths, missing attributes and Git LFS pointers.

use glam::{Vec2, Vec3};

use super::polygon::triangulate;
use super::tests::{folder, write};
use super::*;

/// Twice the signed area of a 2-D polygon (shoelace formula).
fn area2(points: &[Vec2]) -> f32 {
    (0..points.len()).map(|k| points[k].perp_dot(points[(k + 1) % points.len()])).sum()
}

/// Whether `p` is strictly inside the polygon (even-odd rule).
fn inside(points: &[Vec2], p: Vec2) -> bool {
    let mut crossings = false;
    for k in 0..points.len() {
        let (a, b) = (points[k], points[(k + 1) % points.len()]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            crossings = !crossings;
        }
    }
    crossings
}

/// Concave outlines: an L, a comb with three teeth, and an arrow head.
fn concave_outlines() -> Vec<Vec<Vec2>> {
    let v = |pts: &[(f32, f32)]| pts.iter().map(|&(x, y)| Vec2::new(x, y)).collect::<Vec<_>>();
    vec![
        v(&[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)]),
        v(&[
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, 3.0),
            (4.0, 3.0),
            (4.0, 1.0),
            (3.0, 1.0),
            (3.0, 3.0),
            (2.0, 3.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (0.0, 3.0),
        ]),
        v(&[(0.0, 0.0), (2.0, 1.0), (4.0, 0.0), (2.0, 3.0)]),
    ]
}

#[test]
fn concave_polygons_keep_their_area_and_no_triangle_lies_outside() {
    // Placed in a tilted plane, so the triangulation must find the plane itself.
    let (u, v) = (Vec3::new(1.0, 0.0, 1.0).normalize(), Vec3::new(0.3, 1.0, -0.3).normalize());
    let v = (v - v.dot(u) * u).normalize();
    for outline in concave_outlines() {
        for reversed in [false, true] {
            let mut outline = outline.clone();
            if reversed {
                outline.reverse();
            }
            let points: Vec<Vec3> = outline.iter().map(|p| p.x * u + p.y * v + Vec3::splat(5.0)).collect();
            let triangles = triangulate(&points);
            assert_eq!(triangles.len(), outline.len() - 2);
            let mut sum = 0.0;
            for t in &triangles {
                let tri = t.map(|i| outline[i]);
                let a = area2(&tri);
                assert!(a * area2(&outline) > 0.0, "{t:?} is wound against {outline:?}: {triangles:?}");
                sum += a;
                let centroid = (tri[0] + tri[1] + tri[2]) / 3.0;
                assert!(inside(&outline, centroid), "{t:?} of {outline:?} lies outside it");
            }
            assert!((sum - area2(&outline)).abs() < 1e-4, "{sum} vs {}", area2(&outline));
        }
    }
}

#[test]
fn degenerate_and_non_planar_polygons_triangulate_without_panicking() {
    let line = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X, 3.0 * Vec3::X];
    assert_eq!(triangulate(&line).len(), 2);
    let same = [Vec3::ONE; 5];
    assert_eq!(triangulate(&same).len(), 3);
    let bowtie = [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::X, Vec3::Y];
    assert_eq!(triangulate(&bowtie).len(), 2);
    let saddle = [
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.5, 0.4, 0.2),
        Vec3::new(0.0, 1.0, 1.0),
    ];
    assert_eq!(triangulate(&saddle).len(), 3);
    assert!(triangulate(&[Vec3::ZERO, Vec3::X]).is_empty());
    // A tangle of 1000 corners (every ear test fails) finishes, in quadratic time.
    let tangle: Vec<Vec3> =
        (0..1000).map(|k| Vec3::new((k * 7919 % 1000) as f32, (k * 104_729 % 997) as f32, 0.0)).collect();
    assert_eq!(triangulate(&tangle).len(), 998);
}

/// Sum of the areas of the triangles of `mesh`.
fn mesh_area(mesh: &MeshDesc) -> f32 {
    mesh.indices
        .chunks_exact(3)
        .map(|t| {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| mesh.positions[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

#[test]
fn a_concave_obj_face_is_not_fanned() {
    let dir = folder("concave-obj");
    // An L (area 3) starting at a corner that cannot see the whole L: a fan from it
    // would cover the notch and give area 4.
    let obj = b"v 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 0 0 0\nf 1 2 3 4 5 6\n";
    let import = load_mesh(&write(&dir, "l.obj", obj)).unwrap();
    let mesh = &import.meshes[0];
    assert_eq!(mesh.indices.len(), 12);
    assert!((mesh_area(mesh) - 3.0).abs() < 1e-5, "{}", mesh_area(mesh));
}

const QUAD: [[f32; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];

fn header(format: &str, vertex_props: &str, elements: &str) -> String {
    format!("ply\nformat {format} 1.0\nelement vertex 4\n{vertex_props}{elements}end_header\n")
}

const XYZ: &str = "property float x\nproperty float y\nproperty float z\n";

#[test]
fn ply_strips_and_fans_give_the_right_triangles() {
    let dir = folder("strips");
    let strips = header("ascii", XYZ, "element tristrips 1\nproperty list int int vertex_indices\n")
        + "0 0 0\n1 0 0\n0 1 0\n1 1 0\n8 0 1 2 3 -1 3 2 1\n";
    let mesh = &load_mesh(&write(&dir, "s.ply", strips.as_bytes())).unwrap().meshes[0];
    // 0 1 2 3: (0 1 2), (2 1 3) flipped back; the restart begins 3 2 1 afresh.
    assert_eq!(mesh.indices, vec![0, 1, 2, 2, 1, 3, 3, 2, 1]);
    let fan = header("ascii", XYZ, "element face 1\nproperty list uchar int vertex_indices\n")
        + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    let mesh = &load_mesh(&write(&dir, "f.ply", fan.as_bytes())).unwrap().meshes[0];
    assert_eq!(mesh.indices, vec![0, 1, 2, 0, 2, 3]);
}

/// The quad as a binary PLY of either byte order.
fn binary_quad(big_endian: bool) -> Vec<u8> {
    let order = if big_endian { "binary_big_endian" } else { "binary_little_endian" };
    let mut bytes = header(order, XYZ, "element face 1\nproperty list uchar int vertex_indices\n").into_bytes();
    let f = |x: f32| if big_endian { x.to_be_bytes() } else { x.to_le_bytes() };
    let i = |x: i32| if big_endian { x.to_be_bytes() } else { x.to_le_bytes() };
    QUAD.iter().flatten().for_each(|&x| bytes.extend(f(x)));
    bytes.push(4);
    [0, 1, 2, 3].iter().for_each(|&x| bytes.extend(i(x)));
    bytes
}

#[test]
fn big_endian_little_endian_and_ascii_read_the_same() {
    let dir = folder("endian");
    let ascii = header("ascii", XYZ, "element face 1\nproperty list uchar int vertex_indices\n")
        + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    let a = load_mesh(&write(&dir, "a.ply", ascii.as_bytes())).unwrap();
    let le = load_mesh(&write(&dir, "le.ply", &binary_quad(false))).unwrap();
    let be = load_mesh(&write(&dir, "be.ply", &binary_quad(true))).unwrap();
    assert_eq!(a.meshes[0].positions, QUAD.map(Vec3::from).to_vec());
    assert_eq!(a.meshes[0].indices, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(a.meshes[0], le.meshes[0].clone_named(&a.meshes[0]));
    assert_eq!(a.meshes[0], be.meshes[0].clone_named(&a.meshes[0]));
}

trait Named {
    /// The mesh under `other`'s name and path, to compare the rest.
    fn clone_named(&self, other: &MeshDesc) -> MeshDesc;
}

impl Named for MeshDesc {
    fn clone_named(&self, other: &MeshDesc) -> MeshDesc {
        MeshDesc { name: other.name.clone(), path: other.path.clone(), ..self.clone() }
    }
}

#[test]
fn cr_and_crlf_headers_read_as_lf_ones() {
    let dir = folder("line-ends");
    let face = "element face 1\nproperty list uchar int vertex_indices\n";
    let lf = header("ascii", XYZ, face) + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
    let reference = load_mesh(&write(&dir, "lf.ply", lf.as_bytes())).unwrap().meshes.remove(0);
    // A binary body whose first byte is 10 (an LF): after a CR or CRLF header it is data.
    let x = f32::from_le_bytes([10, 0, 0, 0]);
    for (name, eol) in [("cr.ply", "\r"), ("crlf.ply", "\r\n")] {
        let text = lf.replace('\n', eol);
        let mesh = load_mesh(&write(&dir, name, text.as_bytes())).unwrap().meshes.remove(0);
        assert_eq!(mesh.clone_named(&reference), reference, "{name}");
        let mut binary = header("binary_little_endian", XYZ, face).replace('\n', eol).into_bytes();
        binary.extend(x.to_le_bytes());
        QUAD.iter().flatten().skip(1).for_each(|v| binary.extend(v.to_le_bytes()));
        binary.push(4);
        [0i32, 1, 2, 3].iter().for_each(|i| binary.extend(i.to_le_bytes()));
        let mesh = load_mesh(&write(&dir, &format!("bin-{name}"), &binary)).unwrap().meshes.remove(0);
        assert_eq!(mesh.positions[0].x, x, "{name}");
        assert_eq!(mesh.positions[1..], reference.positions[1..], "{name}");
        assert_eq!(mesh.indices, reference.indices, "{name}");
    }
}

#[test]
fn ply_colours_normals_and_uvs_are_read_under_each_name() {
    let dir = folder("names");
    let face = "element face 1\nproperty list uchar int vertex_indices\n";
    let colour_names = [("red", "green", "blue"), ("r", "g", "b"), ("diffuse_red", "diffuse_green", "diffuse_blue")];
    for (r, g, b) in colour_names {
        for (ty, full) in [("uchar", "255"), ("float", "1")] {
            let props = format!("{XYZ}property {ty} {r}\nproperty {ty} {g}\nproperty {ty} {b}\n");
            let text = header("ascii", &props, face)
                + &format!("0 0 0 {full} 0 0\n1 0 0 0 {full} 0\n1 1 0 0 0 0\n0 1 0 {full} {full} {full}\n4 0 1 2 3\n");
            let mesh = &load_mesh(&write(&dir, "c.ply", text.as_bytes())).unwrap().meshes[0];
            assert_eq!(mesh.colors, vec![Vec3::X, Vec3::Y, Vec3::ZERO, Vec3::ONE], "{r} {ty}");
        }
    }
    // uchar 128 is sRGB-encoded: about 0.216 in linear light.
    let props = format!("{XYZ}property uchar red\nproperty uchar green\nproperty uchar blue\n");
    let text = header("ascii", &props, face) + "0 0 0 128 128 128\n1 0 0 0 0 0\n1 1 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n";
    let mesh = &load_mesh(&write(&dir, "grey.ply", text.as_bytes())).unwrap().meshes[0];
    assert!((mesh.colors[0].x - 0.2158605).abs() < 1e-5, "{}", mesh.colors[0]);
    for (u, v) in [("u", "v"), ("s", "t"), ("texture_u", "texture_v"), ("texture_s", "texture_t")] {
        let props = format!(
            "{XYZ}property float nx\nproperty float ny\nproperty float nz\nproperty float {u}\nproperty float {v}\n"
        );
        let text = header("ascii", &props, face)
            + "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";
        let mesh = &load_mesh(&write(&dir, "uv.ply", text.as_bytes())).unwrap().meshes[0];
        assert_eq!(mesh.uvs, vec![Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y], "{u} {v}");
        assert_eq!(mesh.normals, vec![Vec3::Z; 4]);
    }
}

#[test]
fn unknown_ply_header_lines_are_skipped_with_a_warning() {
    let dir = folder("header-lines");
    let text = "ply\nformat ascii 1.0\nobj_info scanned\nelement vertex 3\nproperty float x\nproperty float y\n\
property float z\nfrobnicate 3\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let import = load_mesh(&write(&dir, "h.ply", text.as_bytes())).unwrap();
    assert_eq!(import.meshes[0].indices, vec![0, 1, 2]);
    let warning = import.warnings.iter().find(|w| w.contains("unknown PLY header")).expect("a warning");
    assert!(warning.contains("'obj_info' (line 3)") && warning.contains("'frobnicate' (line 8)"), "{warning}");
}

#[test]
fn git_lfs_pointers_are_named_for_what_they_are() {
    let dir = folder("lfs");
    let pointer = b"version https://git-lfs.github.com/spec/v1\noid sha256:4d7a2146\nsize 12345\n";
    for name in ["bunny.obj", "bunny.ply", "bunny.glb", "bunny.gltf"] {
        let e = load_mesh(&write(&dir, name, pointer)).unwrap_err();
        assert!(e.message.contains("Git LFS pointer") && e.message.contains("git lfs pull"), "{name}: {e}");
        let e = parse_mesh(Path::new(name), pointer.to_vec()).unwrap_err();
        assert!(e.message.contains("Git LFS pointer"), "{name}: {e}");
    }
}

#[test]
fn faces_referring_to_missing_uvs_or_normals_keep_their_positions() {
    let dir = folder("missing");
    let obj = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nf 1/1/1 2/5/1 3/1/1\nf 2/9 4/9 3/9\nf 1//1 2//1 3//1\n";
    let import = load_mesh(&write(&dir, "m.obj", obj)).unwrap();
    let mesh = &import.meshes[0];
    assert_eq!(mesh.indices.len(), 9);
    assert!(mesh.uvs.is_empty() && mesh.normals.is_empty());
    let uv: Vec<_> = import.warnings.iter().filter(|w| w.contains("texture coordinates")).collect();
    assert_eq!(uv.len(), 1, "{:?}", import.warnings);
    assert!(uv[0].contains("2 faces referenced missing texture coordinates"), "{}", uv[0]);
    assert!(import.warnings.iter().any(|w| w.contains("2 faces referenced missing normals")), "{:?}", import.warnings);
    // A missing position is still an error.
    assert!(load_mesh(&write(&dir, "v.obj", b"v 0 0 0\nf 1 2 3\n")).is_err());
}

#[test]
fn obj_vertex_colours_are_read_in_either_range() {
    let dir = folder("obj-colours");
    let unit = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let mesh = load_mesh(&write(&dir, "u.obj", unit)).unwrap().meshes.remove(0);
    assert_eq!(mesh.colors, vec![Vec3::X, Vec3::Y, Vec3::Z]);
    let bytes = b"v 0 0 0 255 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
    let mesh = load_mesh(&write(&dir, "b.obj", bytes)).unwrap().meshes.remove(0);
    assert_eq!(mesh.colors[..2], [Vec3::X, Vec3::Y]);
    assert!(mesh.colors[2].z < 0.01, "1 of 255 is nearly black: {}", mesh.colors[2]);
    let partly = b"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    assert!(load_mesh(&write(&dir, "p.obj", partly)).unwrap().meshes[0].colors.is_empty());
    let merged = merged(&load_mesh(&write(&dir, "u.obj", unit)).unwrap(), "m", "u.obj");
    assert_eq!(merged.colors.len(), 3, "merging keeps the colours");
}

#[test]
fn a_latin1_mtl_keeps_its_materials() {
    let dir = folder("latin1");
    // "Rouge vif é" in Latin-1: 0xE9 is not UTF-8.
    let mut mtl = b"newmtl rouge_\xe9\nKd 1 0 0\n".to_vec();
    mtl.extend(b"newmtl vert\nKd 0 1 0\n");
    write(&dir, "m.mtl", &mtl);
    let mut obj =
        b"mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl rouge_\xe9\nf 1 2 3\nusemtl vert\nf 1 3 2\n".to_vec();
    let import = load_mesh(&write(&dir, "latin.obj", &obj)).unwrap();
    assert_eq!(import.materials.len(), 2, "{:?}", import.warnings);
    assert_eq!(import.materials[0].name, "rouge_é");
    assert_eq!(import.materials[0].diffuse, Vec3::X);
    assert_eq!(import.materials[1].diffuse, Vec3::Y);
    assert!(import.warnings.is_empty(), "{:?}", import.warnings);
    obj.clear();
}

/// A 1×1 PNG at `dir/name`, creating the folders on the way.
fn png(dir: &Path, name: &str) {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    image::RgbImage::from_pixel(1, 1, image::Rgb([255, 0, 0])).save(&path).unwrap();
}

#[test]
fn texture_paths_with_options_backslashes_and_spaces_are_found() {
    let dir = folder("maps");
    png(&dir, "textures/wood.png");
    png(&dir, "my tex.png");
    png(&dir, "plain.png");
    let mtl = "newmtl a\nmap_Kd textures\\wood.png\n\
newmtl b\nmap_Kd -s 2 2 1 -o 0.5 0.5 -bm 1.0 -clamp on my tex.png\n\
newmtl c\nmap_Kd my\\ tex.png\n\
newmtl d\nmap_Kd -blendu off C:\\Users\\someone\\plain.png\n";
    write(&dir, "m.mtl", mtl.as_bytes());
    let mut obj = String::from("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for name in ["a", "b", "c", "d"] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let import = load_mesh(&write(&dir, "t.obj", obj.as_bytes())).unwrap();
    assert!(import.warnings.is_empty(), "{:?}", import.warnings);
    assert_eq!(import.textures.len(), 4);
    assert!(import.materials.iter().all(|m| m.texture.is_some()));
    assert_eq!(mtl::map_file("-s 1 1 1 -clamp on my tex.png").as_deref(), Some("my tex.png"));
    assert_eq!(mtl::map_file("-mm 0 1 -o 1 f.png").as_deref(), Some("f.png"));
    assert_eq!(mtl::map_file("-bm 0.5"), None);
}

#[test]
fn mtl_emission_transparency_mirrors_and_glass() {
    let dir = folder("mtl-terms");
    let mtl = "newmtl lamp\nKe 4 4 3\n\
newmtl veil\nKd 1 1 1\nd 0.25\nNi 1.45\nillum 2\n\
newmtl screen\nTr 0.5\n\
newmtl mirror\nKs 0.9 0.9 0.9\nillum 3\n\
newmtl shiny\nKs 0.5 0.5 0.5\nillum 2\n\
newmtl glass\nKs 1 1 1\nNi 1.5\nillum 7\n\
newmtl bumpy\nmap_Ks spec.png\n";
    write(&dir, "m.mtl", mtl.as_bytes());
    let names = ["lamp", "veil", "screen", "mirror", "shiny", "glass", "bumpy"];
    let mut obj = String::from("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for name in names {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let import = load_mesh(&write(&dir, "t.obj", obj.as_bytes())).unwrap();
    let m = |name: &str| import.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(m("lamp").emission, Vec3::new(4.0, 4.0, 3.0));
    assert_eq!((m("veil").transmissive, m("veil").ior, m("veil").kd), (Vec3::splat(0.75), 1.0, 0.25));
    assert_eq!(m("screen").transmissive, Vec3::splat(0.5));
    assert_eq!(m("mirror").reflective, Some(Vec3::splat(0.9)));
    assert_eq!(m("shiny").reflective, Some(Vec3::ZERO), "illum 2 is a highlight, not a mirror");
    assert_eq!((m("glass").transmissive, m("glass").ior), (Vec3::ONE, 1.5));
    assert_eq!(m("glass").reflective, Some(Vec3::ONE));
    assert!(matches!(m("glass").bsdf, Some(glint_core::desc::BsdfDesc::Dielectric { int_ior: 1.5, .. })));
    assert_eq!(m("veil").bsdf, None, "dissolve is not glass");
    let unused: Vec<_> = import.warnings.iter().filter(|w| w.contains("read but not used")).collect();
    assert_eq!(unused.len(), 1, "{:?}", import.warnings);
    assert!(unused[0].contains("m.mtl") && unused[0].contains("'bumpy'"), "{}", unused[0]);
    assert!(unused[0].contains("map_Ks"), "{}", unused[0]);
}

#[test]
fn mtl_normal_maps_are_read_as_data_and_height_maps_named() {
    let dir = folder("mtl-normals");
    let save = |name: &str, rgb: [u8; 3]| {
        image::save_buffer(dir.join(name), &rgb.repeat(4), 2, 2, image::ExtendedColorType::Rgb8).unwrap();
    };
    save("normal.png", [128, 128, 255]);
    save("height.png", [90, 90, 90]);
    let mtl = "newmtl norm\nnorm normal.png\n\
newmtl blender\nmap_Bump -bm 0.5 normal.png\n\
newmtl height\nbump height.png\n";
    write(&dir, "m.mtl", mtl.as_bytes());
    let mut obj = String::from("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for name in ["norm", "blender", "height"] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let import = load_mesh(&write(&dir, "t.obj", obj.as_bytes())).unwrap();
    let m = |name: &str| import.materials.iter().find(|m| m.name == name).unwrap();
    let norm = m("norm").normal_map.expect("norm is a normal map");
    assert_eq!(norm.scale, 1.0);
    // Read as data: 128/255, not the sRGB-decoded 0.216.
    let TextureDesc::Image { texels, .. } = &import.textures[norm.texture] else { panic!() };
    assert!((texels[0] - Vec3::new(128.0, 128.0, 255.0) / 255.0).length() < 1e-6, "{}", texels[0]);
    assert_eq!(m("blender").normal_map.map(|n| n.scale), Some(0.5), "a bluish map_Bump is a normal map");
    assert_eq!(m("height").normal_map, None);
    assert!(import.warnings.iter().any(|w| w.contains("height.png is a bump (height) map")), "{:?}", import.warnings);
}
