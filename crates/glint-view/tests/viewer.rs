//! The viewer's state machine without a window: camera inputs, toggles, the pass
//! schedule, accumulation against `glint render`'s image, explain, reload and save.

use glam::{Vec2, Vec3};
use glint_core::desc::{SamplePattern, SceneDesc};
use glint_core::film::Image;
use glint_core::integrator::observe::RayKind;
use glint_core::math::Ray;
use glint_core::render::render;
use glint_core::scene::compile;
use glint_view::draw::project;
use glint_view::pass::PassKind;
use glint_view::viewer::{Input, Toggle, ViewMode, Viewer};
use std::sync::atomic::AtomicBool;

const SIZE: (u32, u32) = (96, 64);

fn default_viewer() -> Viewer {
    Viewer::new(glint_scene::default_scene(), Some(SIZE)).expect("the default scene compiles")
}

/// What `glint render` writes for the default scene at SIZE with `samples`² samples of `pattern`.
fn rendered(samples: u32, pattern: SamplePattern) -> Image {
    let mut desc: SceneDesc = glint_scene::default_scene();
    (desc.settings.width, desc.settings.height) = SIZE;
    // As `glint render --samples N`: a count asked for replaces the scene's adaptive sampling.
    (desc.settings.samples_per_axis, desc.settings.adaptive) = (samples, None);
    desc.settings.pattern = pattern;
    let scene = compile(&desc).unwrap();
    render(&scene, &|_, _| {}, &AtomicBool::new(false)).unwrap().0
}

fn run_passes(viewer: &mut Viewer, passes: u32) {
    while viewer.passes() < passes {
        assert!(viewer.step(), "the schedule stopped at {} passes", viewer.passes());
    }
}

#[test]
fn dragging_half_the_height_sideways_turns_the_eye_a_quarter_circle_about_the_target() {
    let mut viewer = default_viewer();
    let before = viewer.camera().clone();
    viewer.handle(Input::Orbit { dx: SIZE.1 as f32 / 2.0, dy: 0.0 });
    let after = viewer.camera();
    assert_eq!(after.target, before.target);
    assert!((after.distance() - before.distance()).abs() < 1e-3);
    let (a, b) = (before.eye - before.target, after.eye - after.target);
    // Dragging right carries the scene right: the eye goes round to the left, a
    // quarter turn about the vertical.
    let turn = Vec2::new(a.x, a.z).angle_to(Vec2::new(b.x, b.z));
    assert!((turn.abs() - std::f32::consts::FRAC_PI_2).abs() < 1e-3, "turned {turn}");
    assert!(b.dot(before.right()) < 0.0, "the eye should move to the left");
    assert!((a.y - b.y).abs() < 1e-3);
}

#[test]
fn reset_restores_the_scene_camera_after_orbit_pan_zoom_fly_and_fov() {
    let mut viewer = default_viewer();
    let home = viewer.camera().clone();
    for input in [
        Input::Orbit { dx: 10.0, dy: 5.0 },
        Input::Pan { dx: 3.0, dy: -2.0 },
        Input::Zoom(2.0),
        Input::Fly { direction: Vec3::Z, seconds: 0.1 },
        Input::Fov(10.0),
    ] {
        let before = viewer.camera().clone();
        viewer.handle(input);
        assert_ne!(*viewer.camera(), before, "{input:?} left the camera where it was");
    }
    viewer.handle(Input::Reset);
    assert_eq!(*viewer.camera(), home);
}

#[test]
fn toggles_change_the_settings_each_pass_renders_with() {
    let mut viewer = default_viewer();
    let before = viewer.pass_settings(PassKind::Sample(0));
    assert!(before.features.shadows && before.features.reflections && before.features.refractions);
    for toggle in [Toggle::Shadows, Toggle::Reflections, Toggle::Refractions, Toggle::Integrator, Toggle::AntiAliasing]
    {
        viewer.handle(Input::Toggle(toggle));
    }
    viewer.handle(Input::MaxDepth(-2));
    let after = viewer.pass_settings(PassKind::Sample(0));
    assert!(!after.features.shadows && !after.features.reflections && !after.features.refractions);
    assert!(matches!(after.integrator, glint_core::desc::IntegratorDesc::Path(p) if p.max_depth == before.max_depth));
    assert_eq!(after.max_depth, before.max_depth - 2);
    assert_eq!(after.sampler.pattern, SamplePattern::Grid);
    assert_ne!(viewer.pass_settings(PassKind::Sample(1)).seed, after.seed, "passes must draw new numbers");
}

#[test]
fn a_change_shows_a_preview_first_then_one_sample_per_pixel() {
    let mut viewer = default_viewer();
    let job = viewer.next_job().unwrap();
    assert_eq!(job.kind, PassKind::Preview(8));
    assert!(viewer.next_job().is_none(), "one pass at a time");
    assert_eq!(viewer.finish(glint_view::pass::run(&job)), Some(PassKind::Preview(8)));
    run_passes(&mut viewer, 1);
    viewer.handle(Input::Zoom(1.0));
    assert_eq!(viewer.next_job().unwrap().kind, PassKind::Preview(8));
}

