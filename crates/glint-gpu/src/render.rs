//! Rendering on the GPU in passes: each pass traces N samples per pixel into a sample
//! buffer, then every pixel gathers the filtered samples that reach it into its
//! accumulator (weighted sum and weight), which stays on the device between passes.
//! The film can be read back after any pass, which is what progressive display needs.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3;
use glint_core::film::Image;
use glint_core::scene::RenderScene;

use crate::device::{Gpu, GpuError};
use crate::shader::{self, binding};
use crate::upload::GpuScene;

/// Samples traced in one dispatch at most, so a pass stays short on a slow device.
const SAMPLES_PER_DISPATCH: u64 = 1 << 21;

/// A render in progress on the GPU: the uploaded scene, the kernels, and the film
/// accumulated so far.
pub struct Progressive<'g> {
    gpu: &'g Gpu,
    scene: GpuScene,
    trace: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    accum: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Samples per pixel the sample buffer holds: the largest pass.
    capacity: u32,
    done: u32,
}

impl<'g> Progressive<'g> {
    /// Uploads the scene and compiles the kernels.
    pub fn new(gpu: &'g Gpu, scene: &RenderScene) -> Result<Self, GpuError> {
        let gpu_scene = GpuScene::new(gpu, scene)?;
        let (width, height) = (scene.settings.width as u64, scene.settings.height as u64);
        let pixels = width * height;
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let film_bytes = pixels * 16;
        if film_bytes > limit {
            return Err(GpuError::TooLarge { what: "film", needed: film_bytes, limit });
        }
        let capacity = (SAMPLES_PER_DISPATCH / pixels).min(limit / film_bytes).clamp(1, scene.settings.spp as u64) as u32;
        let storage = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let samples = storage("samples", film_bytes * capacity as u64, wgpu::BufferUsages::empty());
        let accum = storage("film", film_bytes, wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST);
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("film readback"),
            size: film_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let params = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pass parameters"),
            size: std::mem::size_of::<crate::records::Params>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let (trace, splat, bind_group) = gpu.checked("compiling the render kernels", || {
            let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("glint render kernels"),
                source: wgpu::ShaderSource::Wgsl(shader::source().into()),
            });
            let layout = bind_group_layout(&gpu.device);
            let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("scene"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = |entry: &str| {
                gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pipeline_layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let (trace, splat) = (pipeline("trace_path"), pipeline("splat"));
            let b = &gpu_scene.buffers;
            let entries = [
                (binding::PARAMS, &params),
                (binding::INSTANCES, &b.instances),
                (binding::NODES, &b.nodes),
                (binding::PACKETS, &b.packets),
                (binding::MESHES, &b.meshes),
                (binding::BSDFS, &b.bsdfs),
                (binding::EMITTERS, &b.emitters),
                (binding::FLOATS, &b.floats),
                (binding::WORDS, &b.words),
                (binding::TEXTURES, &b.textures),
                (binding::SAMPLES, &samples),
                (binding::ACCUM, &accum),
            ];
            let entries: Vec<_> = entries
                .iter()
                .map(|&(binding, buffer)| wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() })
                .collect();
            let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("scene"),
                layout: &layout,
                entries: &entries,
            });
            (trace, splat, bind_group)
        })?;
        Ok(Progressive { gpu, scene: gpu_scene, trace, splat, bind_group, params, accum, readback, capacity, done: 0 })
    }

    /// Samples per pixel accumulated so far.
    pub fn samples_done(&self) -> u32 {
        self.done
    }

    /// Traces `samples` more samples per pixel (in as many dispatches as the sample
    /// buffer needs) and adds them to the film.
    pub fn add_samples(&mut self, samples: u32) -> Result<(), GpuError> {
        let mut left = samples;
        while left > 0 {
            let pass = left.min(self.capacity);
            self.dispatch(pass)?;
            left -= pass;
        }
        Ok(())
    }

    fn dispatch(&mut self, pass: u32) -> Result<(), GpuError> {
        let mut params = self.scene.params;
        params.sample_offset = self.done;
        params.pass_samples = pass;
        let gpu = self.gpu;
        gpu.checked("running a pass", || {
            gpu.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            let groups = (params.width.div_ceil(8), params.height.div_ceil(8));
            {
                let mut cpass = encoder.begin_compute_pass(&Default::default());
                cpass.set_bind_group(0, &self.bind_group, &[]);
                cpass.set_pipeline(&self.trace);
                cpass.dispatch_workgroups(groups.0, groups.1, pass);
            }
            {
                // A second pass: the gather must see every sample the first one wrote.
                let mut cpass = encoder.begin_compute_pass(&Default::default());
                cpass.set_bind_group(0, &self.bind_group, &[]);
                cpass.set_pipeline(&self.splat);
                cpass.dispatch_workgroups(groups.0, groups.1, 1);
            }
            gpu.queue.submit([encoder.finish()]);
        })?;
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(format!("waiting for a pass: {e}")))?;
        self.done += pass;
        Ok(())
    }

    /// The film so far: each pixel's weighted sum over its weight.
    pub fn image(&self) -> Result<Image, GpuError> {
        let gpu = self.gpu;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.accum, 0, &self.readback, 0, self.readback.size());
        gpu.queue.submit([encoder.finish()]);
        let slice = self.readback.slice(..);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(format!("reading the film back: {e}")))?;
        receiver
            .recv()
            .map_err(|e| GpuError::Device(e.to_string()))?
            .map_err(|e| GpuError::Device(format!("reading the film back: {e}")))?;
        let (width, height) = (self.scene.params.width, self.scene.params.height);
        let pixels = {
            let view = slice.get_mapped_range().map_err(|e| GpuError::Device(format!("{e:?}")))?;
            let accum: &[[f32; 4]] = bytemuck::cast_slice(&view);
            accum
                .iter()
                .map(|&[r, g, b, w]| if w.abs() > 1e-12 { Vec3::new(r, g, b) / w } else { Vec3::ZERO })
                .collect()
        };
        self.readback.unmap();
        Ok(Image { width, height, pixels })
    }
}

/// Group 0 as every kernel declares it: the parameters, the scene's arrays (read
/// only), the sample buffer and the film.
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    };
    let mut entries = vec![entry(binding::PARAMS, wgpu::BufferBindingType::Uniform)];
    for b in binding::INSTANCES..=binding::TEXTURES {
        entries.push(entry(b, wgpu::BufferBindingType::Storage { read_only: true }));
    }
    for b in [binding::SAMPLES, binding::ACCUM] {
        entries.push(entry(b, wgpu::BufferBindingType::Storage { read_only: false }));
    }
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some("scene"), entries: &entries })
}

/// Why a GPU render stopped without an image.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GpuRenderError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("render cancelled")]
    Cancelled,
}

/// Renders `scene` to completion on `gpu`, reporting progress in samples per pixel
/// (`done`, `total`) after each pass and stopping between passes when `cancel` is set.
pub fn render(
    gpu: &Gpu,
    scene: &RenderScene,
    progress: &dyn Fn(usize, usize),
    cancel: &AtomicBool,
) -> Result<Image, GpuRenderError> {
    let mut film = Progressive::new(gpu, scene)?;
    let total = scene.settings.spp;
    while film.samples_done() < total {
        if cancel.load(Ordering::Relaxed) {
            return Err(GpuRenderError::Cancelled);
        }
        film.add_samples((total - film.samples_done()).min(film.capacity))?;
        progress(film.samples_done() as usize, total as usize);
    }
    Ok(film.image()?)
}
