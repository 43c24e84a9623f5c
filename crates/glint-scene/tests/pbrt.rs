//! pbrt-v4 scenes: directives, transforms, the camera (and pbrt's handedness), shapes,
//! materials, lights and textures read into a `SceneDesc` with pbrt's meaning;
//! malformed input refused at its file and line; a small Cornell box rendered.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};
use glint_core::desc::{
    BsdfDesc, FovAxis, IntegratorDesc, LightDesc, NodeDesc, NodeKind, PathDesc, SceneDesc, ShapeDesc, TextureDesc,
    matrix_of,
};
use glint_scene::pbrt::parse_pbrt;
use glint_scene::{Loaded, SceneError, SceneFormat, load_any};

/// A camera that keeps pbrt's world unmirrored in glint (`Scale -1 1 1` makes the
/// camera transform reverse handedness), so tests can read world positions directly.
const UNMIRRORED: &str = "Scale -1 1 1\nLookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n";

fn parse(text: &str) -> Result<Loaded, SceneError> {
    parse_pbrt(text, "scene.pbrt", Path::new("."))
}

#[track_caller]
fn load(text: &str) -> Loaded {
    parse(text).unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn scene(text: &str) -> SceneDesc {
    load(text).scene
}

/// Asserts an error in scene.pbrt at `line` whose message contains `fragment`.
#[track_caller]
fn assert_error(text: &str, line: u32, fragment: &str) -> SceneError {
    let e = match parse(text) {
        Ok(_) => panic!("expected an error mentioning {fragment:?}"),
        Err(e) => e,
    };
    assert_eq!((e.file.as_str(), e.line()), ("scene.pbrt", line), "wrong place for: {e}");
    assert!(e.message.contains(fragment), "message {:?} lacks {fragment:?}", e.message);
    e
}

#[track_caller]
fn close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, 1e-4), "{a} ≠ {b}");
}

/// Every shape with its material and glint world-from-object matrix, groups flattened.
fn shapes(s: &SceneDesc) -> Vec<(ShapeDesc, usize, Mat4)> {
    fn walk(nodes: &[NodeDesc], parent: Mat4, out: &mut Vec<(ShapeDesc, usize, Mat4)>) {
        for n in nodes {
            let m = parent * matrix_of(&n.transform);
            match &n.kind {
                NodeKind::Shape { shape, material } => out.push((*shape, *material, m)),
                NodeKind::Group(children) => walk(children, m, out),
                other => panic!("{other:?}"),
            }
        }
    }
    let mut out = Vec::new();
    walk(&s.objects, Mat4::IDENTITY, &mut out);
    out
}

/// The glint world position of each shape's object-space origin.
fn centres(s: &SceneDesc) -> Vec<Vec3> {
    shapes(s).iter().map(|(_, _, m)| m.transform_point3(Vec3::ZERO)).collect()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-pbrt-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn transforms_post_multiply_in_pbrt_order() {
    let s = scene(&format!(
        "{UNMIRRORED}AttributeBegin\n Translate 1 2 3\n Scale 2 2 2\n Shape \"sphere\" \"float radius\" 0.5\nAttributeEnd\n\
         AttributeBegin\n Rotate 90 0 0 1\n Translate 1 0 0\n Shape \"sphere\"\nAttributeEnd\n\
         AttributeBegin\n ConcatTransform [1 0 0 0  0 1 0 0  0 0 1 0  4 5 6 1]\n Shape \"sphere\"\nAttributeEnd\n\
         AttributeBegin\n Translate 9 9 9\n Transform [1 0 0 0  0 1 0 0  0 0 1 0  -1 0 0 1]\n Shape \"sphere\"\nAttributeEnd\n"
    ));
    let c = centres(&s);
    close(c[0], Vec3::new(1.0, 2.0, 3.0));
    // Scale 2 then radius 0.5: a unit sphere's surface point (1, 0, 0) lands 1 from the centre.
    let (_, _, m) = shapes(&s)[0];
    close(m.transform_point3(Vec3::X), Vec3::new(2.0, 2.0, 3.0));
    // The Rotate written first acts last: the translation is turned onto +y.
    close(c[1], Vec3::new(0.0, 1.0, 0.0));
    // The 16 numbers are column by column: the last four are the translation.
    close(c[2], Vec3::new(4.0, 5.0, 6.0));
    // Transform replaces the current matrix.
    close(c[3], Vec3::new(-1.0, 0.0, 0.0));
}

#[test]
fn attribute_blocks_restore_transform_and_material() {
    let s = scene(&format!(
        "{UNMIRRORED}Material \"diffuse\" \"rgb reflectance\" [0.1 0.2 0.3]\n\
         AttributeBegin\n Translate 5 0 0\n Material \"conductor\"\n Shape \"sphere\"\nAttributeEnd\n\
         Shape \"sphere\"\nTransformBegin\n Translate 0 7 0\nTransformEnd\nShape \"sphere\"\n"
    ));
    let all = shapes(&s);
    let c = centres(&s);
    close(c[0], Vec3::new(5.0, 0.0, 0.0));
    close(c[1], Vec3::ZERO);
    close(c[2], Vec3::ZERO);
    assert!(matches!(s.materials[all[0].1].bsdf, Some(BsdfDesc::Conductor { .. })));
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[all[1].1].bsdf else { panic!() };
    close(reflectance.value, Vec3::new(0.1, 0.2, 0.3));
}

#[test]
fn look_at_places_the_camera_and_pbrts_image_is_not_mirrored() {
    // A rotation (LookAt alone) needs the world mirrored; `Scale -1 1 1` does not.
    let s =
        scene("LookAt 1 2 3  1 2 0  0 1 0\nCamera \"perspective\" \"float fov\" 30\nWorldBegin\nShape \"sphere\"\n");
    close(s.camera.eye, Vec3::new(-1.0, 2.0, 3.0));
    close(s.camera.look.normalize(), Vec3::NEG_Z);
    close(s.camera.up.normalize(), Vec3::Y);
    assert_eq!((s.camera.fov_y_degrees, s.camera.fov_axis), (30.0, FovAxis::Smaller));
    let root = &s.objects[0];
    assert_eq!(matrix_of(&root.transform), Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)));
    let s = scene(UNMIRRORED);
    close(s.camera.eye, Vec3::new(0.0, 0.0, -5.0));
    assert!(s.objects.is_empty());
}

