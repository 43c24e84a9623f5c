//! The `glint` binary renders path-traced scenes and writes AOV layers.

use std::path::PathBuf;
use std::process::Command;

mod support;

fn glint() -> Command {
    Command::new(env!("CARGO_BIN_EXE_glint"))
}

fn scene(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("glint-cli-{}-{name}", std::process::id()))
}

#[test]
fn path_traced_render_writes_albedo_normal_and_depth_layers() {
    let out = temp("aov.exr");
    let status = glint()
        .args(["render", "--integrator", "path", "--spp", "4", "--width", "24", "--height", "24", "-q"])
        .args(["--aov", "albedo,normal,depth", "-o"])
        .arg(&out)
        .arg(scene("cornell-path.glint"))
        .status()
        .unwrap();
    assert!(status.success());
    let channels = support::exr_channels(&out);
    let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
    for name in ["R", "G", "B", "albedo.R", "normal.X", "normal.Y", "normal.Z", "depth.Z"] {
        assert!(names.contains(&name), "{name} missing from {names:?}");
    }
    let channel = |name: &str| -> Vec<f32> { channels.iter().find(|(n, _)| n == name).unwrap().1.clone() };
    // Every camera ray meets the box: positive distances, albedos within [0, 1], unit
    // normals (where a pixel's samples all saw the same surface).
    assert!(channel("depth.Z").iter().all(|&d| d > 0.5 && d < 10.0));
    assert!(channel("albedo.R").iter().all(|&a| (0.0..=1.0).contains(&a)));
    let (x, y, z) = (channel("normal.X"), channel("normal.Y"), channel("normal.Z"));
    let unit = (0..x.len()).filter(|&i| (x[i] * x[i] + y[i] * y[i] + z[i] * z[i] - 1.0).abs() < 1e-3).count();
    assert!(unit > x.len() / 2, "{unit} of {} normals are unit", x.len());
    std::fs::remove_file(&out).unwrap();
}

#[test]
fn aovs_need_an_exr_output_and_nothing_is_written_otherwise() {
    let out = temp("aov.png");
    let result = glint().args(["render", "--aov", "depth", "-q", "-o"]).arg(&out).output().unwrap();
    assert!(!result.status.success());
    assert!(String::from_utf8_lossy(&result.stderr).contains("OpenEXR"), "{}", String::from_utf8_lossy(&result.stderr));
    assert!(!out.exists());
}
