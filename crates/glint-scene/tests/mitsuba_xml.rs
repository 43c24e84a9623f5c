//! Mitsuba 3 XML scenes: every value kind, defaults, transforms, the camera, shapes,
//! BSDFs, textures and emitters read into a `SceneDesc` with Mitsuba's meaning, and
//! unsupported input refused at its file and line.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{
    BsdfDesc, FilterKind, IntegratorDesc, LightDesc, NodeKind, PathDesc, SamplerKind, SceneDesc, ShapeDesc,
    TextureDesc, TransformOp, matrix_of,
};
use glint_scene::mitsuba::parse_mitsuba;
use glint_scene::{SceneError, SceneFormat, load_any};

const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="45"/></sensor>"#;

/// Parses `body` inside a version 3 `<scene>` (line 1), with a camera when it has none.
fn parse(body: &str) -> Result<SceneDesc, SceneError> {
    let sensor = if body.contains("<sensor") { "" } else { SENSOR };
    let text = format!("<scene version=\"3.0.0\">\n{body}\n{sensor}\n</scene>");
    parse_mitsuba(&text, "scene.xml", Path::new(".")).map(|l| l.scene)
}

#[track_caller]
fn scene(body: &str) -> SceneDesc {
    parse(body).unwrap_or_else(|e| panic!("{e}"))
}

/// Asserts an error in scene.xml at `line` whose message contains `fragment`.
#[track_caller]
fn assert_error(body: &str, line: u32, fragment: &str) -> SceneError {
    let e = match parse(body) {
        Ok(_) => panic!("expected an error mentioning {fragment:?}"),
        Err(e) => e,
    };
    assert_eq!((e.file.as_str(), e.line()), ("scene.xml", line), "wrong place for: {e}");
    assert!(e.message.contains(fragment), "message {:?} lacks {fragment:?}", e.message);
    e
}

#[track_caller]
fn close(a: Vec3, b: Vec3) {
    assert!(a.abs_diff_eq(b, 1e-4), "{a} ≠ {b}");
}

