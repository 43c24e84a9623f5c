//! Progressive accumulation: passes add to the film on the GPU, the film can be read
//! after any pass, and passes of 1 + 3 samples give the image of one pass of 4.

mod common;

use glint_gpu::Progressive;

#[test]
fn passes_accumulate_into_the_film_of_one_render() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene_file("cornell-path.glint", 24, 24, 4);
    let mut film = Progressive::new(&gpu, &scene).expect("uploads");
    film.add_samples(1).expect("first pass");
    assert_eq!(film.samples_done(), 1);
    let first = film.image().expect("readable after a pass");
    film.add_samples(3).expect("more passes");
    assert_eq!(film.samples_done(), 4);
    let all = film.image().expect("readable");
    let whole = common::render_gpu(&gpu, &scene);
    let a = common::agreement(&all, &whole);
    assert!(a.max_abs <= 1e-5 * (1.0 + a.means.0), "passes differ from one render by {}", a.max_abs);
    // One sample per pixel is a noisier estimate of the same image.
    let one = common::agreement(&first, &whole);
    assert!(one.max_abs > 0.0, "the first pass must not already hold every sample");
    assert!((one.means.0 - one.means.1).abs() < 0.25 * one.means.1, "{:?}", one.means);
}

#[test]
fn a_restarted_render_gives_the_image_of_a_fresh_one() {
    let Some(gpu) = common::gpu() else { return };
    let scene = common::scene_file("cornell-path.glint", 24, 24, 2);
    // Another view of the same scene: the camera turned and another seed.
    let mut elsewhere = scene.clone();
    let mut desc = glint_core::desc::CameraDesc::default();
    (desc.eye, desc.look) = (glam::Vec3::new(1.0, 1.0, 4.0), glam::Vec3::new(-1.0, 0.0, -4.0));
    elsewhere.camera = glint_core::camera::Camera::new(&desc, 1.0).expect("a camera");
    elsewhere.settings.seed += 7;
    let mut film = Progressive::new(&gpu, &elsewhere).expect("uploads");
    film.add_samples(2).expect("a pass of the other view");
    let other = film.image().expect("readable");
    assert!(film.restart(&scene).expect("restarts"), "same scene, size and integrator");
    assert_eq!(film.samples_done(), 0);
    film.add_samples(2).expect("a pass");
    let restarted = film.image().expect("readable");
    let fresh = common::render_gpu(&gpu, &scene);
    let a = common::agreement(&restarted, &fresh);
    assert!(a.max_abs <= 1e-5 * (1.0 + a.means.0), "restarted differs from fresh by {}", a.max_abs);
    assert!(common::agreement(&other, &fresh).max_abs > 0.01, "the other view must look different");
    // Another size needs a new render.
    let mut larger = scene.clone();
    larger.settings.width += 8;
    assert!(!film.restart(&larger).expect("no GPU error"));
}
