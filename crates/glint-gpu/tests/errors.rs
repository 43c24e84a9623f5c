//! What the GPU cannot do is said in one sentence: a buffer over the adapter's limit
//! names the limit, and a scene with a feature the GPU does not render names it.

mod common;

use glint_gpu::GpuError;
use glint_gpu::upload::GpuScene;

#[test]
fn a_scene_over_the_buffer_limit_is_refused_naming_the_limit() {
    let Some(mut gpu) = common::gpu() else { return };
    let scene = common::scene_file("mesh-instances.glint", 8, 8, 1);
    gpu.limits.max_storage_buffer_binding_size = 4096;
    let Err(e) = GpuScene::new(&gpu, &scene) else { panic!("a 4 KiB limit cannot hold a mesh") };
    assert!(matches!(e, GpuError::TooLarge { limit: 4096, .. }), "{e:?}");
    let message = e.to_string();
    assert!(message.contains("max_storage_buffer_binding_size = 4096 bytes"), "{message}");
}

#[test]
fn features_the_gpu_lacks_are_named() {
    let solid = "difference { material \"m\" superellipsoid { exponents [0.3 0.3] } sphere { scale 0.7 } }";
    let source = format!("material \"m\" {{ bsdf diffuse {{ reflectance 0.5 }} }}\n{solid}\n");
    let superellipsoid_csg = common::scene(&source, 8, 8, 1);
    let why =
        glint_gpu::upload::unsupported(&superellipsoid_csg).expect("CSG of superellipsoids is not on the GPU yet");
    assert!(why.contains("CSG with Superellipsoid operands"), "{why}");
    let blobs = common::scene_file("blobs.glint", 8, 8, 1);
    assert_eq!(glint_gpu::upload::unsupported(&blobs), None, "blobs run on the GPU");
    let csg = common::scene_file("csg.glint", 8, 8, 1);
    assert_eq!(glint_gpu::upload::unsupported(&csg), None, "CSG of analytic solids runs on the GPU");
    let mut adaptive_with_aovs = common::scene_file("soft-shadows.glint", 8, 8, 1);
    adaptive_with_aovs.settings.aovs = true;
    assert_eq!(glint_gpu::upload::unsupported(&adaptive_with_aovs), None, "adaptive sampling and AOVs run on the GPU");
    let whitted = common::scene_file("default.glint", 8, 8, 1);
    assert_eq!(glint_gpu::upload::unsupported(&whitted), None);
    let path = common::scene_file("cornell-path.glint", 8, 8, 1);
    assert_eq!(glint_gpu::upload::unsupported(&path), None);
}