/// Renders `s` with the Whitted integrator (fast, deterministic) at its size.
fn render_whitted(mut s: SceneDesc) -> glint_core::film::Image {
    s.settings.integrator = IntegratorDesc::Whitted;
    s.settings.spp = None;
    s.settings.samples_per_axis = 1;
    let compiled = glint_core::scene::compile(&s).unwrap();
    glint_core::render::render(&compiled, &|_, _| {}, &std::sync::atomic::AtomicBool::new(false)).unwrap().0
}

#[test]
fn the_image_shows_what_pbrt_shows() {
    // pbrt's camera space is left-handed: looking from +z at the origin with +y up,
    // world +x is on the image's LEFT. A red sphere there, a blue one at −x.
    let body = "Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 16\nWorldBegin\n\
        LightSource \"point\" \"point3 from\" [0 0 5] \"rgb I\" [25 25 25]\n\
        AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [1 0 0]\n Translate 1.5 0 0\n Shape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n\
        AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [0 0 1]\n Translate -1.5 0 0\n Shape \"sphere\" \"float radius\" 0.6\nAttributeEnd\n";
    let image =
        render_whitted(scene(&format!("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n{body}")));
    let (left, right) = (image.get(7, 8), image.get(24, 8));
    assert!(left.x > 0.1 && left.z < 0.01, "left shows the red sphere at +x: {left}");
    assert!(right.z > 0.1 && right.x < 0.01, "right shows the blue sphere at −x: {right}");
    // With the customary `Scale -1 1 1`, pbrt shows +x on the right.
    let image = render_whitted(scene(&format!(
        "Scale -1 1 1\nLookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\n{body}"
    )));
    let (left, right) = (image.get(7, 8), image.get(24, 8));
    assert!(right.x > 0.1 && left.z > 0.1, "{left} {right}");
}

#[test]
fn object_instances_store_the_mesh_once() {
    let s = scene(&format!(
        "{UNMIRRORED}ObjectBegin \"tri\"\n Translate 0 0 1\n Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\nObjectEnd\n\
         Translate 10 0 0\nObjectInstance \"tri\"\nTranslate 10 0 0\nObjectInstance \"tri\"\n"
    ));
    assert_eq!(s.meshes.len(), 1);
    let all = shapes(&s);
    assert_eq!(all.len(), 2);
    assert!(all.iter().all(|(shape, _, _)| *shape == ShapeDesc::Mesh { index: 0 }));
    close(all[0].2.transform_point3(Vec3::ZERO), Vec3::new(10.0, 0.0, 1.0));
    close(all[1].2.transform_point3(Vec3::X), Vec3::new(21.0, 0.0, 1.0));
}

