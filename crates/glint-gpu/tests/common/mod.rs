//! Shared by the GPU tests: the device (lavapipe in CI) and scene helpers.
#![allow(dead_code)]

use std::path::Path;
use std::sync::atomic::AtomicBool;

use glint_core::film::Image;
use glint_core::scene::{RenderScene, compile};
use glint_gpu::Gpu;

/// The GPU, or `None` (with a visible note) on a machine without any Vulkan, Metal
/// or DX12 adapter. CI sets `GLINT_REQUIRE_GPU=1`, so there a missing adapter fails.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(gpu) => Some(gpu),
        Err(e) if std::env::var_os("GLINT_REQUIRE_GPU").is_none() => {
            eprintln!("SKIPPED: no GPU adapter ({e})");
            None
        }
        Err(e) => panic!("GLINT_REQUIRE_GPU is set but: {e}"),
    }
}

/// A native scene from source, at the given size and samples per pixel.
pub fn scene(source: &str, width: u32, height: u32, spp: u32) -> RenderScene {
    let mut desc = glint_scene::parse_scene(source, "test.glint", Path::new(".")).expect("scene parses");
    desc.settings.width = width;
    desc.settings.height = height;
    desc.settings.spp = Some(spp);
    compile(&desc).expect("scene compiles")
}

/// A native scene from source at the given size, its samples as the source sets them.
pub fn scene_as_written(source: &str, width: u32, height: u32) -> RenderScene {
    let mut desc = glint_scene::parse_scene(source, "test.glint", Path::new(".")).expect("scene parses");
    desc.settings.width = width;
    desc.settings.height = height;
    compile(&desc).expect("scene compiles")
}

/// A native scene from source at the given size (and samples, if given), each of whose
/// meshes `decorate` changes before it is compiled.
fn decorated_scene(
    source: &str,
    (width, height, spp): (u32, u32, Option<u32>),
    decorate: impl Fn(&mut glint_core::desc::MeshDesc),
) -> RenderScene {
    let mut desc = glint_scene::parse_scene(source, "test.glint", Path::new(".")).expect("scene parses");
    desc.settings.width = width;
    desc.settings.height = height;
    desc.settings.spp = spp.or(desc.settings.spp);
    desc.meshes.iter_mut().for_each(decorate);
    compile(&desc).expect("scene compiles")
}

/// A native scene from source whose meshes get vertex colours from their positions
/// (`|p|` clamped to 1, so each octant shows another tint).
pub fn painted_scene(source: &str, width: u32, height: u32, spp: Option<u32>) -> RenderScene {
    decorated_scene(source, (width, height, spp), |mesh| {
        mesh.colors = mesh.positions.iter().map(|p| p.abs().min(glam::Vec3::ONE)).collect();
    })
}

/// A native scene from source whose meshes get uvs from their positions (longitude and
/// height), so that normal maps have a frame to bend normals in.
pub fn uv_mapped_scene(source: &str, width: u32, height: u32, spp: Option<u32>) -> RenderScene {
    decorated_scene(source, (width, height, spp), |mesh| {
        let uv = |p: &glam::Vec3| glam::Vec2::new(p.z.atan2(p.x) / std::f32::consts::TAU + 0.5, 0.5 + 0.5 * p.y);
        mesh.uvs = mesh.positions.iter().map(uv).collect();
    })
}

/// A scene file of the repository.
pub fn scene_file(name: &str, width: u32, height: u32, spp: u32) -> RenderScene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
    let mut desc = glint_scene::load_scene(&path).expect("scene loads");
    desc.settings.width = width;
    desc.settings.height = height;
    desc.settings.spp = Some(spp);
    compile(&desc).expect("scene compiles")
}

/// The file names of the repository's example scenes (`scenes/*.glint`), sorted.
pub fn example_scene_names() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".glint"))
        .collect();
    names.sort();
    names
}

pub fn render_cpu(scene: &RenderScene) -> Image {
    glint_core::render::render(scene, &|_, _| {}, &AtomicBool::new(false)).expect("CPU render").0
}

pub fn render_gpu(gpu: &Gpu, scene: &RenderScene) -> Image {
    glint_gpu::render(gpu, scene, &|_, _| {}, &AtomicBool::new(false)).expect("GPU render").0
}

/// Per-pixel agreement of two renders of the same samples.
pub struct Agreement {
    /// Largest absolute difference of any channel.
    pub max_abs: f32,
    /// Fraction of pixels whose channels differ by more than `1e-3·(1 + value)`.
    pub differing: f32,
    /// Mean of each image, all channels.
    pub means: (f32, f32),
}

pub fn agreement(a: &Image, b: &Image) -> Agreement {
    assert_eq!((a.width, a.height), (b.width, b.height));
    let mut max_abs = 0.0f32;
    let mut differing = 0;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        let d = (*p - *q).abs();
        max_abs = max_abs.max(d.max_element());
        if d.max_element() > 1e-3 * (1.0 + p.max_element()) {
            differing += 1;
        }
    }
    let mean = |i: &Image| i.pixels.iter().map(|p| p.element_sum()).sum::<f32>() / (3 * i.pixels.len()) as f32;
    Agreement { max_abs, differing: differing as f32 / a.pixels.len() as f32, means: (mean(a), mean(b)) }
}

/// Renders `scene` on both backends and asserts they agree: means within 0.5%, at most
/// 2% of pixels differing by more than `1e-3·(1 + value)`. Prints a table row
/// (`--nocapture` shows them): name, size, spp, largest difference, share differing,
/// means.
pub fn check(name: &str, scene: &RenderScene, gpu: &Gpu) {
    let cpu = render_cpu(scene);
    let gpu_image = render_gpu(gpu, scene);
    let a = agreement(&cpu, &gpu_image);
    eprintln!(
        "| {name} | {}x{} | {} | {:.2e} | {:.2}% | {:.5} | {:.5} |",
        scene.settings.width,
        scene.settings.height,
        scene.settings.spp,
        a.max_abs,
        100.0 * a.differing,
        a.means.0,
        a.means.1
    );
    assert!(a.means.0 > 0.0, "{name}: the CPU image is black");
    assert!((a.means.0 - a.means.1).abs() <= 0.005 * a.means.0, "{name}: means {:?}", a.means);
    assert!(a.differing <= 0.02, "{name}: {:.2}% of pixels differ", 100.0 * a.differing);
}
