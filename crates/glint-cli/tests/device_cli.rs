//! `glint render --device`: the GPU renders as the CPU does, and a scene its driver
//! cannot run is refused in one sentence, leaving no output file; `auto` falls back to
//! the CPU and says why.

use std::path::PathBuf;
use std::process::Command;

mod support;

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

/// A temporary path of its own for each call: tests run in parallel, and two that wrote
/// the same scene to one path removed it under each other.
fn temp(name: &str) -> PathBuf {
    static CALLS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    std::env::temp_dir().join(format!("glint-device-{}-{call}-{name}", std::process::id()))
}

/// Whether some GPU adapter (lavapipe counts) exists here; CI installs lavapipe.
fn has_adapter() -> bool {
    glint_gpu::Gpu::new().is_ok() || std::env::var_os("GLINT_REQUIRE_GPU").is_some()
}

/// A Whitted scene of CSG with a numerically solved operand (`solid`) written to a
/// temporary file.
fn csg_of(name: &str, solid: &str) -> PathBuf {
    let path = temp(&format!("{name}-csg.glint"));
    let source = format!(
        "settings {{ width 16 height 12 }}\ncamera {{ eye [0 0 4] look_at [0 0 0] }}\n\
         light point {{ position [2 3 4] color [1 1 1] }}\nmaterial \"m\" {{ diffuse [0.8 0.3 0.2] }}\n\
         difference {{ material \"m\" {solid} sphere {{ scale 0.7 translate [0.4 0.4 0.6] }} }}\n"
    );
    std::fs::write(&path, source).unwrap();
    path
}

fn csg_of_an_implicit_surface() -> PathBuf {
    csg_of("implicit", "implicit { function \"x^2 + y^2 + z^2 - 1\" bounds [-1.1 -1.1 -1.1] [1.1 1.1 1.1] }")
}

/// Whether the GPU adapter here caps a kernel's loop iterations (lavapipe does), so
/// that glint refuses implicit surfaces and blobs on it.
fn adapter_caps_loops() -> bool {
    glint_gpu::Gpu::new().is_ok_and(|gpu| gpu.caps_loop_iterations())
}

#[test]
fn gpu_refuses_a_scene_beyond_its_driver_in_one_sentence_and_writes_nothing() {
    if !adapter_caps_loops() {
        eprintln!("SKIPPED: no adapter that caps loops here");
        return;
    }
    let out = temp("refused.png");
    let scene = csg_of_an_implicit_surface();
    let output = glint().args(["render", "--device", "gpu", "-q", "-o"]).arg(&out).arg(&scene).output().unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cannot run glint's kernels: its driver stops a kernel's loops after 65535"), "{stderr}");
    assert!(!out.exists());
    let _ = std::fs::remove_file(scene);
}

#[test]
fn auto_renders_on_the_cpu_where_no_hardware_gpu_can_and_says_why() {
    let out = temp("auto.png");
    let scene = csg_of_an_implicit_surface();
    let output = glint().args(["render", "--device", "auto", "-o"]).arg(&out).arg(&scene).output().unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let stderr = String::from_utf8_lossy(&output.stderr);
    let hardware = glint_gpu::Gpu::new().is_ok_and(|gpu| gpu.is_hardware() && !gpu.caps_loop_iterations());
    if !hardware {
        assert!(stderr.contains("glint: rendering on the CPU: "), "{stderr}");
    }
    assert!(out.exists());
    let _ = (std::fs::remove_file(out), std::fs::remove_file(scene));
}

/// Renders the scene file `name` small on the CPU and on the GPU and asserts the 8-bit
/// sRGB images agree within one step of rounding (the same samples give the same bytes).
fn gpu_renders_like_the_cpu(name: &str) {
    gpu_renders_file_like_the_cpu(name, &scene(name));
}

fn gpu_renders_file_like_the_cpu(name: &str, file: &std::path::Path) {
    if !has_adapter() {
        eprintln!("SKIPPED: no GPU adapter");
        return;
    }
    let render = |device: &str| {
        let out = temp(&format!("{name}-{device}.ppm"));
        let output = glint()
            .args(["render", "--spp", "4", "--width", "20", "--height", "16", "--device", device, "-o"])
            .arg(&out)
            .arg(file)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        assert!(output.status.success(), "{stderr}");
        let bytes = std::fs::read(&out).expect("PPM written");
        let _ = std::fs::remove_file(out);
        (bytes, stderr)
    };
    let (cpu, _) = render("cpu");
    let (gpu, stderr) = render("gpu");
    assert!(stderr.contains("on the GPU"), "{stderr}");
    assert_eq!(cpu.len(), gpu.len());
    let worst = cpu.iter().zip(&gpu).map(|(a, b)| a.abs_diff(*b)).max().unwrap();
    assert!(worst <= 1, "{name}: largest difference {worst} steps");
}

#[test]
fn gpu_renders_a_path_traced_scene_like_the_cpu() {
    gpu_renders_like_the_cpu("cornell-path.glint");
}

#[test]
fn gpu_renders_a_whitted_scene_like_the_cpu() {
    gpu_renders_like_the_cpu("cornell-whitted.glint");
}

#[test]
fn gpu_renders_csg_of_a_superellipsoid_like_the_cpu() {
    let file = csg_of("superellipsoid", "superellipsoid { exponents [0.3 0.3] }");
    gpu_renders_file_like_the_cpu("superellipsoid CSG", &file);
    let _ = std::fs::remove_file(file);
}

/// Adaptive sampling with AOV layers on both devices: the sample-count images and the
/// depth layers agree (the GPU takes the CPU's samples).
#[test]
fn gpu_samples_adaptively_and_writes_aov_layers_like_the_cpu() {
    if !has_adapter() {
        eprintln!("SKIPPED: no GPU adapter");
        return;
    }
    let render = |device: &str| {
        let (out, counts) = (temp(&format!("adaptive-{device}.exr")), temp(&format!("counts-{device}.png")));
        let output = glint()
            .args(["render", "--width", "24", "--height", "16", "--device", device, "--aov", "depth", "-o"])
            .arg(&out)
            .arg("--aov-samples")
            .arg(&counts)
            .arg(scene("soft-shadows.glint"))
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).to_string();
        assert!(output.status.success(), "{stderr}");
        let depth = support::exr_channel(&out, "depth.Z");
        let counts_image = glint_scene::image_out::read_image(&counts).expect("a sample-count image");
        let _ = (std::fs::remove_file(out), std::fs::remove_file(counts));
        (depth, counts_image, stderr)
    };
    let (cpu_depth, cpu_counts, _) = render("cpu");
    let (gpu_depth, gpu_counts, stderr) = render("gpu");
    assert!(stderr.contains("on the GPU"), "{stderr}");
    let same = cpu_counts.pixels.iter().zip(&gpu_counts.pixels).filter(|(a, b)| a == b).count();
    assert!(same * 100 >= 97 * cpu_counts.pixels.len(), "{same} of {} sample counts agree", cpu_counts.pixels.len());
    let distinct = gpu_counts.pixels.iter().map(|p| p.x.to_bits()).collect::<std::collections::BTreeSet<_>>();
    assert!(distinct.len() > 1, "every pixel took as many samples");
    // A sample at a silhouette may meet the other surface in f32 on one device.
    let close = cpu_depth.iter().zip(&gpu_depth).filter(|(a, b)| (*a - *b).abs() <= 1e-3 * (1.0 + a.abs())).count();
    assert!(close * 100 >= 98 * cpu_depth.len(), "only {close} of {} depths agree", cpu_depth.len());
}