#[test]
fn meshes_read_positions_normals_uvs_and_bilinear_patches() {
    let s = scene(&format!(
        "{UNMIRRORED}Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0] \"integer indices\" [0 1 2 0 2 3]\n\
           \"normal N\" [0 0 1 0 0 1 0 0 1 0 0 1] \"point2 uv\" [0 0 1 0 1 1 0 1]\n\
         Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n\
         ReverseOrientation\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n"
    ));
    let m = &s.meshes[0];
    assert_eq!((m.positions.len(), m.normals.len(), m.uvs.len(), m.indices.len()), (4, 4, 4, 6));
    // Both triangles of the patch face +z, as ∂p/∂u × ∂p/∂v does.
    let b = &s.meshes[1];
    for t in b.indices.chunks(3) {
        let [p0, p1, p2] = [t[0], t[1], t[2]].map(|i| b.positions[i as usize]);
        assert!((p1 - p0).cross(p2 - p0).z > 0.0, "{t:?}");
    }
    assert_eq!(b.indices.len(), 6);
    // ReverseOrientation turns the winding around.
    assert_eq!(s.meshes[2].indices, vec![0, 2, 1]);
}

#[test]
fn includes_are_found_next_to_the_including_file() {
    let dir = temp_dir("include");
    std::fs::create_dir_all(dir.join("geometry")).unwrap();
    std::fs::write(dir.join("geometry/ball.pbrt"), "Translate 0 3 0\nShape \"sphere\"\nInclude \"more.pbrt\"\n")
        .unwrap();
    std::fs::write(dir.join("geometry/more.pbrt"), "Shape \"disk\"\n").unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        format!("{UNMIRRORED}AttributeBegin\nInclude \"geometry/ball.pbrt\"\nAttributeEnd\nShape \"sphere\"\n"),
    )
    .unwrap();
    let loaded = load_any(&dir.join("scene.pbrt")).unwrap();
    assert_eq!(loaded.format, SceneFormat::Pbrt);
    let c = centres(&loaded.scene);
    assert_eq!(c.len(), 3);
    close(c[0], Vec3::new(0.0, 3.0, 0.0));
    close(c[1], Vec3::new(0.0, 3.0, 0.0));
    close(c[2], Vec3::ZERO);
    std::fs::write(dir.join("bad.pbrt"), "WorldBegin\n\nInclude \"missing.pbrt\"\n").unwrap();
    let e = load_any(&dir.join("bad.pbrt")).unwrap_err();
    assert_eq!(e.line(), 3, "{e}");
    assert!(e.message.contains("missing.pbrt"), "{e}");
    std::fs::write(dir.join("self.pbrt"), "Include \"self.pbrt\"\n").unwrap();
    assert!(load_any(&dir.join("self.pbrt")).unwrap_err().message.contains("nest"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn named_materials_map_to_their_bsdfs() {
    let s = scene(&format!(
        "{UNMIRRORED}MakeNamedMaterial \"copper\" \"string type\" \"conductor\" \"float roughness\" 0.25\n\
         MakeNamedMaterial \"gold\" \"string type\" \"conductor\" \"spectrum eta\" \"metal-Au-eta\" \"spectrum k\" \"metal-Au-k\" \"bool remaproughness\" false \"float roughness\" 0.2\n\
         MakeNamedMaterial \"glass\" \"string type\" \"dielectric\" \"float eta\" 1.33\n\
         MakeNamedMaterial \"bk7\" \"string type\" \"dielectric\" \"spectrum eta\" \"glass-BK7\"\n\
         MakeNamedMaterial \"paint\" \"string type\" \"coateddiffuse\" \"rgb reflectance\" [0.4 0.2 0.2] \"float roughness\" 0.01\n\
         MakeNamedMaterial \"pane\" \"string type\" \"thindielectric\"\n\
         NamedMaterial \"copper\"\nShape \"sphere\"\nNamedMaterial \"gold\"\nShape \"sphere\"\nNamedMaterial \"glass\"\nShape \"sphere\"\n\
         NamedMaterial \"bk7\"\nShape \"sphere\"\nNamedMaterial \"paint\"\nShape \"sphere\"\nNamedMaterial \"pane\"\nShape \"sphere\"\n"
    ));
    let bsdf = |i: usize| s.materials[shapes(&s)[i].1].bsdf.unwrap();
    let BsdfDesc::Conductor { eta, k, alpha, .. } = bsdf(0) else { panic!("{:?}", bsdf(0)) };
    // pbrt's default conductor is copper; roughness 0.25 remaps to alpha 0.5.
    assert!(eta.x < eta.z && k.x > k.z, "{eta} {k}");
    assert!((alpha.value - 0.5).abs() < 1e-6);
    let BsdfDesc::Conductor { eta, alpha, .. } = bsdf(1) else { panic!() };
    assert!(eta.z > 1.0 && eta.x < 0.5, "gold: {eta}");
    assert_eq!(alpha.value, 0.2);
    assert!(matches!(bsdf(2), BsdfDesc::Dielectric { int_ior, ext_ior, .. } if int_ior == 1.33 && ext_ior == 1.0));
    assert!(matches!(bsdf(3), BsdfDesc::Dielectric { int_ior, .. } if (int_ior - 1.5168).abs() < 1e-4));
    let BsdfDesc::Plastic { diffuse, int_ior, alpha, .. } = bsdf(4) else { panic!() };
    close(diffuse.value, Vec3::new(0.4, 0.2, 0.2));
    assert_eq!(int_ior, 1.5);
    assert!((alpha.value - 0.1).abs() < 1e-6);
    assert!(matches!(bsdf(5), BsdfDesc::ThinDielectric { int_ior, .. } if int_ior == 1.5));
}

#[test]
fn pbrt_v3_materials_are_approximated_with_a_warning() {
    let loaded = load(&format!(
        "{UNMIRRORED}Material \"matte\" \"color Kd\" [0.1 0.2 0.3]\nShape \"sphere\"\n\
         Material \"glass\" \"float index\" 1.4\nShape \"sphere\"\nMaterial \"mirror\"\nShape \"sphere\"\n"
    ));
    let s = &loaded.scene;
    let bsdf = |i: usize| s.materials[shapes(s)[i].1].bsdf.unwrap();
    assert!(matches!(bsdf(0), BsdfDesc::Diffuse { reflectance } if reflectance.value == Vec3::new(0.1, 0.2, 0.3)));
    assert!(matches!(bsdf(1), BsdfDesc::Dielectric { int_ior, .. } if int_ior == 1.4));
    assert!(matches!(bsdf(2), BsdfDesc::Conductor { eta, k, .. } if eta == Vec3::ZERO && k == Vec3::ONE));
    assert_eq!(loaded.warnings.iter().filter(|w| w.contains("pbrt-v3 material")).count(), 3, "{:?}", loaded.warnings);
}

#[test]
fn area_lights_make_the_following_shapes_emit() {
    let loaded = load(&format!(
        "{UNMIRRORED}AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [2 3 4] \"float scale\" 2\n Shape \"sphere\"\n Shape \"disk\"\nAttributeEnd\n\
         Shape \"sphere\"\nAttributeBegin\n AreaLightSource \"diffuse\" \"blackbody L\" 3000 \"bool twosided\" true\n Shape \"disk\"\nAttributeEnd\n"
    ));
    let s = &loaded.scene;
    let all = shapes(s);
    close(s.materials[all[0].1].emission, Vec3::new(4.0, 6.0, 8.0));
    assert_eq!(all[0].1, all[1].1, "one emitting material for both shapes");
    assert_eq!(s.materials[all[2].1].emission, Vec3::ZERO, "AttributeEnd ends the area light");
    let warm = s.materials[all[3].1].emission;
    assert!(warm.x > warm.z, "a 3000 K black body is warm: {warm}");
    // pbrt's lights are one-sided unless `twosided`: glint emits from both sides of a
    // two-sided material only.
    assert!(!s.materials[all[0].1].two_sided && s.materials[all[3].1].two_sided);
    assert!(s.materials[all[2].1].two_sided, "pbrt's materials scatter on both sides");
}

#[test]
fn blackbodies_have_unit_luminance_and_take_pbrt_v3s_scale() {
    let s = scene(&format!(
        "{UNMIRRORED}LightSource \"point\" \"blackbody I\" 2700\nLightSource \"point\" \"blackbody I\" [2700 3]\n"
    ));
    let (LightDesc::Point { color: a, .. }, LightDesc::Point { color: b, .. }) = (&s.lights[0], &s.lights[1]) else {
        panic!()
    };
    let luminance = a.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    assert!((luminance - 1.0).abs() < 0.05 && a.x > a.z, "{a}");
    close(*b, 3.0 * *a);
}

#[test]
fn area_light_power_sets_each_shapes_radiance() {
    // A 2×2 quad emitting 8π W from one side: L = Φ / (π · A) = 2; a disk of radius 1
    // emitting π W from both sides: L = π / (π · π · 2).
    let s = scene(&format!(
        "{UNMIRRORED}AttributeBegin\nAreaLightSource \"diffuse\" \"float power\" 25.132741\n\
         Shape \"bilinearmesh\" \"point3 P\" [0 0 0 2 0 0 0 2 0 2 2 0]\nAttributeEnd\n\
         AreaLightSource \"diffuse\" \"float power\" 3.1415927 \"bool twosided\" true\nShape \"disk\"\n"
    ));
    let all = shapes(&s);
    close(s.materials[all[0].1].emission, Vec3::splat(2.0));
    close(s.materials[all[1].1].emission, Vec3::splat(1.0 / (2.0 * std::f32::consts::PI)));
}

#[test]
fn light_sources_are_placed_by_the_current_transform() {
    let s = scene(&format!(
        "{UNMIRRORED}Translate 0 1 0\nLightSource \"point\" \"point3 from\" [1 2 3] \"rgb I\" [1 2 3] \"float scale\" 2\n\
         LightSource \"spot\" \"point3 from\" [0 0 0] \"point3 to\" [0 -1 0] \"float coneangle\" 20 \"float conedelta\" 4\n\
         LightSource \"distant\" \"point3 from\" [0 10 0] \"point3 to\" [0 0 0] \"blackbody L\" 6500\n\
         LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
    ));
    let LightDesc::Point { position, color, attenuation } = s.lights[0] else { panic!() };
    close(position, Vec3::new(1.0, 3.0, 3.0));
    close(color, Vec3::new(2.0, 4.0, 6.0));
    assert_eq!(attenuation, Vec3::new(0.0, 0.0, 1.0));
    let LightDesc::Spot { position, direction, angle_degrees, penumbra_degrees, .. } = s.lights[1] else { panic!() };
    close(position, Vec3::Y);
    close(direction, Vec3::NEG_Y);
    assert_eq!((angle_degrees, penumbra_degrees), (20.0, 4.0));
    let LightDesc::Directional { direction, color } = s.lights[2] else { panic!() };
    close(direction, Vec3::NEG_Y);
    assert!((color.dot(Vec3::new(0.2126, 0.7152, 0.0722)) - 1.0).abs() < 0.05, "unit luminance: {color}");
    let LightDesc::Environment(env) = &s.lights[3] else { panic!() };
    close(env.radiance, Vec3::new(0.1, 0.2, 0.3));
}

#[test]
fn render_settings_follow_pbrt() {
    let s = scene(
        "Film \"rgb\" \"integer xresolution\" 64 \"integer yresolution\" 48 \"string filename\" \"out.exr\"\n\
         Sampler \"halton\" \"integer pixelsamples\" 8\nIntegrator \"volpath\" \"integer maxdepth\" 3\nWorldBegin\n",
    );
    assert_eq!((s.settings.width, s.settings.height, s.settings.spp), (64, 48, Some(8)));
    let IntegratorDesc::Path(PathDesc { max_depth, .. }) = s.settings.integrator else { panic!() };
    assert_eq!(max_depth, 4, "pbrt's maxdepth 3 is glint's (Mitsuba's) 4");
    let s = scene("WorldBegin\n");
    let IntegratorDesc::Path(PathDesc { max_depth, .. }) = s.settings.integrator else { panic!() };
    assert_eq!((s.settings.width, s.settings.height, s.settings.spp, max_depth), (1280, 720, Some(16), 6));
    assert_eq!(s.camera.fov_y_degrees, 90.0);
}

#[test]
fn textures_attach_to_reflectance() {
    let s = scene(&format!(
        "{UNMIRRORED}Texture \"checks\" \"spectrum\" \"checkerboard\" \"float uscale\" 4 \"float vscale\" 2 \"rgb tex1\" [1 0 0] \"rgb tex2\" [0 0 1]\n\
         Texture \"grey\" \"spectrum\" \"constant\" \"rgb value\" [0.3 0.3 0.3]\n\
         Material \"diffuse\" \"texture reflectance\" \"checks\"\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"point2 uv\" [0 0 1 0 0 1 1 1]\n\
         Material \"diffuse\" \"texture reflectance\" \"grey\"\nShape \"sphere\"\n"
    ));
    let all = shapes(&s);
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[all[0].1].bsdf else { panic!() };
    let TextureDesc::Checker { even, odd, cells, .. } = &s.textures[reflectance.texture.unwrap()] else { panic!() };
    assert_eq!((*even, *odd, cells.x, cells.y), (Vec3::X, Vec3::Z, 4.0, 2.0));
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[all[1].1].bsdf else { panic!() };
    assert_eq!((reflectance.value, reflectance.texture), (Vec3::splat(0.3), None));
}

#[test]
fn ply_meshes_plain_and_gzipped() {
    use std::io::Write;
    let dir = temp_dir("ply");
    let ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
               element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::fs::write(dir.join("tri.ply"), ply).unwrap();
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(ply.as_bytes()).unwrap();
    std::fs::write(dir.join("tri.ply.gz"), gz.finish().unwrap()).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        format!("{UNMIRRORED}Shape \"plymesh\" \"string filename\" \"tri.ply\"\nShape \"plymesh\" \"string filename\" \"tri.ply.gz\"\n"),
    )
    .unwrap();
    let s = load_any(&dir.join("scene.pbrt")).unwrap().scene;
    assert_eq!(s.meshes.len(), 2);
    assert_eq!(s.meshes[0].positions, s.meshes[1].positions);
    close(s.meshes[1].positions[1], Vec3::X);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn loop_subdivision_refines_the_control_mesh() {
    let s = scene(&format!(
        "{UNMIRRORED}Shape \"loopsubdiv\" \"integer levels\" 2 \"point3 P\" [1 1 1 1 -1 -1 -1 1 -1 -1 -1 1] \"integer indices\" [0 1 2 0 3 1 0 2 3 1 3 2]\n"
    ));
    assert_eq!(s.meshes[0].indices.len(), 3 * 4 * 16);
    assert_eq!(s.meshes[0].normals.len(), s.meshes[0].positions.len());
}

#[test]
fn unsupported_but_valid_input_warns_with_its_line() {
    let loaded = load(&format!(
        "{UNMIRRORED}Shape \"curve\" \"point3 P\" [0 0 0 1 1 1 2 2 2 3 3 3]\nMaterial \"hair\"\nShape \"sphere\" \"float zmax\" 0.5 \"float nonsense\" 1\n"
    ));
    let w = &loaded.warnings;
    assert!(w.iter().any(|w| w.starts_with("scene.pbrt:5:1") && w.contains("curve")), "{w:?}");
    assert!(w.iter().any(|w| w.starts_with("scene.pbrt:6:1") && w.contains("hair")), "{w:?}");
    assert!(w.iter().any(|w| w.starts_with("scene.pbrt:7:") && w.contains("zmax")), "{w:?}");
    assert!(w.iter().any(|w| w.starts_with("scene.pbrt:7:") && w.contains("nonsense")), "{w:?}");
    assert_eq!(shapes(&loaded.scene).len(), 1);
}

#[test]
fn bad_input_is_an_error_at_its_line() {
    assert_error("WorldBegin\n\nSphere \"x\"\n", 3, "unknown directive 'Sphere'");
    assert_error("WorldBegin\nShape \"sphere\"\n  \"float radius\" [ \"big\" ]\n", 3, "not of that type");
    assert_error("WorldBegin\nShape \"sphere\" \"integer radius\" 2\n", 2, "expected float");
    assert_error("WorldBegin\nShape \"sphere\" \"real radius\" 2\n", 2, "unknown parameter type");
    assert_error("WorldBegin\nShape \"sphere\n", 2, "unterminated string");
    assert_error("WorldBegin\nTranslate 1 -nan 0\n", 2, "not a finite number");
    assert_error("WorldBegin\nTranslate 1 1e999 0\n", 2, "not a finite number");
    assert_error(
        "WorldBegin\n\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]\n",
        3,
        "out of range",
    );
    assert_error("WorldBegin\nAttributeBegin\n", 2, "never closed");
    assert_error("WorldBegin\nAttributeEnd\n", 2, "no AttributeBegin");
    assert_error("WorldBegin\nNamedMaterial \"nope\"\n", 2, "no material is named");
    assert_error("WorldBegin\nObjectInstance \"nope\"\n", 2, "no object is named");
    assert_error("Shape \"sphere\"\n", 1, "after WorldBegin");
    assert_error("WorldBegin\nCamera \"perspective\"\n", 2, "before WorldBegin");
    assert_error("WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [1 1]\n", 2, "takes 3 numbers");
    assert_error("WorldBegin\nMaterial \"conductor\" \"spectrum eta\" \"metal-Xx-eta\"\n", 2, "unknown metal");
    assert_error("WorldBegin\nShape \"sphere\" \"float radius\" [1\n", 2, "never closed");
    assert_error("WorldBegin\nTranslate 1 2\n", 2, "takes 3 numbers");
}

#[test]
fn colour_spaces_convert_rgb_to_srgb() {
    let s = scene(&format!(
        "{UNMIRRORED}ColorSpace \"rec2020\"\nMaterial \"diffuse\" \"rgb reflectance\" [0 0.5 0]\nShape \"sphere\"\n"
    ));
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[shapes(&s)[0].1].bsdf else { panic!() };
    // Rec. 2020's green is more saturated than sRGB's: negative red and blue.
    assert!(reflectance.value.y > 0.5 && reflectance.value.x < 0.0, "{}", reflectance.value);
}

/// A Cornell-like box in pbrt's terms: red wall at x = +1 (the image's left, pbrt's
/// camera being left-handed), green at x = −1, a light under the ceiling.
const CORNELL: &str = r#"LookAt 0 0 3.4  0 0 0  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 32 "integer yresolution" 32
Sampler "independent" "integer pixelsamples" 16
Integrator "path" "integer maxdepth" 4
WorldBegin
MakeNamedMaterial "white" "string type" "diffuse" "rgb reflectance" [0.7 0.7 0.7]
MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [0.7 0.05 0.05]
MakeNamedMaterial "green" "string type" "diffuse" "rgb reflectance" [0.05 0.7 0.05]
NamedMaterial "white"
Shape "bilinearmesh" "point3 P" [-1 -1 -1  1 -1 -1  -1 -1 1  1 -1 1]
Shape "bilinearmesh" "point3 P" [-1 1 -1  1 1 -1  -1 1 1  1 1 1]
Shape "bilinearmesh" "point3 P" [-1 -1 -1  1 -1 -1  -1 1 -1  1 1 -1]
NamedMaterial "red"
Shape "bilinearmesh" "point3 P" [1 -1 -1  1 1 -1  1 -1 1  1 1 1]
NamedMaterial "green"
Shape "bilinearmesh" "point3 P" [-1 -1 -1  -1 1 -1  -1 -1 1  -1 1 1]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [12 12 12]
  NamedMaterial "white"
  Shape "trianglemesh" "point3 P" [-0.3 0.99 -0.3  0.3 0.99 -0.3  0.3 0.99 0.3  -0.3 0.99 0.3]
    "integer indices" [0 1 2 0 2 3]
AttributeEnd
"#;

#[test]
fn a_cornell_box_renders_with_the_light_on_top_and_red_on_the_left() {
    let s = scene(CORNELL);
    let compiled = glint_core::scene::compile(&s).unwrap();
    let (image, _) =
        glint_core::render::render(&compiled, &|_, _| {}, &std::sync::atomic::AtomicBool::new(false)).unwrap();
    let mean = |xs: std::ops::Range<u32>, ys: std::ops::Range<u32>| {
        let n = (xs.len() * ys.len()) as f32;
        ys.flat_map(|y| xs.clone().map(move |x| (x, y))).map(|(x, y)| image.get(x, y)).sum::<Vec3>() / n
    };
    let light = mean(14..18, 3..5);
    let middle = mean(12..20, 12..20);
    assert!(light.min_element() > 2.0 * middle.max_element(), "the light is brightest: {light} vs {middle}");
    let (left, right) = (mean(1..4, 10..22), mean(28..31, 10..22));
    assert!(left.x > 2.0 * left.y, "left wall is red: {left}");
    assert!(right.y > 2.0 * right.x, "right wall is green: {right}");
    assert!(middle.min_element() > 0.01, "indirect light reaches the back wall: {middle}");
}

/// Writes a `w`×`h` 8-bit PNG whose pixel (x, y) (row 0 at the top) is `f(x, y)`.
fn write_png(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) {
    image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y))).save(path).unwrap();
}

