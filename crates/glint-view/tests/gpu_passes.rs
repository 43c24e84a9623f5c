//! The viewer's sample passes on the GPU (lavapipe in CI): they accumulate on the device
//! toward the image the CPU's passes average to, a camera move starts them over, and
//! previews stay on the CPU.

use glint_core::film::Image;
use glint_gpu::Gpu;
use glint_view::pass::PassKind;
use glint_view::viewer::{Input, Viewer};

/// The GPU for the whole test run, or `None` (with a note) on a machine without an
/// adapter; CI sets `GLINT_REQUIRE_GPU=1`, so there a missing adapter fails.
fn gpu() -> Option<&'static Gpu> {
    match Gpu::new() {
        Ok(gpu) => Some(Box::leak(Box::new(gpu))),
        Err(e) if std::env::var_os("GLINT_REQUIRE_GPU").is_none() => {
            eprintln!("SKIPPED: no GPU adapter ({e})");
            None
        }
        Err(e) => panic!("GLINT_REQUIRE_GPU is set but: {e}"),
    }
}

fn cornell_viewer() -> Viewer {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/cornell-path.glint");
    let desc = glint_scene::load_any(std::path::Path::new(path)).expect("the example loads").scene;
    Viewer::new(desc, Some((32, 32))).expect("compiles")
}

fn run_passes(viewer: &mut Viewer, passes: u32) {
    while viewer.passes() < passes {
        assert!(viewer.step(), "the schedule stopped at {} passes", viewer.passes());
    }
}

fn mean(image: &Image) -> f32 {
    image.pixels.iter().map(|p| p.element_sum() / 3.0).sum::<f32>() / image.pixels.len() as f32
}

#[test]
fn gpu_passes_average_to_the_cpu_passes_image_and_restart_after_a_move() {
    let Some(gpu) = gpu() else { return };
    let mut on_cpu = cornell_viewer();
    run_passes(&mut on_cpu, 12);
    assert!(!on_cpu.timing().on_gpu);

    let mut on_gpu = cornell_viewer();
    on_gpu.use_gpu(Some(gpu));
    run_passes(&mut on_gpu, 12);
    assert!(on_gpu.timing().on_gpu, "the sample passes ran on the GPU: {:?}", on_gpu.status());
    assert_eq!(on_gpu.passes(), 12);
    let (cpu, gpu_mean) = (mean(on_cpu.image()), mean(on_gpu.image()));
    assert!(cpu > 0.01, "the Cornell box is lit: {cpu}");
    assert!((cpu - gpu_mean).abs() < 0.05 * cpu, "12 passes: CPU mean {cpu}, GPU mean {gpu_mean}");

    // A move starts over: a CPU preview first, then the GPU's passes from one.
    let before = on_gpu.image().clone();
    on_gpu.handle(Input::Orbit { dx: 6.0, dy: 0.0 });
    assert_eq!(on_gpu.passes(), 0);
    let job = on_gpu.next_job().expect("a preview is scheduled");
    assert!(matches!(job.kind, PassKind::Preview(_)));
    on_gpu.finish(glint_view::pass::run(&job));
    run_passes(&mut on_gpu, 2);
    assert_eq!(on_gpu.passes(), 2, "the GPU's film was cleared, not added to");
    assert_ne!(on_gpu.image().pixels, before.pixels, "the new view is drawn");
}
