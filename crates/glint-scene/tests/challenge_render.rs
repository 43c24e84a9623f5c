//! Ray Tracer Challenge scenes render as the book draws them: each test re-derives the
//! expected pixels with the book's own formulas (its camera's `ray_for_pixel`, its
//! `lighting()`, its patterns) and compares them with glint's render of the YAML scene.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use glam::{Mat4, Vec3};
use glint_core::desc::SceneDesc;
use glint_core::film::Image;
use glint_core::render::render;
use glint_core::scene::compile;
use glint_scene::challenge::parse_challenge;
use glint_scene::parse_scene;

fn load(yaml: &str) -> SceneDesc {
    let (scene, warnings) = parse_challenge(yaml, "test.yml").unwrap_or_else(|e| panic!("scene should load: {e}"));
    assert!(warnings.is_empty(), "unexpected warnings: {warnings:?}");
    scene
}

fn draw(desc: &SceneDesc) -> Image {
    let scene = compile(desc).expect("scene compiles");
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders").0
}

fn pixel(image: &Image, x: u32, y: u32) -> Vec3 {
    image.pixels[(y * image.width + x) as usize]
}

/// The book's camera: `view_transform(from, to, up)` and `ray_for_pixel`.
struct BookCamera {
    world_from_camera: Mat4,
    half_width: f32,
    half_height: f32,
    pixel_size: f32,
}

impl BookCamera {
    fn new(width: u32, height: u32, fov: f32, from: Vec3, to: Vec3, up: Vec3) -> Self {
        let forward = (to - from).normalize();
        // Not normalised, exactly as in the book (its axes shrink when up is oblique).
        let left = forward.cross(up.normalize());
        let true_up = left.cross(forward);
        let orientation =
            Mat4::from_cols(left.extend(0.0), true_up.extend(0.0), (-forward).extend(0.0), glam::Vec4::W).transpose();
        let view = orientation * Mat4::from_translation(-from);
        let half_view = (fov / 2.0).tan();
        let aspect = width as f32 / height as f32;
        let (half_width, half_height) =
            if aspect >= 1.0 { (half_view, half_view / aspect) } else { (half_view * aspect, half_view) };
        Self { world_from_camera: view.inverse(), half_width, half_height, pixel_size: half_width * 2.0 / width as f32 }
    }

    fn ray_for_pixel(&self, px: u32, py: u32) -> (Vec3, Vec3) {
        let x = self.half_width - (px as f32 + 0.5) * self.pixel_size;
        let y = self.half_height - (py as f32 + 0.5) * self.pixel_size;
        let pixel = self.world_from_camera.transform_point3(Vec3::new(x, y, -1.0));
        let origin = self.world_from_camera.transform_point3(Vec3::ZERO);
        (origin, (pixel - origin).normalize())
    }
}

/// The nearest hit of a ray with a sphere, and the margin to its silhouette (how far
/// the ray is from grazing it), so tests can skip pixels on the edge.
fn hit_sphere(origin: Vec3, dir: Vec3, centre: Vec3, radius: f32) -> Option<(f32, f32)> {
    let oc = origin - centre;
    let b = oc.dot(dir);
    let disc = b * b - (oc.length_squared() - radius * radius);
    (disc >= 0.0).then(|| (-b - disc.sqrt(), disc.sqrt()))
}

const CAMERA: &str = "
- add: camera
  width: WIDTH
  height: HEIGHT
  field-of-view: 0.9
  from: [1, 1.5, -5]
  to: [0, 0.5, 0]
  up: [0, 1, 0]
";

fn camera(width: u32, height: u32) -> String {
    CAMERA.replace("WIDTH", &width.to_string()).replace("HEIGHT", &height.to_string())
}

