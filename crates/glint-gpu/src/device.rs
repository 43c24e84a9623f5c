//! Finding a GPU and opening it, with one clear sentence when that cannot be done.

use glint_core::scene::RenderScene;

use crate::hardware;
use crate::shader::binding;

/// Why the GPU backend cannot render.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (Vulkan, Metal or DX12); install the GPU's driver, or Mesa's CPU driver \
         lavapipe (Debian: mesa-vulkan-drivers), or render with --device cpu"
    )]
    NoAdapter,
    #[error("the GPU adapter '{adapter}' cannot run glint's kernels: {reason}")]
    Unsuitable { adapter: String, reason: String },
    #[error(
        "the scene's {what} take {needed} bytes in one buffer, over this adapter's limit \
         max_storage_buffer_binding_size = {limit} bytes; render it with --device cpu"
    )]
    TooLarge { what: &'static str, needed: u64, limit: u64 },
    #[error("the GPU reported an error: {0}")]
    Device(String),
}

/// Loop iterations a kernel may run in all on a driver that caps them
/// ([`Gpu::caps_loop_iterations`]).
pub const LOOP_CAP: u32 = 65_535;

/// An opened GPU: the device and queue every kernel runs on, and what it is.
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub info: wgpu::AdapterInfo,
    pub limits: wgpu::Limits,
    /// Whether the driver caps loop iterations, once measured.
    loop_cap: std::sync::OnceLock<bool>,
}

impl Gpu {
    /// Opens the most capable adapter (a discrete GPU before an integrated one, a
    /// software one such as lavapipe last), with the adapter's own limits so large
    /// scenes fit where the hardware allows.
    pub fn new() -> Result<Gpu, GpuError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = pollster::block_on(instance.request_adapter(&options)).map_err(|_| GpuError::NoAdapter)?;
        let info = adapter.get_info();
        let limits = adapter.limits();
        let unsuitable = |reason: String| GpuError::Unsuitable { adapter: info.name.clone(), reason };
        if limits.max_storage_buffers_per_shader_stage < binding::STORAGE_COUNT {
            return Err(unsuitable(format!(
                "it allows {} storage buffers per shader stage (max_storage_buffers_per_shader_stage), glint needs {}",
                limits.max_storage_buffers_per_shader_stage,
                binding::STORAGE_COUNT
            )));
        }
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("glint"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
            .map_err(|e| unsuitable(format!("opening it failed: {e}")))?;
        Ok(Gpu { device, queue, info, limits, loop_cap: std::sync::OnceLock::new() })
    }

    /// What `--device auto` renders `scene` on: the most capable adapter, opened, if it
    /// is a real GPU that can render everything in the scene; otherwise why glint's own
    /// CPU path renders instead. Where the machine has no GPU at all
    /// ([`hardware::gpu_may_exist`]), Vulkan is not loaded.
    pub fn open_hardware(scene: &RenderScene) -> Result<Gpu, String> {
        if !hardware::gpu_may_exist() {
            return Err("this machine has no GPU (no /dev/dri render node, no NVIDIA or WSL GPU device)".into());
        }
        let gpu = Gpu::new().map_err(|e| e.to_string())?;
        if !gpu.is_hardware() {
            return Err(format!("the only GPU adapter, {}, is a CPU driver", gpu.describe()));
        }
        if let Some(why) = crate::upload::beyond_adapter(&gpu, scene) {
            return Err(format!("the GPU adapter {} cannot: {why}", gpu.describe()));
        }
        Ok(gpu)
    }

    /// Whether the adapter is a real GPU rather than a CPU driver (lavapipe,
    /// SwiftShader, WARP): `--device auto` renders on glint's own CPU path instead of
    /// one of those.
    pub fn is_hardware(&self) -> bool {
        self.info.device_type != wgpu::DeviceType::Cpu
    }

    /// Whether this driver stops every loop of a kernel once the kernel has run
    /// [`LOOP_CAP`] loop iterations in all, as Mesa's lavapipe 22.3 (Debian 12) does:
    /// a kernel that goes on past it silently computes wrong results. Measured once,
    /// by a kernel that runs one loop past the cap and then a short one.
    pub fn caps_loop_iterations(&self) -> bool {
        *self.loop_cap.get_or_init(|| crate::render::loop_iterations_capped(self).unwrap_or(true))
    }

    /// "name (backend, driver)", for saying where a render runs.
    pub fn describe(&self) -> String {
        let driver = if self.info.driver.is_empty() { String::new() } else { format!(", {}", self.info.driver) };
        format!("{} ({:?}{driver})", self.info.name, self.info.backend)
    }

    /// Runs `work` with validation errors captured instead of aborting the process.
    pub(crate) fn checked<T>(&self, what: &str, work: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let value = work();
        match pollster::block_on(scope.pop()) {
            None => Ok(value),
            Some(e) => Err(GpuError::Device(format!("{what}: {e}"))),
        }
    }
}