#[test]
fn image_textures_keep_their_rows_and_resolve_next_to_the_file() {
    let dir = temp_dir("imagemap");
    // Top row white, bottom row black: pbrt's t = 0 is the bottom row, as glint's v = 0.
    write_png(&dir.join("rows.png"), 2, 2, |_, y| if y == 0 { [255; 3] } else { [0; 3] });
    std::fs::write(
        dir.join("scene.pbrt"),
        format!(
            "{UNMIRRORED}Texture \"rows\" \"spectrum\" \"imagemap\" \"string filename\" \"rows.png\"\n\
             Texture \"dim\" \"spectrum\" \"scale\" \"texture tex\" \"rows\" \"float scale\" 0.5\n\
             Material \"diffuse\" \"texture reflectance\" \"rows\"\nShape \"sphere\"\n\
             Material \"diffuse\" \"texture reflectance\" \"dim\"\nShape \"sphere\"\n"
        ),
    )
    .unwrap();
    let s = load_any(&dir.join("scene.pbrt")).unwrap().scene;
    let TextureDesc::Image { width, height, texels, .. } = &s.textures[0] else { panic!() };
    assert_eq!((*width, *height), (2, 2));
    assert_eq!((texels[0], texels[3]), (Vec3::ONE, Vec3::ZERO));
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[shapes(&s)[0].1].bsdf else { panic!() };
    assert_eq!((reflectance.value, reflectance.texture), (Vec3::ONE, Some(0)));
    // A `scale` texture is the same image with the factor as the parameter's value.
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[shapes(&s)[1].1].bsdf else { panic!() };
    assert_eq!((reflectance.value, reflectance.texture), (Vec3::splat(0.5), Some(0)));
    assert_eq!(s.textures.len(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_equal_area_environment_map_is_resampled_to_equirectangular() {
    let dir = temp_dir("envmap");
    // The centre of pbrt-v4's octahedral map is the light's +z; its corners are −z.
    write_png(&dir.join("sky.png"), 16, 16, |x, y| {
        if (6..10).contains(&x) && (6..10).contains(&y) { [255; 3] } else { [0; 3] }
    });
    std::fs::write(
        dir.join("scene.pbrt"),
        format!("{UNMIRRORED}LightSource \"infinite\" \"string filename\" \"sky.png\" \"float scale\" 2\n"),
    )
    .unwrap();
    let s = load_any(&dir.join("scene.pbrt")).unwrap().scene;
    let LightDesc::Environment(env) = &s.lights[0] else { panic!() };
    assert_eq!(env.radiance, Vec3::splat(2.0));
    let TextureDesc::Image { width, height, texels, .. } = &s.textures[env.texture.unwrap()] else { panic!() };
    assert_eq!((*width, *height), (32, 16));
    // glint's equirectangular map has +z at its centre (u = atan2(x, −z)/2π = ½) and
    // −z at its left edge.
    let at = |i: u32, j: u32| texels[(j * width + i) as usize];
    assert!(at(16, 8).min_element() > 0.5, "+z is bright: {}", at(16, 8));
    assert!(at(0, 8).max_element() < 0.01, "−z is dark: {}", at(0, 8));
    assert!(at(16, 0).max_element() < 0.01, "+y is dark: {}", at(16, 0));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn convert_writes_inline_meshes_as_ply_files() {
    let dir = temp_dir("convert");
    std::fs::write(dir.join("box.pbrt"), CORNELL).unwrap();
    let out = dir.join("box.glint");
    let converted = glint_scene::convert::convert(&dir.join("box.pbrt"), &out).unwrap();
    assert_eq!(converted.format, SceneFormat::Pbrt);
    let back = load_any(&out).unwrap().scene;
    let original = scene(CORNELL);
    assert_eq!(back.meshes.len(), original.meshes.len());
    for (a, b) in back.meshes.iter().zip(&original.meshes) {
        assert_eq!((&a.positions, &a.indices), (&b.positions, &b.indices));
    }
    assert!(dir.join("box.meshes/0.ply").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn every_prefix_of_a_scene_is_an_answer_never_a_panic() {
    // Cut anywhere (mid-token, mid-list, mid-block), the text reads as a scene or an
    // error; an accepted scene also compiles.
    let text = format!(
        "{CORNELL}Texture \"t\" \"spectrum\" \"checkerboard\" \"rgb tex1\" [1 0 0]\nShape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]\n"
    );
    for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
        if let Ok(loaded) = parse(&text[..end]) {
            let compiled = glint_core::scene::compile(&loaded.scene);
            assert!(compiled.is_ok(), "prefix of {end} bytes read but does not compile: {:?}", compiled.err());
        }
    }
}

#[test]
fn named_coordinate_systems_and_the_camera_space() {
    // The camera sits at (0, 0, −5) looking along +z: 2 in front of it is (0, 0, −3).
    let s = scene(&format!(
        "{UNMIRRORED}Translate 4 0 0\nCoordinateSystem \"shifted\"\nIdentity\n\
         AttributeBegin\nCoordSysTransform \"camera\"\nTranslate 0 0 2\nShape \"sphere\"\nAttributeEnd\n\
         AttributeBegin\nCoordSysTransform \"shifted\"\nShape \"sphere\"\nAttributeEnd\nShape \"sphere\"\n"
    ));
    let c = centres(&s);
    close(c[0], Vec3::new(0.0, 0.0, -3.0));
    close(c[1], Vec3::new(4.0, 0.0, 0.0));
    close(c[2], Vec3::ZERO);
}

/// Found by fuzzing: a negative cone angle reached `clamp(0, angle)` and panicked.
#[test]
fn a_spot_lights_cone_angle_outside_its_range_is_an_error() {
    for angle in ["-70", "0", "190"] {
        let text = format!("WorldBegin\nLightSource \"spot\" \"float coneangle\" {angle} \"float conedelta\" 5\n");
        assert_error(&text, 2, "must lie in (0, 180]");
    }
}