#[test]
fn objects_appear_where_the_books_camera_puts_them() {
    // Landscape and portrait: the book's field of view spans the larger side.
    for (width, height) in [(64, 48), (40, 64)] {
        let yaml = camera(width, height)
            + "
- add: light
  at: [0, 10, -10]
  intensity: [1, 1, 1]
- add: sphere
  material: { color: [1, 1, 1], ambient: 1, diffuse: 0, specular: 0 }
  transform:
    - [scale, 0.6, 0.6, 0.6]
    - [translate, 1.2, 0.9, 0.5]
";
        let image = draw(&load(&yaml));
        let book = BookCamera::new(width, height, 0.9, Vec3::new(1.0, 1.5, -5.0), Vec3::new(0.0, 0.5, 0.0), Vec3::Y);
        let (mut inside, mut wrong) = (0, 0);
        for py in 0..height {
            for px in 0..width {
                let (o, d) = book.ray_for_pixel(px, py);
                let hit = hit_sphere(o, d, Vec3::new(1.2, 0.9, 0.5), 0.6);
                if hit.is_some_and(|(_, margin)| margin < 0.05) {
                    continue; // on the silhouette
                }
                let expected = if hit.is_some() { 1.0 } else { 0.0 };
                inside += hit.is_some() as u32;
                wrong += ((pixel(&image, px, py).x - expected).abs() > 1e-3) as u32;
            }
        }
        assert!(inside > 50, "the sphere should cover some pixels, covers {inside}");
        assert_eq!(wrong, 0, "{width}x{height}: {wrong} pixels differ from the book's camera");
    }
}

#[test]
fn positive_x_is_on_the_right_as_in_the_book() {
    // The book's own check: looking from -z towards +z, +x is on the right.
    let yaml = "
- add: camera
  width: 32
  height: 16
  field-of-view: 1.2
  from: [0, 0, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [0, 0, -5]
  intensity: [1, 1, 1]
- add: sphere
  material: { color: [1, 0, 0], ambient: 1, diffuse: 0, specular: 0 }
  transform: [[scale, 0.5, 0.5, 0.5], [translate, 2, 0, 0]]
- add: sphere
  material: { color: [0, 1, 0], ambient: 1, diffuse: 0, specular: 0 }
  transform: [[scale, 0.5, 0.5, 0.5], [translate, 0, 1, 0]]
";
    let image = draw(&load(yaml));
    let red: Vec<u32> = (0..32).filter(|&x| (0..16).any(|y| pixel(&image, x, y).x > 0.5)).collect();
    let green: Vec<u32> = (0..16).filter(|&y| (0..32).any(|x| pixel(&image, x, y).y > 0.5)).collect();
    assert!(!red.is_empty() && red.iter().all(|&x| x >= 16), "+x must be on the right: columns {red:?}");
    assert!(!green.is_empty() && green.iter().all(|&y| y < 8), "+y must be at the top: rows {green:?}");
}

/// The book's `lighting()` for one point light, not in shadow.
fn book_lighting(color: Vec3, m: [f32; 4], light: (Vec3, Vec3), point: Vec3, eyev: Vec3, normalv: Vec3) -> Vec3 {
    let [ambient, diffuse, specular, shininess] = m;
    let (position, intensity) = light;
    let effective = color * intensity;
    let lightv = (position - point).normalize();
    let mut result = effective * ambient;
    let light_dot_normal = lightv.dot(normalv);
    if light_dot_normal >= 0.0 {
        result += effective * diffuse * light_dot_normal;
        let reflectv = -lightv - 2.0 * (-lightv).dot(normalv) * normalv;
        let reflect_dot_eye = reflectv.dot(eyev);
        if reflect_dot_eye > 0.0 {
            result += intensity * specular * reflect_dot_eye.powf(shininess);
        }
    }
    result
}

#[test]
fn phong_lighting_matches_the_books() {
    let (width, height) = (64, 48);
    let yaml = camera(width, height)
        + "
- add: light
  at: [-4, 6, -6]
  intensity: [0.9, 0.8, 0.7]
- add: sphere
  material:
    color: [0.8, 0.4, 0.2]
    ambient: 0.2
    diffuse: 0.6
    specular: 0.7
    shininess: 30
  transform:
    - [translate, 0, 0.5, 0]
";
    let image = draw(&load(&yaml));
    let book = BookCamera::new(width, height, 0.9, Vec3::new(1.0, 1.5, -5.0), Vec3::new(0.0, 0.5, 0.0), Vec3::Y);
    let centre = Vec3::new(0.0, 0.5, 0.0);
    let light = (Vec3::new(-4.0, 6.0, -6.0), Vec3::new(0.9, 0.8, 0.7));
    let mut checked = 0;
    for py in 0..height {
        for px in 0..width {
            let (o, d) = book.ray_for_pixel(px, py);
            let Some((t, margin)) = hit_sphere(o, d, centre, 1.0) else { continue };
            if margin < 0.05 {
                continue;
            }
            let point = o + t * d;
            let expected = book_lighting(
                Vec3::new(0.8, 0.4, 0.2),
                [0.2, 0.6, 0.7, 30.0],
                light,
                point,
                -d,
                (point - centre).normalize(),
            );
            let got = pixel(&image, px, py);
            assert!((got - expected).abs().max_element() < 2e-3, "pixel {px},{py}: glint {got}, book {expected}");
            checked += 1;
        }
    }
    assert!(checked > 300, "{checked}");
}

/// Renders a top-down view of a patterned plane lit straight from far above, so that
/// each pixel is the pattern's colour, and compares it with `expected(x, z)`.
fn check_plane_pattern(material: &str, expected: impl Fn(f32, f32) -> Option<Vec3>) {
    let (width, height) = (64, 48);
    let yaml = format!(
        "
- add: camera
  width: {width}
  height: {height}
  field-of-view: 1.2
  from: [0.3, 6, -0.2]
  to: [0.3, 0, 0]
  up: [0, 0, 1]
- add: light
  at: [0.3, 100000, 0]
  intensity: [1, 1, 1]
- add: plane
  material:
{material}
    ambient: 0
    diffuse: 1
    specular: 0
"
    );
    let image = draw(&load(&yaml));
    let book = BookCamera::new(width, height, 1.2, Vec3::new(0.3, 6.0, -0.2), Vec3::new(0.3, 0.0, 0.0), Vec3::Z);
    let mut checked = 0;
    for py in 0..height {
        for px in 0..width {
            let (o, d) = book.ray_for_pixel(px, py);
            let p = o - (o.y / d.y) * d;
            let Some(colour) = expected(p.x, p.z) else { continue };
            let got = pixel(&image, px, py);
            assert!(
                (got - colour).abs().max_element() < 2e-3,
                "pixel {px},{py} at ({}, {}): {got} vs {colour}",
                p.x,
                p.z
            );
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked}");
}

/// Whether `x` is within `margin` of a whole number (a cell edge, where the two
/// renderers may round differently).
fn near_edge(x: f32, margin: f32) -> bool {
    (x - x.round()).abs() < margin
}

#[test]
fn solid_checkers_on_a_plane_match_the_books() {
    let (a, b) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.9));
    for (scale, shift) in [(1.0, 0.0), (0.5, 0.0), (0.7, 0.7)] {
        let material = format!(
            "    pattern:
      type: checkers
      colors: [[0.9, 0.1, 0.1], [0.1, 0.1, 0.9]]
      transform:
        - [scale, {scale}, {scale}, {scale}]
        - [translate, {shift}, 0, 0]"
        );
        check_plane_pattern(&material, |x, z| {
            let (u, w) = ((x - shift) / scale, z / scale);
            if near_edge(u, 0.03) || near_edge(w, 0.03) {
                return None;
            }
            // The book: floor(x) + floor(y) + floor(z) even → first colour (y = 0 here).
            Some(if (u.floor() + w.floor()) as i64 % 2 == 0 { a } else { b })
        });
    }
}