fn shape_of(s: &SceneDesc, i: usize) -> (ShapeDesc, usize, Mat4) {
    match &s.objects[i].kind {
        NodeKind::Shape { shape, material } => (*shape, *material, matrix_of(&s.objects[i].transform)),
        other => panic!("{other:?}"),
    }
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("glint-mitsuba-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn every_value_kind_and_default_substitution() {
    let s = scene(
        r#"<default name="spp" value="16"/>
        <default name="red" value="0.25"/>
        <default name="dist" value="ggx"/>
        <sensor type="perspective">
            <float name="fov" value="45"/>
            <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        </sensor>
        <shape type="sphere">
            <point name="center" x="1" y="2" z="3"/>
            <float name="radius" value="0.5"/>
            <bsdf type="roughplastic">
                <rgb name="diffuse_reflectance" value="$red, 0.5, 1"/>
                <string name="distribution" value="$dist"/>
                <boolean name="nonlinear" value="true"/>
                <spectrum name="specular_reflectance" value="0.75"/>
            </bsdf>
        </shape>
        <emitter type="directional">
            <vector name="direction" value="0 -1 0"/>
            <spectrum name="irradiance" value="2"/>
        </emitter>"#,
    );
    assert_eq!(s.settings.spp, Some(16));
    let (shape, m, world) = shape_of(&s, 0);
    assert_eq!(shape, ShapeDesc::Sphere);
    close(world.transform_point3(Vec3::ZERO), Vec3::new(1.0, 2.0, 3.0));
    close(world.transform_point3(Vec3::X), Vec3::new(1.5, 2.0, 3.0));
    match s.materials[m].bsdf {
        Some(BsdfDesc::Plastic { diffuse, specular, nonlinear, alpha, int_ior, .. }) => {
            assert_eq!(diffuse.value, Vec3::new(0.25, 0.5, 1.0));
            assert_eq!(specular, Vec3::splat(0.75));
            assert!(nonlinear);
            assert_eq!(alpha.value, 0.1);
            assert_eq!(int_ior, 1.49);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(s.materials[m].diffuse, Vec3::new(0.25, 0.5, 1.0));
    assert!(!s.materials[m].two_sided);
    assert_eq!(s.lights, vec![LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::splat(2.0) }]);
}

#[test]
fn a_missing_default_and_a_wavelength_spectrum_are_errors_at_their_line() {
    assert_error("<shape type=\"sphere\">\n<float name=\"radius\" value=\"$r\"/></shape>", 3, "'$r'");
    assert_error(
        "<shape type=\"sphere\"><emitter type=\"area\">\n<spectrum name=\"radiance\" value=\"400:1, 700:2\"/>\
         </emitter></shape>",
        3,
        "wavelength",
    );
}

#[test]
fn lookat_camera_gives_eye_look_and_up() {
    let s = scene(
        r#"<sensor type="perspective">
            <transform name="to_world"><lookat origin="1, 2, 3" target="1, 2, 0" up="0, 1, 0"/></transform>
            <float name="fov" value="40"/><string name="fov_axis" value="y"/>
        </sensor>"#,
    );
    close(s.camera.eye, Vec3::new(1.0, 2.0, 3.0));
    close(s.camera.look.normalize(), Vec3::NEG_Z);
    close(s.camera.up.normalize(), Vec3::Y);
    assert!((s.camera.fov_y_degrees - 40.0).abs() < 1e-4);
    // Mitsuba's local +x (the image's left) is up × look; glint's right is up × (−look).
    let mitsuba_left = s.camera.up.cross(s.camera.look).normalize();
    close(mitsuba_left, Vec3::NEG_X);
    assert_eq!((s.settings.width, s.settings.height), (768, 576));
}

#[test]
fn transforms_apply_in_document_order() {
    let s = scene(
        r#"<shape type="cube"><transform name="to_world">
            <scale x="2"/><rotate y="1" angle="90"/><translate value="0 0 5"/>
        </transform></shape>
        <sensor type="perspective">
            <transform name="to_world"><rotate axis="0 1 0" angle="180"/><translate x="0" y="1" z="4"/></transform>
        </sensor>"#,
    );
    let (_, _, m) = shape_of(&s, 0);
    // (1,0,0) → scaled (2,0,0) → turned about +y to (0,0,−2) → moved to (0,0,3).
    close(m.transform_point3(Vec3::X), Vec3::new(0.0, 0.0, 3.0));
    close(m.transform_point3(Vec3::Y), Vec3::new(0.0, 1.0, 5.0));
    close(s.camera.eye, Vec3::new(0.0, 1.0, 4.0));
    close(s.camera.look, Vec3::NEG_Z);
    close(s.camera.up, Vec3::Y);
}

#[test]
fn matrix_is_row_major() {
    let s = scene(
        r#"<shape type="cube"><transform name="to_world">
            <matrix value="1 0 0 7  0 1 0 8  0 0 1 9  0 0 0 1"/>
        </transform></shape>"#,
    );
    close(shape_of(&s, 0).2.transform_point3(Vec3::ZERO), Vec3::new(7.0, 8.0, 9.0));
}

fn fov_y(axis: &str, fov: f32) -> f32 {
    let s = scene(&format!(
        r#"<sensor type="perspective"><float name="fov" value="{fov}"/><string name="fov_axis" value="{axis}"/>
            <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>
        </sensor>"#
    ));
    // The vertical angle the camera has at this image size.
    let tan_y = s.camera.fov_axis.tan_half_vertical(s.camera.fov_y_degrees, 2.0);
    2.0 * tan_y.atan().to_degrees()
}

#[test]
fn fov_axis_survives_a_change_of_image_size() {
    let s = scene(
        r#"<sensor type="perspective"><float name="fov" value="90"/><string name="fov_axis" value="x"/>
            <film type="hdrfilm"><integer name="width" value="200"/><integer name="height" value="100"/></film>
        </sensor>"#,
    );
    assert_eq!((s.camera.fov_y_degrees, s.camera.fov_axis), (90.0, glint_core::desc::FovAxis::X));
    // Made square (--width 100), the horizontal angle is still 90°: so is the vertical.
    assert!((s.camera.fov_axis.tan_half_vertical(90.0, 1.0) - 1.0).abs() < 1e-6);
}

#[test]
fn fov_axes_convert_to_the_vertical_angle() {
    let tan_half = |d: f32| (0.5 * d.to_radians()).tan();
    let from_tan = |t: f32| 2.0 * t.atan().to_degrees();
    // Aspect 2: the vertical half-angle tangent is half the horizontal one.
    assert!((fov_y("x", 90.0) - from_tan(0.5)).abs() < 1e-3);
    assert!((fov_y("y", 60.0) - 60.0).abs() < 1e-3);
    assert!((fov_y("smaller", 60.0) - 60.0).abs() < 1e-3);
    assert!((fov_y("larger", 90.0) - from_tan(0.5)).abs() < 1e-3);
    // Diagonal: tan(half) spreads over sqrt(2² + 1²) in the ratio of the sides.
    let expected = from_tan(tan_half(70.0) / 5f32.sqrt());
    assert!((fov_y("diagonal", 70.0) - expected).abs() < 1e-3);
}

#[test]
fn a_mirroring_camera_is_an_error_at_its_line() {
    assert_error(
        "<sensor type=\"perspective\">\n<transform name=\"to_world\"><scale x=\"-1\"/></transform>\n</sensor>",
        3,
        "mirror",
    );
}

#[test]
fn rectangle_and_disk_normals_map_onto_mitsubas_plus_z() {
    let s = scene(
        r#"<shape type="rectangle"/>
        <shape type="disk"><transform name="to_world"><rotate x="1" angle="-90"/></transform></shape>
        <shape type="rectangle"><boolean name="flip_normals" value="true"/></shape>"#,
    );
    let normal = |m: Mat4| m.inverse().transpose().transform_vector3(Vec3::Y).normalize();
    let (shape, _, m) = shape_of(&s, 0);
    assert_eq!(shape, ShapeDesc::Rectangle);
    close(normal(m), Vec3::Z);
    // The square [−1, 1]² stays in z = 0 with Mitsuba's uv: glint's (x, 0, z) → (x, −z, 0).
    close(m.transform_point3(Vec3::new(1.0, 0.0, 1.0)), Vec3::new(1.0, -1.0, 0.0));
    let (shape, _, m) = shape_of(&s, 1);
    assert_eq!(shape, ShapeDesc::Disk);
    // Mitsuba's +z normal turned by −90° about x points along +y.
    close(normal(m), Vec3::Y);
    close(normal(shape_of(&s, 2).2), Vec3::NEG_Z);
    // The mirrored (flipped) rectangle is a valid placement for the scene compiler.
    glint_core::scene::compile(&s).unwrap();
}

#[test]
fn a_scene_without_a_sensor_is_refused() {
    let e = parse_mitsuba("<scene version=\"3.0.0\">\n</scene>", "scene.xml", Path::new(".")).unwrap_err();
    assert!(e.message.contains("no <sensor>"), "{e}");
    let e = parse_mitsuba("<scene>\n</scene>", "scene.xml", Path::new(".")).unwrap_err();
    assert!(e.message.contains("'version'"), "{e}");
}

#[test]
fn conductors_by_name_and_by_eta_k() {
    let s = scene(
        r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="Au"/></bsdf></shape>
        <shape type="sphere"><bsdf type="roughconductor">
            <rgb name="eta" value="0.2 0.9 1.1"/><rgb name="k" value="3.9 2.4 2.1"/>
            <float name="alpha" value="0.3"/><string name="distribution" value="ggx"/>
        </bsdf></shape>
        <shape type="sphere"><bsdf type="conductor"/></shape>"#,
    );
    let bsdf = |i: usize| s.materials[shape_of(&s, i).1].bsdf;
    match bsdf(0) {
        Some(BsdfDesc::Conductor { eta, k, alpha, specular }) => {
            assert!(eta.x < 0.2 && eta.z > 1.4 && k.x > 3.9, "gold: {eta} {k}");
            assert_eq!(alpha.value, 0.0);
            assert_eq!(specular.value, Vec3::ONE);
        }
        other => panic!("{other:?}"),
    }
    match bsdf(1) {
        Some(BsdfDesc::Conductor { eta, k, alpha, .. }) => {
            assert_eq!((eta, k), (Vec3::new(0.2, 0.9, 1.1), Vec3::new(3.9, 2.4, 2.1)));
            assert_eq!(alpha.value, 0.3);
        }
        other => panic!("{other:?}"),
    }
    // Mitsuba's default material "none" is a perfect mirror.
    assert!(matches!(bsdf(2), Some(BsdfDesc::Conductor { eta: Vec3::ZERO, k: Vec3::ONE, .. })));
    let gold = s.materials[shape_of(&s, 0).1].diffuse;
    assert!(gold.x > gold.z, "gold looks yellow in the Whitted preview: {gold}");
    assert_error(
        "<shape type=\"sphere\">\n<bsdf type=\"conductor\"><string name=\"material\" value=\"Xx\"/></bsdf></shape>",
        3,
        "unknown conductor 'Xx'",
    );
}

#[test]
fn named_and_numeric_indices_of_refraction() {
    let s = scene(
        r#"<shape type="sphere"><bsdf type="dielectric">
            <string name="int_ior" value="water"/><string name="ext_ior" value="air"/>
        </bsdf></shape>
        <shape type="sphere"><bsdf type="thindielectric"><float name="int_ior" value="1.7"/></bsdf></shape>
        <shape type="sphere"><bsdf type="dielectric"/></shape>
        <shape type="sphere"><bsdf type="roughdielectric">
            <string name="int_ior" value="diamond"/><string name="distribution" value="ggx"/>
        </bsdf></shape>"#,
    );
    let m = |i: usize| &s.materials[shape_of(&s, i).1];
    assert!(matches!(m(0).bsdf, Some(BsdfDesc::Dielectric { int_ior: 1.333, ext_ior: 1.000_277, .. })));
    assert!(matches!(m(1).bsdf, Some(BsdfDesc::ThinDielectric { int_ior: 1.7, ext_ior: 1.000_277, .. })));
    assert!(matches!(m(2).bsdf, Some(BsdfDesc::Dielectric { int_ior: 1.5046, .. })));
    match m(3).bsdf {
        Some(BsdfDesc::Dielectric { int_ior, alpha, .. }) => assert_eq!((int_ior, alpha.value), (2.419, 0.1)),
        other => panic!("{other:?}"),
    }
    assert!((0..4).all(|i| m(i).two_sided), "dielectrics are two-sided");
    assert_error(
        "<shape type=\"sphere\"><bsdf type=\"dielectric\">\n<string name=\"int_ior\" value=\"unobtanium\"/></bsdf></shape>",
        3,
        "unknown material",
    );
}

#[test]
fn twosided_wraps_and_references_share_one_material() {
    let s = scene(
        r#"<bsdf type="twosided" id="paper"><bsdf type="diffuse"><rgb name="reflectance" value="0.1 0.2 0.3"/></bsdf></bsdf>
        <shape type="cube"><ref id="paper"/></shape>
        <shape type="cube"><ref name="bsdf" id="paper"/></shape>
        <shape type="cube"/>"#,
    );
    let (a, b, c) = (shape_of(&s, 0).1, shape_of(&s, 1).1, shape_of(&s, 2).1);
    assert_eq!(a, b);
    assert!(s.materials[a].two_sided);
    assert!(
        matches!(s.materials[a].bsdf, Some(BsdfDesc::Diffuse { reflectance }) if reflectance.value == Vec3::new(0.1, 0.2, 0.3))
    );
    // No BSDF: Mitsuba's default, one-sided grey diffuse.
    assert!(!s.materials[c].two_sided);
    assert!(
        matches!(s.materials[c].bsdf, Some(BsdfDesc::Diffuse { reflectance }) if reflectance.value == Vec3::splat(0.5))
    );
}

#[test]
fn an_area_emitter_makes_the_shape_emissive() {
    let s = scene(
        r#"<bsdf type="diffuse" id="white"/>
        <shape type="rectangle"><ref id="white"/><emitter type="area"><rgb name="radiance" value="10 9 8"/></emitter></shape>
        <shape type="rectangle"><ref id="white"/></shape>"#,
    );
    let (lamp, wall) = (shape_of(&s, 0).1, shape_of(&s, 1).1);
    assert_ne!(lamp, wall);
    assert_eq!(s.materials[lamp].emission, Vec3::new(10.0, 9.0, 8.0));
    assert_eq!(s.materials[wall].emission, Vec3::ZERO);
    assert_eq!(s.materials[lamp].bsdf, s.materials[wall].bsdf);
}

#[test]
fn lights_and_the_constant_environment() {
    let s = scene(
        r#"<emitter type="point"><point name="position" value="1 2 3"/><rgb name="intensity" value="5"/></emitter>
        <emitter type="spot">
            <transform name="to_world"><lookat origin="0 4 0" target="0 0 0" up="0 0 1"/></transform>
            <float name="cutoff_angle" value="40"/>
        </emitter>
        <emitter type="constant"><rgb name="radiance" value="0.5"/></emitter>"#,
    );
    assert_eq!(
        s.lights[0],
        LightDesc::Point { position: Vec3::new(1.0, 2.0, 3.0), color: Vec3::splat(5.0), attenuation: Vec3::Z }
    );
    match s.lights[1] {
        LightDesc::Spot { position, direction, angle_degrees, penumbra_degrees, attenuation, falloff, .. } => {
            close(position, Vec3::new(0.0, 4.0, 0.0));
            close(direction, Vec3::NEG_Y);
            assert_eq!((angle_degrees, penumbra_degrees, attenuation), (40.0, 10.0, Vec3::Z));
            // Mitsuba fades linearly in angle across the penumbra.
            assert_eq!(falloff, glint_core::desc::SpotFalloff::Linear);
        }
        ref other => panic!("{other:?}"),
    }
    assert!(matches!(&s.lights[2], LightDesc::Environment(e) if e.radiance == Vec3::splat(0.5) && e.texture.is_none()));
}

#[test]
fn envmap_exr_keeps_values_above_one() {
    let dir = temp_dir("envmap");
    let exr = dir.join("sky.exr");
    image::Rgb32FImage::from_raw(2, 1, vec![5.0, 2.5, 0.5, 0.25, 0.5, 40.0]).unwrap().save(&exr).unwrap();
    let text = r#"<scene version="3.0.0">
        <emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="2"/>
            <transform name="to_world"><rotate y="1" angle="90"/></transform></emitter>
        <sensor type="perspective"/>
    </scene>"#;
    let s = parse_mitsuba(text, "env.xml", &dir).unwrap().scene;
    let LightDesc::Environment(env) = &s.lights[0] else { panic!("{:?}", s.lights) };
    assert_eq!(env.radiance, Vec3::splat(2.0));
    assert_eq!(env.transform, vec![TransformOp::Rotate { axis: Vec3::Y, degrees: 90.0 }]);
    match &s.textures[env.texture.unwrap()] {
        TextureDesc::Image { width: 2, height: 1, texels, .. } => {
            assert_eq!(texels, &vec![Vec3::new(5.0, 2.5, 0.5), Vec3::new(0.25, 0.5, 40.0)]);
        }
        other => panic!("{other:?}"),
    }
    // Radiance RGBE (.hdr) files load linear too.
    image::Rgb32FImage::from_raw(1, 1, vec![8.0, 1.0, 0.5]).unwrap().save(dir.join("sky.hdr")).unwrap();
    let text = text.replace("sky.exr", "sky.hdr");
    let s = parse_mitsuba(&text, "env.xml", &dir).unwrap().scene;
    match &s.textures[0] {
        TextureDesc::Image { texels, .. } => close(texels[0], Vec3::new(8.0, 1.0, 0.5)),
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mesh_files_load_with_mitsubas_uv_and_load_any_knows_the_format() {
    let dir = temp_dir("mesh");
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n").unwrap();
    image::RgbImage::from_raw(1, 2, vec![255, 0, 0, 0, 0, 255]).unwrap().save(dir.join("tex.png")).unwrap();
    let xml = dir.join("scene.xml");
    std::fs::write(
        &xml,
        r#"<?xml version="1.0"?>
<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="8"/></integrator>
    <sensor type="perspective"><sampler type="stratified"/>
        <film type="hdrfilm"><rfilter type="box"/></film></sensor>
    <shape type="obj"><string name="filename" value="tri.obj"/><boolean name="flip_normals" value="true"/>
        <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="tex.png"/>
            <transform name="to_uv"><scale x="2"/></transform></texture></bsdf>
    </shape>
    <shape type="cylinder"><float name="radius" value="0.5"/></shape>
</scene>"#,
    )
    .unwrap();
    let loaded = load_any(&xml).unwrap();
    assert_eq!(loaded.format, SceneFormat::Mitsuba);
    let s = loaded.scene;
    assert_eq!(
        s.settings.integrator,
        IntegratorDesc::Path(PathDesc { max_depth: 8, rr_depth: 5, sampler: SamplerKind::Sobol })
    );
    assert_eq!(s.settings.filter.kind, FilterKind::Box);
    let (ShapeDesc::Mesh { index }, m, _) = shape_of(&s, 0) else { panic!() };
    let mesh = &s.meshes[index];
    // flip_tex_coords (on by default) turns v around; flip_normals the winding.
    assert_eq!(mesh.uvs, vec![Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.0, 0.0)]);
    assert_eq!(mesh.indices, vec![0, 2, 1]);
    // The 1×2 image (red over blue) tiled twice across u and stored upside down.
    let Some(BsdfDesc::Diffuse { reflectance }) = s.materials[m].bsdf else { panic!() };
    match &s.textures[reflectance.texture.unwrap()] {
        TextureDesc::Image { width: 2, height: 2, texels, .. } => {
            assert_eq!(texels[0], Vec3::Z);
            assert_eq!(texels[1], Vec3::Z);
            assert_eq!(texels[2], Vec3::X);
        }
        other => panic!("{other:?}"),
    }
    // The open cylinder is a tube of radius 0.5 from z = 0 to z = 1, normals outwards.
    let (ShapeDesc::Mesh { index }, _, _) = shape_of(&s, 1) else { panic!() };
    let tube = &s.meshes[index];
    for (p, n) in tube.positions.iter().zip(&tube.normals) {
        assert!((p.truncate().length() - 0.5).abs() < 1e-5 && (p.z == 0.0 || p.z == 1.0));
        close(*n, (p.truncate() / 0.5).extend(0.0));
    }
    let [a, b, c] = [0, 1, 2].map(|k| tube.positions[tube.indices[k] as usize]);
    assert!((b - a).cross(c - a).dot(tube.normals[tube.indices[0] as usize]) > 0.0, "counter-clockwise from outside");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn checkerboard_cells_and_offsets() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
            <rgb name="color0" value="1 0 0"/><rgb name="color1" value="0 0 1"/>
            <transform name="to_uv"><scale value="3"/><translate x="0.5"/></transform>
        </texture></bsdf></shape>"#,
    );
    match &s.textures[0] {
        TextureDesc::Checker { even, odd, cells, .. } => {
            assert_eq!((*even, *odd, *cells), (Vec3::Z, Vec3::X, Vec2::splat(6.0)));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn integrator_and_film_defaults_follow_mitsuba() {
    let s = scene("");
    assert_eq!(
        s.settings.integrator,
        IntegratorDesc::Path(PathDesc { max_depth: u32::MAX, rr_depth: 5, sampler: SamplerKind::Independent })
    );
    assert_eq!(s.settings.spp, Some(4));
    assert_eq!((s.settings.filter.kind, s.settings.filter.radius), (FilterKind::Gaussian, 1.5));
    let s = scene(
        r#"<integrator type="path"><integer name="max_depth" value="-1"/><integer name="rr_depth" value="3"/></integrator>
        <sensor type="perspective"><film type="hdrfilm"><rfilter type="gaussian"><float name="stddev" value="0.25"/></rfilter>
        </film></sensor>"#,
    );
    assert!(matches!(s.settings.integrator, IntegratorDesc::Path(PathDesc { max_depth: u32::MAX, rr_depth: 3, .. })));
    assert_eq!(s.settings.filter.radius, 0.75);
    assert_error("\n<integrator type=\"volpath\"/>", 3, "integrator 'volpath'");
}

#[test]
fn rough_plugins_take_mitsubas_distribution_beckmann_by_default() {
    use glint_core::desc::MicrofacetKind;
    for (bsdf, want) in [
        ("<bsdf type=\"roughplastic\"/>", MicrofacetKind::Beckmann),
        (
            "<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"beckmann\"/></bsdf>",
            MicrofacetKind::Beckmann,
        ),
        ("<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/></bsdf>", MicrofacetKind::Ggx),
        ("<bsdf type=\"twosided\"><bsdf type=\"roughconductor\"/></bsdf>", MicrofacetKind::Beckmann),
    ] {
        let s = scene(&format!("<shape type=\"sphere\">{bsdf}</shape>"));
        assert_eq!(s.materials.last().unwrap().microfacet, want, "{bsdf}");
    }
}

#[test]
fn unsupported_input_is_refused_at_its_line() {
    assert_error("<shape type=\"sphere\">\n<bsdf type=\"blendbsdf\"/></shape>", 3, "BSDF type 'blendbsdf'");
    assert_error(
        "<shape type=\"sphere\">\n<bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"phong\"/></bsdf></shape>",
        3,
        "'phong' is not a microfacet distribution",
    );
    assert_error(
        "\n<shape type=\"obj\"><string name=\"filename\" value=\"no-such-mesh.obj\"/></shape>",
        3,
        "no-such-mesh.obj",
    );
    assert_error("\n\n<shape type=\"sphere\"><float name=\"weird\" value=\"1\"/></shape>", 4, "parameter 'weird'");
    assert_error("\n<emitter type=\"sunsky\"/>", 3, "emitter type 'sunsky'");
    assert_error(
        "\n<shape type=\"sphere\"><bsdf type=\"roughconductor\"><string name=\"distribution\" value=\"ggx\"/>\
         <float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf></shape>",
        3,
        "anisotropic",
    );
    assert_error(
        "\n<shape type=\"rectangle\"><bsdf type=\"diffuse\"><rgb name=\"reflectance\" value=\"#ff0000\"/></bsdf></shape>",
        3,
        "not a number",
    );
}

#[test]
fn includes_splice_in_another_files_objects() {
    let dir = temp_dir("include");
    std::fs::write(dir.join("part.xml"), "<scene version=\"3.0.0\">\n<shape type=\"cube\"/>\n</scene>").unwrap();
    let text = "<scene version=\"3.0.0\"><include filename=\"part.xml\"/><sensor type=\"perspective\"/></scene>";
    let s = parse_mitsuba(text, "main.xml", &dir).unwrap().scene;
    assert_eq!(shape_of(&s, 0).0, ShapeDesc::Cube);
    assert!(s.objects[0].origin.ends_with("part.xml:2:1"), "{}", s.objects[0].origin);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_rendered_image_is_not_mirrored() {
    // Mitsuba shows world +x on the image's right for this look-at; so must glint.
    let mut s = scene(
        r#"<sensor type="perspective"><float name="fov" value="60"/>
            <transform name="to_world"><lookat origin="0 0 5" target="0 0 0" up="0 1 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="16"/></film>
        </sensor>
        <emitter type="point"><point name="position" value="0 0 5"/><rgb name="intensity" value="25"/></emitter>
        <shape type="sphere"><point name="center" value="1.5 0 0"/><float name="radius" value="0.6"/>
            <bsdf type="diffuse"><rgb name="reflectance" value="1 0 0"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.6"/><translate x="-1.5"/></transform>
            <bsdf type="diffuse"><rgb name="reflectance" value="0 0 1"/></bsdf></shape>"#,
    );
    s.settings.integrator = IntegratorDesc::Whitted;
    s.settings.spp = None;
    let compiled = glint_core::scene::compile(&s).unwrap();
    let (image, _) =
        glint_core::render::render(&compiled, &|_, _| {}, &std::sync::atomic::AtomicBool::new(false)).unwrap();
    let (right, left) = (image.get(24, 8), image.get(7, 8));
    assert!(right.x > 0.1 && right.z < 0.01, "right side shows the red sphere: {right}");
    // The rectangle faces +z, towards the camera, and is lit.
    assert!(left.z > 0.1 && left.x < 0.01, "left side shows the blue rectangle: {left}");
}

#[test]
fn a_normalmap_bsdf_gives_its_nested_bsdf_a_normal_map() {
    let dir = temp_dir("normalmap");
    image::RgbImage::from_raw(1, 1, vec![128, 128, 255]).unwrap().save(dir.join("n.png")).unwrap();
    let xml = dir.join("scene.xml");
    std::fs::write(
        &xml,
        r#"<scene version="3.0.0">
    <sensor type="perspective"/>
    <shape type="sphere">
        <bsdf type="normalmap">
            <texture name="normalmap" type="bitmap"><boolean name="raw" value="true"/><string name="filename" value="n.png"/></texture>
            <bsdf type="roughplastic"><rgb name="diffuse_reflectance" value="0.2, 0.4, 0.6"/></bsdf>
        </bsdf>
    </shape>
</scene>"#,
    )
    .unwrap();
    let s = load_any(&xml).unwrap().scene;
    let (_, m, _) = shape_of(&s, 0);
    assert!(matches!(s.materials[m].bsdf, Some(BsdfDesc::Plastic { .. })));
    let map = s.materials[m].normal_map.expect("a normal map");
    let TextureDesc::Image { texels, .. } = &s.textures[map.texture] else { panic!() };
    close(texels[0], Vec3::new(128.0, 128.0, 255.0) / 255.0);
    assert_error(
        r#"<shape type="sphere"><bsdf type="normalmap"><bsdf type="diffuse"/></bsdf></shape>"#,
        2,
        "normalmap",
    );
}

#[test]
fn principled_reads_as_the_metallic_roughness_bsdf_and_names_the_lobes_it_leaves_out() {
    let s = scene(
        r#"<shape type="sphere"><bsdf type="principled">
    <rgb name="base_color" value="0.8, 0.2, 0.1"/>
    <float name="metallic" value="0.3"/>
    <float name="roughness" value="0.4"/>
    <float name="specular" value="0.5"/>
    <float name="main_specular_sampling_rate" value="2"/>
</bsdf></shape>"#,
    );
    let Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, ior }) = s.materials[0].bsdf else {
        panic!("{:?}", s.materials[0].bsdf)
    };
    close(base.value, Vec3::new(0.8, 0.2, 0.1));
    assert_eq!(metallic.value, 0.3);
    assert!((alpha.value - 0.16).abs() < 1e-6, "alpha = roughness²: {}", alpha.value);
    assert!((ior - 1.5).abs() < 1e-3, "specular 0.5 is F0 = 4 %, an index of 1.5: {ior}");
    // Defaults: grey, plastic, roughness 0.5; an explicit eta wins over specular.
    let s = scene(r#"<shape type="sphere"><bsdf type="principled"><float name="eta" value="1.33"/></bsdf></shape>"#);
    let Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, ior }) = s.materials[0].bsdf else { panic!() };
    assert_eq!((base.value, metallic.value, alpha.value, ior), (Vec3::splat(0.5), 0.0, 0.25, 1.33));
    // Lobes glint lacks are left out with one warning naming them.
    let loaded = parse_mitsuba(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"/><shape type=\"sphere\"><bsdf type=\"principled\">\
         <float name=\"clearcoat\" value=\"1\"/><float name=\"sheen\" value=\"0.5\"/><float name=\"clearcoat_gloss\" value=\"0.9\"/>\
         </bsdf></shape></scene>",
        "scene.xml",
        Path::new("."),
    )
    .unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].contains("sheen 0.5, clearcoat 1 left out"), "{:?}", loaded.warnings);
}

#[test]
fn a_principled_roughness_texture_is_squared_into_the_alpha() {
    let s = scene(
        r#"<shape type="rectangle"><bsdf type="principled">
    <texture type="checkerboard" name="roughness"><rgb name="color0" value="0.5"/><rgb name="color1" value="1"/></texture>
</bsdf></shape>"#,
    );
    let Some(BsdfDesc::MetallicRoughness { alpha, .. }) = s.materials[0].bsdf else { panic!() };
    let TextureDesc::Checker { even, odd, .. } = &s.textures[alpha.texture.expect("textured")] else { panic!() };
    close(*even, Vec3::splat(0.25));
    close(*odd, Vec3::ONE);
}
