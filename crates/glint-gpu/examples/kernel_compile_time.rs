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
    let every_shape = std::env::temp_dir().join(format!("glint-every-shape-{}.glint", std::process::id()));
    let mesh = scenes.join("meshes/icosphere.obj");
    std::fs::write(&every_shape, EVERY_SHAPE.replace("MESH", &mesh.to_string_lossy()))
        .expect("temporary scene written");
    let runs = [
        ("path", scenes.join("cornell-path.glint")),
        ("whitted", scenes.join("cornell-whitted.glint")),
        ("path, every shape", every_shape.clone()),
    ];
    for (kernel, file) in runs {
        let mut desc = glint_scene::load_scene(&file).expect("scene loads");
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
    let _ = std::fs::remove_file(every_shape);
}

/// A scene whose kernels keep every shape's code (`render.rs` specializes kernels by
/// the shapes a scene has): a mesh, a torus, a quadric, and CSG with a superellipsoid
/// operand, which turns on the solver shared with implicit surfaces and blobs.
const EVERY_SHAPE: &str = r#"
settings { integrator path {} }
camera { eye [0 0 6] look_at [0 0 0] fov 40 }
material "m" { bsdf diffuse { reflectance 0.5 } }
light point { position [2 3 4] color [10 10 10] }
mesh "tri" { file "MESH" }
torus { minor_radius 0.3 material "m" translate [-1.5 0 0] }
quadric { coefficients [1 -0.25 1 0 0 0 0 0 0 -0.16] bounds [-1 -1 -1] [1 1 1] material "m" translate [1.2 1 0] }
difference { material "m" superellipsoid { exponents [0.3 0.3] } sphere { scale 0.7 translate [0.3 0.3 0.6] } }
mesh_instance "tri" { material "m" scale 0.5 translate [1 -1 0] }
"#;
