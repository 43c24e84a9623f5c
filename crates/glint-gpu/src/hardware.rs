//! Whether a Linux machine has a GPU at all, told from its device nodes without loading
//! Vulkan, so that `--device auto` need not open Vulkan where only a CPU driver could
//! answer.
//!
//! Creating a wgpu instance makes the Vulkan loader load every installed driver, and
//! Debian's `mesa-vulkan-drivers` installs Intel's, AMD's and lavapipe's together,
//! lavapipe with LLVM: on a machine without a GPU the probe took about 50 ms of a
//! 120 ms render of a small scene (and printed lavapipe's own complaints) to learn that
//! the only adapter runs on the CPU, where glint's own CPU path renders instead. A
//! driver for real hardware opens it through a device node: a DRM render or card node
//! (`/dev/dri/renderD128`: Mesa's drivers, Nouveau's NVK among them), NVIDIA's own
//! (`/dev/nvidiactl`, `/dev/nvidia0`), or WSL's paravirtual GPU (`/dev/dxg`). Where
//! none exists, no adapter but a CPU driver can be found.

use std::path::Path;

/// Environment variables that point the Vulkan loader at drivers of the user's choice,
/// which are then asked whatever `/dev` holds.
const DRIVER_OVERRIDES: [&str; 3] = ["VK_DRIVER_FILES", "VK_ICD_FILENAMES", "VK_ADD_DRIVER_FILES"];

/// Whether this machine may have a GPU a Vulkan driver can open: false only on Linux
/// with no GPU device node and the loader's driver search left alone.
pub fn gpu_may_exist() -> bool {
    if !cfg!(target_os = "linux") || DRIVER_OVERRIDES.iter().any(|v| std::env::var_os(v).is_some()) {
        return true;
    }
    has_gpu_nodes(Path::new("/dev"))
}

/// Whether the device directory `dev` holds a node a GPU's driver opens.
pub fn has_gpu_nodes(dev: &Path) -> bool {
    let named = |dir: &Path, prefixes: &[&str]| {
        std::fs::read_dir(dir).is_ok_and(|entries| {
            entries.flatten().any(|e| e.file_name().to_str().is_some_and(|n| prefixes.iter().any(|p| n.starts_with(p))))
        })
    };
    named(&dev.join("dri"), &["renderD", "card"]) || named(dev, &["nvidiactl", "nvidia0", "dxg"])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory standing for `/dev`, holding the files `nodes`.
    fn dev_with(name: &str, nodes: &[&str]) -> std::path::PathBuf {
        let dev = std::env::temp_dir().join(format!("glint-dev-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dev);
        std::fs::create_dir_all(dev.join("dri")).unwrap();
        for node in nodes {
            std::fs::write(dev.join(node), "").unwrap();
        }
        dev
    }

    #[test]
    fn gpu_nodes_are_told_from_a_machine_without_one() {
        let cases: [(&str, &[&str], bool); 6] = [
            ("mesa", &["dri/renderD128", "null"], true),
            ("card-only", &["dri/card0"], true),
            ("nvidia", &["nvidiactl", "nvidia0", "nvidia-uvm"], true),
            ("wsl", &["dxg"], true),
            ("none", &["null", "zero", "tty0", "dri/by-path"], false),
            ("no-dri", &[], false),
        ];
        for (name, nodes, expected) in cases {
            let dev = dev_with(name, nodes);
            if name == "no-dri" {
                std::fs::remove_dir(dev.join("dri")).unwrap();
            }
            assert_eq!(has_gpu_nodes(&dev), expected, "{name}: {nodes:?}");
            let _ = std::fs::remove_dir_all(dev);
        }
    }
}
