//! How long the driver takes to compile each render kernel: the pipeline is created and
//! a 4×4 image rendered at 1 spp (lavapipe compiles lazily, at the first dispatch).
//! Run with a cold shader cache, e.g.
//! `MESA_SHADER_CACHE_DISABLE=true cargo run --release -p glint-gpu --example kernel_compile_time`.

use std::path::Path;
use std::time::Instant;

use glint_core::scene::compile;
use glint_gpu::{Gpu, Progressive};

fn main() {
    let gpu = Gpu::new().expect("a GPU adapter (lavapipe will do)");
    println!("adapter: {}", gpu.describe());
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for (kernel, file) in [("path", "cornell-path.glint"), ("whitted", "cornell-whitted.glint")] {
        let mut desc = glint_scene::load_scene(&scenes.join(file)).expect("scene loads");
        desc.settings.width = 4;
        desc.settings.height = 4;
        desc.settings.spp = Some(1);
        let scene = compile(&desc).expect("scene compiles");
        let start = Instant::now();
        let mut film = Progressive::new(&gpu, &scene).expect("kernels compile");
        let created = start.elapsed();
        film.add_samples(1).expect("renders");
        film.image().expect("reads back");
        let total = start.elapsed();
        println!(
            "{kernel}: pipeline created in {:.2} s, first 4x4 image after {:.2} s",
            created.as_secs_f64(),
            total.as_secs_f64()
        );
    }
}
