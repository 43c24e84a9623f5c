//! The GPU renders the same image as the CPU: both backends draw the same samples from
//! the same 32-bit sampler, so path-traced images agree pixel by pixel up to the few
//! paths that float rounding sends another way.

mod common;

use common::*;

#[test]
fn cornell_box_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_file("cornell-path.glint", 48, 48, 16);
    let cpu = render_cpu(&scene);
    let gpu_image = render_gpu(&gpu, &scene);
    let a = agreement(&cpu, &gpu_image);
    eprintln!("cornell: max |diff| {} differing {:.4} means {:?}", a.max_abs, a.differing, a.means);
    assert!((a.means.0 - a.means.1).abs() <= 0.01 * a.means.0, "{:?}", a.means);
    assert!(a.differing < 0.05, "{} of pixels differ", a.differing);
}
