//! A small golden image: the default scene rendered at low resolution and compared with
//! a committed reference within a tolerance. (The example scenes under `scenes/` have no
//! golden images; `native_files.rs` checks only that each one loads.)
//!
//! After an intended change of the picture, regenerate with
//! `GLINT_BLESS=1 cargo test -p glint-scene --test golden` and look at the new images.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use glint_core::desc::SceneDesc;
use glint_core::film::{Image, Transfer};
use glint_core::render::render;
use glint_core::scene::compile;
use glint_scene::image_out::{OutputFormat, read_image, write_image};

/// Mean absolute difference allowed (linear units), and the share of pixels allowed to
/// differ by more than 0.1: room for float noise across platforms, none for a change.
const MEAN_TOLERANCE: f32 = 2e-3;
const OUTLIER_SHARE: f32 = 0.002;

fn golden_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden").join(format!("{name}.png"))
}

fn check_golden(name: &str, mut desc: SceneDesc, width: u32, height: u32) {
    desc.settings.width = width;
    desc.settings.height = height;
    let scene = compile(&desc).expect("scene compiles");
    let (image, _) = render(&scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders");
    let path = golden_path(name);
    if std::env::var_os("GLINT_BLESS").is_some() {
        write_image(&image, &path, OutputFormat::Png16, Transfer::Srgb).unwrap();
        return;
    }
    let reference = read_image(&path).unwrap_or_else(|e| panic!("missing golden image {}: {e}", path.display()));
    assert_eq!((reference.width, reference.height), (width, height));
    // The reference is a display image: compare what a viewer sees, clamped to [0, 1].
    let image = clamped(&image);
    let mean = image.mean_abs_diff(&reference);
    let outliers = outlier_share(&image, &reference);
    if mean > MEAN_TOLERANCE || outliers > OUTLIER_SHARE {
        let actual = path.with_extension("actual.png");
        let _ = write_image(&image, &actual, OutputFormat::Png16, Transfer::Srgb);
        panic!("{name}: mean difference {mean:.5}, {:.3}% outliers; see {}", 100.0 * outliers, actual.display());
    }
}

fn clamped(image: &Image) -> Image {
    let pixels = image.pixels.iter().map(|p| p.clamp(glam::Vec3::ZERO, glam::Vec3::ONE)).collect();
    Image { pixels, ..*image }
}

fn outlier_share(a: &Image, b: &Image) -> f32 {
    let bad = a.pixels.iter().zip(&b.pixels).filter(|(p, q)| (**p - **q).abs().max_element() > 0.1).count();
    bad as f32 / a.pixels.len() as f32
}

#[test]
fn default_scene_matches_its_golden_image() {
    check_golden("default-160x120", glint_scene::default_scene(), 160, 120);
}
