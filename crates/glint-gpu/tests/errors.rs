//! What the GPU cannot do is said in one sentence: a buffer over the adapter's limit
//! names the limit, and a driver that caps loops names the cap.

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

/// Every shape and solid the CPU has uploads, CSG of solved operands included; a
/// driver that caps loops refuses implicit surfaces and blobs wherever they are, as
/// instances or as CSG operands, and nothing else.
#[test]
fn only_a_loop_capped_driver_refuses_a_scene_and_names_why() {
    let Some(gpu) = common::gpu() else { return };
    let capped = gpu.caps_loop_iterations();
    let csg = |solid: &str| {
        let source = format!(
            "material \"m\" {{ bsdf diffuse {{ reflectance 0.5 }} }}\n\
             difference {{ material \"m\" {solid} sphere {{ scale 0.7 }} }}\n"
        );
        common::scene(&source, 8, 8, 1)
    };
    let implicit = csg("implicit { function \"x^2 + y^2 + z^2 - 1\" bounds [-1.1 -1.1 -1.1] [1.1 1.1 1.1] }");
    let blob = csg("blob { threshold 0.5 component sphere { radius 1 strength 1 } }");
    for (what, scene) in [("implicit", &implicit), ("blob", &blob)] {
        GpuScene::new(&gpu, scene).unwrap_or_else(|e| panic!("CSG of a {what} uploads: {e}"));
        match glint_gpu::upload::beyond_adapter(&gpu, scene) {
            Some(why) => assert!(capped && why.contains("65535 iterations"), "{what}: {why}"),
            None => assert!(!capped, "a capped driver must refuse CSG of a {what}"),
        }
    }
    let superellipsoid = csg("superellipsoid { exponents [0.3 0.3] }");
    GpuScene::new(&gpu, &superellipsoid).expect("CSG of a superellipsoid uploads");
    assert_eq!(glint_gpu::upload::beyond_adapter(&gpu, &superellipsoid), None);
    for name in ["blobs.glint", "csg.glint", "default.glint", "cornell-path.glint"] {
        let scene = common::scene_file(name, 8, 8, 1);
        GpuScene::new(&gpu, &scene).unwrap_or_else(|e| panic!("{name} uploads: {e}"));
        let refused = glint_gpu::upload::beyond_adapter(&gpu, &scene).is_some();
        assert_eq!(refused, capped && name == "blobs.glint", "{name}");
    }
}
