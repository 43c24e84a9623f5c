//! What the film keeps besides the colour, and how many samples it takes: the AOV
//! layers (albedo, normal, depth) and adaptive sampling on the GPU give what the CPU
//! gives for the same samples.

mod common;

use std::sync::atomic::AtomicBool;

use glint_core::desc::{AdaptiveDesc, IntegratorDesc, PathDesc};
use glint_core::film::Image;
use glint_core::render::RenderStats;
use glint_core::scene::RenderScene;
use glint_gpu::Gpu;

fn cpu(scene: &RenderScene) -> (Image, RenderStats) {
    glint_core::render::render(scene, &|_, _| {}, &AtomicBool::new(false)).expect("CPU render")
}

fn gpu_render(gpu: &Gpu, scene: &RenderScene) -> (Image, RenderStats) {
    glint_gpu::render(gpu, scene, &|_, _| {}, &AtomicBool::new(false)).expect("GPU render")
}

/// Asserts two renders of one layer agree where their samples do: at most `share` of
/// the pixels differ by more than `1e-3·(1 + value)`, and the means within 0.5%.
fn assert_layers_agree(what: &str, cpu: &Image, gpu: &Image, share: f32) {
    let a = common::agreement(cpu, gpu);
    eprintln!("{what}: largest difference {:.2e}, {:.2}% differ, means {:?}", a.max_abs, 100.0 * a.differing, a.means);
    assert!(a.means.0.abs() > 0.0, "{what}: the CPU layer is black");
    assert!((a.means.0 - a.means.1).abs() <= 0.005 * a.means.0.abs(), "{what}: means {:?}", a.means);
    assert!(a.differing <= share, "{what}: {:.2}% of pixels differ", 100.0 * a.differing);
}

fn check_aovs(name: &str, scene: &RenderScene, gpu: &Gpu) {
    let (cpu_image, cpu_stats) = cpu(scene);
    let (gpu_image, gpu_stats) = gpu_render(gpu, scene);
    let (c, g) = (cpu_stats.aovs.expect("CPU AOVs"), gpu_stats.aovs.expect("GPU AOVs"));
    assert_layers_agree(&format!("{name} colour"), &cpu_image, &gpu_image, 0.02);
    assert_layers_agree(&format!("{name} albedo"), &c.albedo, &g.albedo, 0.02);
    assert_layers_agree(&format!("{name} normal"), &c.normal, &g.normal, 0.02);
    assert_layers_agree(&format!("{name} depth"), &c.depth, &g.depth, 0.02);
    // The layers are the first hit's, not copies of the colour: a normal has unit
    // length where every sample of a pixel met a surface.
    let unit = g.normal.pixels.iter().filter(|n| (n.length() - 1.0).abs() < 1e-3).count();
    assert!(unit * 2 > g.normal.pixels.len(), "{name}: only {unit} unit normals");
}

#[test]
fn aov_layers_match_the_cpu_for_both_integrators() {
    let Some(gpu) = common::gpu() else { return };
    let mut whitted = common::scene_file("default.glint", 32, 24, 4);
    // Uniform samples, as written for; adaptive sampling is compared below.
    (whitted.settings.aovs, whitted.settings.adaptive) = (true, None);
    check_aovs("whitted default", &whitted, &gpu);
    let mut path = common::scene_file("cornell-path.glint", 24, 24, 4);
    path.settings.aovs = true;
    check_aovs("path cornell", &path, &gpu);
}

#[test]
fn without_aovs_the_gpu_reports_none() {
    let Some(gpu) = common::gpu() else { return };
    let mut scene = common::scene_file("default.glint", 8, 8, 1);
    scene.settings.adaptive = None;
    let (_, stats) = gpu_render(&gpu, &scene);
    assert!(stats.aovs.is_none());
    assert_eq!(stats.samples_per_pixel, vec![1; 64]);
}

/// Compares adaptive renders: the sample counts agree per pixel (a few may fall on the
/// other side of the threshold, whose statistics the GPU keeps in f32 and the CPU in
/// f64), the counts really vary, and the images agree.
fn check_adaptive(name: &str, scene: &RenderScene, gpu: &Gpu) {
    let adaptive = scene.settings.adaptive.expect("an adaptive scene");
    let (cpu_image, cpu_stats) = cpu(scene);
    let (gpu_image, gpu_stats) = gpu_render(gpu, scene);
    let (c, g) = (&cpu_stats.samples_per_pixel, &gpu_stats.samples_per_pixel);
    assert_eq!(c.len(), g.len());
    let same = c.iter().zip(g).filter(|(a, b)| a == b).count();
    eprintln!("{name}: {same} of {} pixels took the CPU's sample count", c.len());
    assert!(same as f32 >= 0.97 * c.len() as f32, "{name}: only {same} of {} counts agree", c.len());
    assert!(g.iter().all(|&n| (adaptive.min_samples..=adaptive.max_samples).contains(&n)), "{name}: {g:?}");
    let (fewest, most) = (g.iter().min().unwrap(), g.iter().max().unwrap());
    assert!(fewest < most, "{name}: every pixel took {fewest} samples");
    assert_layers_agree(&format!("{name} adaptive"), &cpu_image, &gpu_image, 0.03);
}

#[test]
fn adaptive_sampling_takes_the_cpus_samples() {
    let Some(gpu) = common::gpu() else { return };
    // Soft shadows: the penumbrae need more samples than the lit floor.
    let whitted = common::scene_file("soft-shadows.glint", 32, 24, 1);
    check_adaptive("whitted soft-shadows", &whitted, &gpu);
    let mut path = common::scene_file("cornell-path.glint", 16, 16, 1);
    path.settings.integrator = IntegratorDesc::Path(PathDesc { max_depth: 4, ..PathDesc::default() });
    path.settings.adaptive = Some(AdaptiveDesc { min_samples: 4, max_samples: 32, threshold: 0.02 });
    check_adaptive("path cornell", &path, &gpu);
}

#[test]
fn adaptive_rounds_split_into_passes_give_the_same_film() {
    let Some(gpu) = common::gpu() else { return };
    // A pixel budget so large that each round takes several passes: the image cannot
    // tell.
    let scene = common::scene_file("soft-shadows.glint", 16, 12, 1);
    let (whole, whole_stats) = gpu_render(&gpu, &scene);
    let mut split = glint_gpu::Progressive::new(&gpu, &scene).expect("uploads");
    split.limit_pass_samples(3);
    split.sample_adaptively(&|_, _| {}, &AtomicBool::new(false)).expect("adaptive rounds");
    assert_eq!(split.samples_per_pixel().unwrap(), whole_stats.samples_per_pixel);
    let a = common::agreement(&whole, &split.image().unwrap());
    assert!(a.max_abs <= 1e-5 * (1.0 + a.means.0), "split rounds differ by {}", a.max_abs);
}