#[test]
fn planar_mapped_checkers_match_the_books() {
    let (a, b) = (Vec3::new(0.9, 0.1, 0.1), Vec3::new(0.1, 0.1, 0.9));
    let material = "    pattern:
      type: map
      mapping: planar
      uv_pattern:
        type: checkers
        width: 4
        height: 2
        colors: [[0.9, 0.1, 0.1], [0.1, 0.1, 0.9]]";
    check_plane_pattern(material, |x, z| {
        let (u, v) = (x.rem_euclid(1.0) * 4.0, z.rem_euclid(1.0) * 2.0);
        if near_edge(u, 0.05) || near_edge(v, 0.05) {
            return None;
        }
        Some(if (u.floor() + v.floor()) as i64 % 2 == 0 { a } else { b })
    });
}

#[test]
fn spherical_mapped_checkers_match_the_books() {
    let (width, height) = (64, 64);
    let yaml = "
- add: camera
  width: 64
  height: 64
  field-of-view: 0.6
  from: [2, 3, -5]
  to: [0, 0, 0]
  up: [0, 1, 0]
- add: light
  at: [2, 3, -5]
  intensity: [1, 1, 1]
- add: sphere
  material:
    pattern:
      type: map
      mapping: spherical
      uv_pattern:
        type: checkers
        width: 16
        height: 8
        colors: [[1, 0, 0], [0, 1, 0]]
    ambient: 0
    diffuse: 1
    specular: 0
";
    let image = draw(&load(yaml));
    let book = BookCamera::new(width, height, 0.6, Vec3::new(2.0, 3.0, -5.0), Vec3::ZERO, Vec3::Y);
    let mut checked = 0;
    for py in 0..height {
        for px in 0..width {
            let (o, d) = book.ray_for_pixel(px, py);
            let Some((t, margin)) = hit_sphere(o, d, Vec3::ZERO, 1.0) else { continue };
            if margin < 0.1 {
                continue;
            }
            let (u, v) = glint_scene_book_spherical_map(o + t * d);
            let (cu, cv) = (u * 16.0, v * 8.0);
            if near_edge(cu, 0.1) || near_edge(cv, 0.1) {
                continue;
            }
            let red_expected = (cu.floor() + cv.floor()) as i64 % 2 == 0;
            let got = pixel(&image, px, py);
            assert_eq!(got.x > got.y, red_expected, "pixel {px},{py}: {got}");
            checked += 1;
        }
    }
    assert!(checked > 300, "{checked}");
}