#[test]
fn a_result_from_before_a_change_is_dropped() {
    let mut viewer = default_viewer();
    let job = viewer.next_job().unwrap();
    let stale = glint_view::pass::run(&job);
    viewer.handle(Input::Orbit { dx: 5.0, dy: 0.0 });
    assert_eq!(viewer.finish(stale), None);
    assert!(job.cancel.load(std::sync::atomic::Ordering::Relaxed), "the old pass is cancelled");
    assert!(viewer.next_job().is_some());
}

#[test]
fn one_pass_at_pixel_centres_is_glint_renders_image() {
    let mut viewer = default_viewer();
    viewer.handle(Input::Toggle(Toggle::AntiAliasing));
    run_passes(&mut viewer, 1);
    assert!(!viewer.busy(), "without anti-aliasing one pass is the whole image");
    let difference = viewer.image().mean_abs_diff(&rendered(1, SamplePattern::Grid));
    assert!(difference < 1e-4, "mean difference {difference}");
}

#[test]
fn accumulated_passes_converge_to_glint_renders_anti_aliased_image() {
    let reference = rendered(16, SamplePattern::Jittered);
    let mut viewer = default_viewer();
    run_passes(&mut viewer, 1);
    let one = viewer.image().mean_abs_diff(&reference);
    run_passes(&mut viewer, 256);
    let many = viewer.image().mean_abs_diff(&reference);
    // Both are 256-sample estimates: noise alone leaves about √2/16 of one pass's error;
    // a bias (a shifted pixel, a wrong weight) would leave a floor far above it.
    assert!(many < one / 6.0, "1 pass: {one}, 256 passes: {many}");
}

#[test]
fn explaining_a_pixel_of_the_mirror_sphere_lists_its_reflected_ray_and_what_it_hits() {
    let mut viewer = default_viewer();
    let camera = viewer.render_camera().unwrap();
    // The mirror sphere's centre (scenes/default.glint), a little above it to stay off the floor's reflection.
    let pixel = project(&camera, Vec3::new(-1.2, 1.3, -0.5), Vec2::new(SIZE.0 as f32, SIZE.1 as f32)).unwrap();
    let explained = viewer.explain(pixel.x as u32, pixel.y as u32).unwrap().clone();
    let rays = &explained.tree.rays;
    let mirror = rays[0].hit.expect("the camera ray hits the sphere");
    assert_eq!(viewer.desc().materials[mirror.material as usize].name, "mirror");
    let reflected = rays.iter().find(|r| r.kind == RayKind::Reflected && r.parent == Some(0)).expect("a reflected ray");
    let scene = viewer.scene().lock().unwrap();
    let direct = scene.intersect(&Ray::new(reflected.origin, reflected.dir), f32::INFINITY);
    match (reflected.hit, direct) {
        (Some(listed), Some(traced)) => {
            assert_eq!(listed.instance, traced.instance);
            assert!((listed.distance - traced.t * reflected.dir.length()).abs() < 1e-4);
            assert!(listed.point.distance(traced.point) < 1e-4);
        }
        (None, None) => {}
        (listed, traced) => panic!("the tree says {listed:?}, a direct trace {traced:?}"),
    }
    let text = glint_view::explain::describe(&explained.tree, (explained.x, explained.y), &scene, viewer.desc());
    assert!(text.contains("reflected ray of #0") && text.contains("'mirror'") && text.contains("+ "), "{text}");
}

#[test]
fn a_debug_view_is_one_pass_and_differs_from_the_beauty_image() {
    let mut viewer = default_viewer();
    run_passes(&mut viewer, 1);
    let beauty = viewer.image().clone();
    viewer.handle(Input::NextView);
    assert!(matches!(viewer.view(), ViewMode::Debug(_)));
    while viewer.step() {}
    assert!(viewer.image().mean_abs_diff(&beauty) > 0.05);
}

#[test]
fn a_failed_reload_keeps_the_image_and_says_where_a_good_one_replaces_the_scene() {
    let mut viewer = default_viewer();
    run_passes(&mut viewer, 1);
    let image = viewer.image().clone();
    let camera = viewer.camera().clone();
    viewer.reload(Err("scene.glint:3:7: unknown property 'colr'".into()));
    assert_eq!(viewer.error(), Some("scene.glint:3:7: unknown property 'colr'"));
    assert!(viewer.image() == &image, "the last good image stays");
    let mut brighter = glint_scene::default_scene();
    brighter.settings.background = Vec3::new(1.0, 0.0, 0.0);
    viewer.reload(Ok(brighter));
    assert_eq!(viewer.error(), None);
    assert_eq!(*viewer.camera(), camera, "a reload keeps the camera");
    run_passes(&mut viewer, 1);
    assert!(viewer.image().pixels[0].x > 0.9, "the new background shows");
}

#[test]
fn save_writes_a_png_and_an_exr_of_the_image() {
    let mut viewer = default_viewer();
    run_passes(&mut viewer, 1);
    let dir = std::env::temp_dir().join(format!("glint-view-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for name in ["shot.png", "shot.exr"] {
        viewer.save(&dir.join(name)).unwrap();
        let bytes = std::fs::read(dir.join(name)).unwrap();
        let magic: &[u8] = if name.ends_with("png") { b"\x89PNG" } else { &[0x76, 0x2f, 0x31, 0x01] };
        assert!(bytes.starts_with(magic), "{name} is not a {}", &name[5..]);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