/// The book's `spherical_map`, written out again here so the test does not trust the
/// importer's copy.
fn glint_scene_book_spherical_map(p: Vec3) -> (f32, f32) {
    let theta = p.x.atan2(p.z);
    let phi = (p.y / p.length()).acos();
    let raw_u = theta / std::f32::consts::TAU;
    (1.0 - (raw_u + 0.5), 1.0 - phi / std::f32::consts::PI)
}

#[test]
fn a_yaml_scene_renders_like_the_equivalent_native_scene() {
    let yaml = "
- add: camera
  width: 64
  height: 48
  field-of-view: 1.0471975512
  from: [0, 1.5, -5]
  to: [0, 1, 0]
  up: [0, 1, 0]
- add: light
  at: [-10, 10, -10]
  intensity: [1, 1, 1]
- add: plane
  material: { color: [1, 0.9, 0.9], specular: 0 }
- add: sphere
  material: { color: [0.1, 1, 0.5], diffuse: 0.7, specular: 0.3 }
  transform: [[translate, -0.5, 1, 0.5]]
- add: sphere
  material: { color: [0.5, 1, 0.1], diffuse: 0.7, specular: 0.3, reflective: 0.5 }
  transform: [[scale, 0.5, 0.5, 0.5], [translate, 1.5, 0.5, -0.5]]
";
    // The same scene written by hand in glint's terms: z mirrored, the vertical angle
    // 2·atan(tan(30°)/sin θ · 48/64) (θ between the view direction and up: the book's
    // unnormalised camera axes), L_a = Σ intensities, k_s = 1 with grey O_s and O_r.
    let sine = Vec3::new(0.0, -0.5, 5.0).normalize().cross(Vec3::Y).length();
    let fov = (2.0 * ((std::f32::consts::PI / 6.0).tan() / sine * 0.75).atan()).to_degrees();
    let native = format!(
        "
settings {{ width 64 height 48 background 0 ambient 1 output_transfer \"identity\" }}
camera {{ eye [0 1.5 5] look_at [0 1 0] up [0 1 0] fov {fov} }}
material \"floor\" {{ diffuse [1 0.9 0.9] ka 0.1 kd 0.9 ks 1 specular 0 reflective 0 shininess 200 }}
material \"a\" {{ diffuse [0.1 1 0.5] ka 0.1 kd 0.7 ks 1 specular 0.3 reflective 0 shininess 200 }}
material \"b\" {{ diffuse [0.5 1 0.1] ka 0.1 kd 0.7 ks 1 specular 0.3 reflective 0.5 shininess 200 }}
light point {{ position [-10 10 10] color 1 }}
plane {{ material \"floor\" }}
sphere {{ material \"a\" translate [-0.5 1 -0.5] }}
sphere {{ material \"b\" scale 0.5 translate [1.5 0.5 0.5] }}
"
    );
    let from_yaml = draw(&load(yaml));
    let from_native = draw(&parse_scene(&native, "equivalent.glint", Path::new("")).expect("native parses"));
    let mean = from_yaml.mean_abs_diff(&from_native);
    let worst = from_yaml
        .pixels
        .iter()
        .zip(&from_native.pixels)
        .map(|(a, b)| (*a - *b).abs().max_element())
        .fold(0.0, f32::max);
    assert!(mean < 1e-3 && worst < 0.05, "mean difference {mean}, worst {worst}");
}
