//! Rendering on the GPU in passes: each pass traces N samples per pixel into a sample
//! buffer, then every pixel gathers the filtered samples that reach it into its
//! accumulator (weighted sum and weight), which stays on the device between passes.
//! The film can be read back after any pass, which is what progressive display needs.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Vec3;
use glint_core::desc::{AdaptiveDesc, IntegratorDesc};
use glint_core::film::{AovImages, Image};
use glint_core::integrator::SurfaceId;
use glint_core::render::{NonFiniteSamples, RenderStats, SourceTally};
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
    /// The adaptive round's statistics and decision kernels, for a scene that samples
    /// adaptively.
    adaptive: Option<AdaptiveKernels>,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    /// The film (see film.wgsl for its layout).
    accum: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Non-finite samples by source (see film.wgsl's `write_sample`), then the
    /// adaptive round's two tallies.
    faults: wgpu::Buffer,
    /// The material of each instance, to name the surfaces that made faults.
    instance_materials: Vec<u32>,
    /// Samples per pixel the sample buffer holds: the largest pass.
    capacity: u32,
    /// Samples per pixel so far, in every pixel; the adaptive rounds' largest count.
    done: u32,
    /// Whether the film holds adaptive rounds (each pixel its own count) rather than
    /// uniform passes.
    sampled_adaptively: bool,
}

/// Adaptive sampling's settings and the kernels of its rounds.
struct AdaptiveKernels {
    settings: AdaptiveDesc,
    /// Whether each pixel starts from a pilot at its centre
    /// ([`RenderScene::adaptive_pilot`]).
    pilot: bool,
    update: wgpu::ComputePipeline,
    decide: wgpu::ComputePipeline,
    /// Resets the pixels that go on past their pilot, after the pilots of those that
    /// stop there are splatted.
    drop_pilots: wgpu::ComputePipeline,
}

impl<'g> Progressive<'g> {
    /// Uploads the scene and compiles the kernels.
    pub fn new(gpu: &'g Gpu, scene: &RenderScene) -> Result<Self, GpuError> {
        if let Some(reason) = crate::upload::beyond_adapter(gpu, scene) {
            return Err(GpuError::Unsuitable { adapter: gpu.info.name.clone(), reason });
        }
        let gpu_scene = GpuScene::new(gpu, scene)?;
        let (width, height) = (scene.settings.width as u64, scene.settings.height as u64);
        let pixels = width * height;
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let sample_bytes = pixels * 16 * film_stride_of(&gpu_scene.params) as u64;
        let film_bytes = sample_bytes + if scene.settings.adaptive.is_some() { pixels * 16 } else { 0 };
        if film_bytes > limit {
            return Err(GpuError::TooLarge { what: "film", needed: film_bytes, limit });
        }
        let most_samples = scene.settings.adaptive.map_or(scene.settings.spp, |a| a.max_samples);
        let capacity = (SAMPLES_PER_DISPATCH / pixels).min(limit / sample_bytes).clamp(1, most_samples as u64) as u32;
        let storage = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | usage,
                mapped_at_creation: false,
            })
        };
        let samples = storage("samples", sample_bytes * capacity as u64, wgpu::BufferUsages::empty());
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
        let faults = storage(
            "non-finite samples and round tallies",
            8 * (scene.instances.len() as u64 + 2),
            wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
        );
        let (trace, splat, adaptive, bind_group) = gpu.checked("compiling the render kernels", || {
            let kernels = Kernels::new(gpu);
            let bind_group = kernels.bind(gpu, &gpu_scene, &params, [&samples, &accum, &faults]);
            let entry = match scene.settings.integrator {
                IntegratorDesc::Path(_) => "trace_path",
                IntegratorDesc::Whitted => "trace_whitted",
            };
            let adaptive = scene.settings.adaptive.map(|settings| AdaptiveKernels {
                settings,
                pilot: scene.adaptive_pilot(),
                update: kernels.pipeline(gpu, "adaptive_update", scene),
                decide: kernels.pipeline(gpu, "adaptive_decide", scene),
                drop_pilots: kernels.pipeline(gpu, "adaptive_drop_pilots", scene),
            });
            (kernels.pipeline(gpu, entry, scene), kernels.pipeline(gpu, "splat", scene), adaptive, bind_group)
        })?;
        let render = Progressive {
            gpu,
            scene: gpu_scene,
            trace,
            splat,
            adaptive,
            bind_group,
            params,
            accum,
            readback,
            faults,
            instance_materials: scene.instances.iter().map(|i| i.material).collect(),
            capacity,
            done: 0,
            sampled_adaptively: false,
        };
        render.clear_faults();
        Ok(render)
    }

    /// No fault counted yet, every smallest pixel index at its largest.
    fn clear_faults(&self) {
        let empty: Vec<u32> = (0..self.fault_words()).map(|i| if i % 2 == 0 { 0 } else { u32::MAX }).collect();
        self.gpu.queue.write_buffer(&self.faults, 0, bytemuck::cast_slice(&empty));
    }

    /// Words of the fault tallies; the round tallies follow.
    fn fault_words(&self) -> u64 {
        self.faults.size() / 4 - 2
    }

    /// The samples that came back NaN or infinite so far, left out of the film, by the
    /// surface whose shading first made each one so (its instance, named with the
    /// instance's material; `None`: the background), as the CPU's render reports them.
    pub fn non_finite(&self) -> Result<NonFiniteSamples, GpuError> {
        let words: Vec<u32> = read_buffer(self.gpu, &self.faults)?;
        let mut tally = NonFiniteSamples::default();
        let width = self.scene.params.width.max(1);
        for (source, pair) in words[..self.fault_words() as usize].chunks_exact(2).enumerate() {
            let [count, pixel] = [pair[0], pair[1]];
            if count == 0 {
                continue;
            }
            let surface = source.checked_sub(1).map(|instance| SurfaceId {
                instance: instance as u32,
                material: self.instance_materials.get(instance).copied().unwrap_or(0),
            });
            let example_pixel = (pixel % width, pixel / width);
            tally.add(surface, SourceTally { count: u64::from(count), example_pixel });
        }
        Ok(tally)
    }

    /// Starts over with `scene`'s camera and settings, keeping the uploaded scene and
    /// the compiled kernels: what an interactive viewer does after each move. `scene`
    /// must be the scene this render was made for, at the same size and with the same
    /// integrator, AOVs and adaptive sampling; `false` (and nothing changed) when it is not, and a new
    /// [`Progressive`] is needed.
    pub fn restart(&mut self, scene: &RenderScene) -> Result<bool, GpuError> {
        let p = &self.scene.params;
        let same_kernel = match scene.settings.integrator {
            IntegratorDesc::Path(_) => p.integrator == crate::records::INTEGRATOR_PATH,
            IntegratorDesc::Whitted => p.integrator == crate::records::INTEGRATOR_WHITTED,
        };
        let same_scene =
            p.instance_count as usize == scene.instances.len() && p.node_count as usize == scene.bvh.nodes.len();
        let same_film = (p.width, p.height, p.aovs)
            == (scene.settings.width, scene.settings.height, scene.settings.aovs as u32)
            && self.adaptive.as_ref().map(|a| (a.settings, a.pilot))
                == scene.settings.adaptive.map(|settings| (settings, scene.adaptive_pilot()));
        if !same_kernel || !same_scene || !same_film {
            return Ok(false);
        }
        crate::upload::set_view(&mut self.scene.params, scene);
        let gpu = self.gpu;
        gpu.checked("clearing the film", || {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            encoder.clear_buffer(&self.accum, 0, None);
            gpu.queue.submit([encoder.finish()]);
            self.clear_faults();
        })?;
        self.done = 0;
        self.sampled_adaptively = false;
        Ok(true)
    }

    /// Caps each dispatch at `samples` samples per pixel (at least 1): shorter passes
    /// keep a slow device responsive, and the film does not change.
    pub fn limit_pass_samples(&mut self, samples: u32) {
        self.capacity = self.capacity.min(samples).max(1);
    }

    /// Samples per pixel accumulated so far.
    pub fn samples_done(&self) -> u32 {
        self.done
    }

    /// Traces `samples` more samples per pixel (in as many dispatches as the sample
    /// buffer needs) and adds them to the film. These passes sample uniformly, also in
    /// a scene that asks for adaptive sampling (what a viewer wants between moves);
    /// [`Progressive::sample_adaptively`] renders such a scene as the CPU does.
    pub fn add_samples(&mut self, samples: u32) -> Result<(), GpuError> {
        let mut left = samples;
        while left > 0 {
            let pass = left.min(self.capacity);
            let mut params = self.scene.params;
            params.sample_offset = self.done;
            params.pass_samples = pass;
            self.dispatch(&params, &[&self.trace, &self.splat])?;
            self.done += pass;
            left -= pass;
        }
        Ok(())
    }

    /// Adaptive sampling of a fresh film, in rounds: every pixel first takes the
    /// minimum; then each one goes on, doubling, while its standard error is above the
    /// threshold, after four times the minimum where it differs from a neighbour
    /// (glint_core::render's rule, decided per pixel on the device). `progress(done,
    /// total)` counts the pixels that have finished after each round; setting `cancel`
    /// stops between rounds. Does nothing for a scene without adaptive sampling.
    pub fn sample_adaptively(
        &mut self,
        progress: &dyn Fn(usize, usize),
        cancel: &AtomicBool,
    ) -> Result<(), GpuRenderError> {
        let Some(settings) = self.adaptive.as_ref().map(|a| a.settings) else { return Ok(()) };
        let pixels = (self.scene.params.width * self.scene.params.height) as usize;
        // At least one sample each, whatever the settings say.
        let min = settings.min_samples.max(1);
        let start: Vec<[u32; 4]> = vec![[0, 0, 0, min]; pixels];
        let state_at = self.accum.size() - 16 * pixels as u64;
        self.gpu.queue.write_buffer(&self.accum, state_at, bytemuck::cast_slice(&start));
        let mut params = self.scene.params;
        (params.adaptive_min, params.adaptive_max) = (min, settings.max_samples.max(min));
        params.adaptive_threshold = settings.threshold;
        let (mut taken, mut need) = (0, min);
        while need > 0 {
            if cancel.load(Ordering::Relaxed) {
                return Err(GpuRenderError::Cancelled);
            }
            params.pass_samples = need.min(self.capacity);
            // Every pixel samples alike until they all reach the minimum.
            let first = taken < min && taken + params.pass_samples >= min;
            let adaptive = self.adaptive.as_ref().expect("checked above");
            // A pilot round (its minimum is one) decides before it splats: only the
            // pilots of the pixels that stop there reach the film.
            let pilot = first && adaptive.pilot;
            params.adaptive_first = if pilot { crate::records::ADAPTIVE_PILOT } else { first as u32 };
            taken += params.pass_samples;
            let tally_at = 4 * self.fault_words();
            self.gpu.queue.write_buffer(&self.faults, tally_at, bytemuck::cast_slice(&[0u32, 0]));
            if pilot {
                let kernels = [&self.trace, &adaptive.update, &adaptive.decide, &self.splat, &adaptive.drop_pilots];
                self.dispatch(&params, &kernels)?;
            } else {
                self.dispatch(&params, &[&self.trace, &self.splat, &adaptive.update, &adaptive.decide])?;
            }
            let tallies: Vec<u32> = read_buffer(self.gpu, &self.faults)?;
            let [sampling, most] = [tallies[tally_at as usize / 4], tallies[tally_at as usize / 4 + 1]];
            progress(pixels - sampling as usize, pixels);
            need = most;
        }
        self.sampled_adaptively = true;
        self.done = self.samples_per_pixel()?.into_iter().max().unwrap_or(0);
        Ok(())
    }

    /// Runs `kernels` one after another over every pixel, the pass's samples deep for
    /// the first (the trace), and waits for them.
    fn dispatch(&self, params: &crate::records::Params, kernels: &[&wgpu::ComputePipeline]) -> Result<(), GpuError> {
        let gpu = self.gpu;
        gpu.checked("running a pass", || {
            gpu.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(params));
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            let groups = (params.width.div_ceil(8), params.height.div_ceil(8));
            for (i, kernel) in kernels.iter().enumerate() {
                // One compute pass each: a kernel must see everything the one before wrote.
                let mut cpass = encoder.begin_compute_pass(&Default::default());
                cpass.set_bind_group(0, &self.bind_group, &[]);
                cpass.set_pipeline(kernel);
                cpass.dispatch_workgroups(groups.0, groups.1, if i == 0 { params.pass_samples } else { 1 });
            }
            gpu.queue.submit([encoder.finish()]);
        })?;
        gpu.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(format!("waiting for a pass: {e}")))?;
        Ok(())
    }

    /// The film's vec4s as they are on the device.
    fn film(&self) -> Result<Vec<[f32; 4]>, GpuError> {
        let gpu = self.gpu;
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&self.accum, 0, &self.readback, 0, self.readback.size());
        gpu.queue.submit([encoder.finish()]);
        map_read(gpu, &self.readback)
    }

    /// Plane `plane` of the film (0: colour; 1, 2: the AOVs) resolved: each pixel's
    /// weighted sums over its weight, black where no sample reached.
    fn resolve(&self, film: &[[f32; 4]], plane: usize, pick: impl Fn([f32; 4]) -> Vec3) -> Image {
        let stride = film_stride_of(&self.scene.params);
        let pixels = (self.scene.params.width * self.scene.params.height) as usize;
        let pixels = (0..pixels)
            .map(|p| {
                let w = film[p * stride][3];
                if w.abs() > 1e-12 { pick(film[p * stride + plane]) / w } else { Vec3::ZERO }
            })
            .collect();
        Image { width: self.scene.params.width, height: self.scene.params.height, pixels }
    }

    /// The film so far: each pixel's weighted sum over its weight.
    pub fn image(&self) -> Result<Image, GpuError> {
        let film = self.film()?;
        Ok(self.resolve(&film, 0, |v| Vec3::new(v[0], v[1], v[2])))
    }

    /// The albedo, normal and depth images so far, filtered like the colour, when the
    /// scene asks for them.
    pub fn aovs(&self) -> Result<Option<AovImages>, GpuError> {
        if self.scene.params.aovs == 0 {
            return Ok(None);
        }
        let film = self.film()?;
        Ok(Some(AovImages {
            albedo: self.resolve(&film, 1, |v| Vec3::new(v[0], v[1], v[2])),
            normal: self.resolve(&film, 2, |v| Vec3::new(v[0], v[1], v[2])),
            depth: self.resolve(&film, 1, |v| Vec3::splat(v[3])),
        }))
    }

    /// Camera samples taken in each pixel so far, row by row.
    pub fn samples_per_pixel(&self) -> Result<Vec<u32>, GpuError> {
        let pixels = (self.scene.params.width * self.scene.params.height) as usize;
        if !self.sampled_adaptively {
            return Ok(vec![self.done; pixels]);
        }
        let film = self.film()?;
        Ok(film[film.len() - pixels..].iter().map(|state| state[0].to_bits()).collect())
    }
}

/// Vec4s per pixel of the film and per sample: colour, then the AOV planes.
fn film_stride_of(params: &crate::records::Params) -> usize {
    if params.aovs != 0 { 3 } else { 1 }
}

/// The pipeline-overridable constants that leave out of a scene's kernels the code of
/// what it does not have (see implicit.wgsl's `SOLVED_SHAPES`).
fn specialization(scene: &RenderScene) -> [(&'static str, f64); 7] {
    use glint_core::shape::ShapeKind;
    let kinds: Vec<ShapeKind> = crate::upload::shape_kinds(scene).collect();
    let has = |wanted: &[ShapeKind]| f64::from(u8::from(kinds.iter().any(|k| wanted.contains(k))));
    [
        ("SOLVED_SHAPES", has(&[ShapeKind::Superellipsoid, ShapeKind::Implicit, ShapeKind::Blob])),
        ("IMPLICITS", has(&[ShapeKind::Implicit])),
        ("BLOBS", has(&[ShapeKind::Blob])),
        ("MESHES", has(&[ShapeKind::Mesh])),
        ("QUADRICS", has(&[ShapeKind::Quadric])),
        ("TORI", has(&[ShapeKind::Torus])),
        ("CSG_SHAPES", has(&[ShapeKind::Csg])),
    ]
}

/// The compiled program and the one bind-group layout all its kernels share.
struct Kernels {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
}

impl Kernels {
    fn new(gpu: &Gpu) -> Kernels {
        let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("glint kernels"),
            source: wgpu::ShaderSource::Wgsl(shader::source().into()),
        });
        let layout = bind_group_layout(&gpu.device);
        let pipeline_layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        Kernels { module, layout, pipeline_layout }
    }

    /// The kernel `entry`, specialized for `scene` ([`specialization`]).
    fn pipeline(&self, gpu: &Gpu, entry: &str, scene: &RenderScene) -> wgpu::ComputePipeline {
        let constants = specialization(scene);
        gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(entry),
            layout: Some(&self.pipeline_layout),
            module: &self.module,
            entry_point: Some(entry),
            compilation_options: wgpu::PipelineCompilationOptions { constants: &constants, ..Default::default() },
            cache: None,
        })
    }

    fn bind(
        &self,
        gpu: &Gpu,
        scene: &GpuScene,
        params: &wgpu::Buffer,
        [samples, accum, faults]: [&wgpu::Buffer; 3],
    ) -> wgpu::BindGroup {
        let b = &scene.buffers;
        let entries = [
            (binding::PARAMS, params),
            (binding::INSTANCES, &b.instances),
            (binding::NODES, &b.nodes),
            (binding::PACKETS, &b.packets),
            (binding::MESHES, &b.meshes),
            (binding::BSDFS, &b.bsdfs),
            (binding::EMITTERS, &b.emitters),
            (binding::FLOATS, &b.floats),
            (binding::WORDS, &b.words),
            (binding::TEXTURES, &b.textures),
            (binding::MATERIALS, &b.materials),
            (binding::LIGHTS, &b.lights),
            (binding::SAMPLES, samples),
            (binding::ACCUM, accum),
            (binding::MOTIONS, &b.motions),
            (binding::CSG_NODES, &b.csg_nodes),
            (binding::FAULTS, faults),
        ];
        let entries: Vec<_> = entries
            .iter()
            .map(|&(binding, buffer)| wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() })
            .collect();
        gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &self.layout,
            entries: &entries,
        })
    }
}

/// One ray for [`trace_rays`]: origin, direction (any length) and the far end of the
/// interval searched, in units of the direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayQuery {
    pub origin: Vec3,
    pub dir: Vec3,
    pub t_max: f32,
}

/// The closest hit a [`RayQuery`] found: distance, instance and part (a mesh's
/// triangle, a cube's face), as `RenderScene::intersect` reports them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    pub t: f32,
    pub instance: u32,
    pub part: u32,
}

/// Traces `rays` against `scene` on the GPU, closest hit each: what the tests compare
/// with the CPU's traversal and what benchmarks time.
pub fn trace_rays(gpu: &Gpu, scene: &RenderScene, rays: &[RayQuery]) -> Result<Vec<Option<RayHit>>, GpuError> {
    let gpu_scene = GpuScene::new(gpu, scene)?;
    let count = rays.len().max(1) as u64;
    let ray_words: Vec<[f32; 4]> =
        rays.iter().flat_map(|r| [r.origin.extend(r.t_max).to_array(), r.dir.extend(0.0).to_array()]).collect();
    let samples = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("rays"),
        size: 32 * count,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(&samples, 0, bytemuck::cast_slice(&ray_words));
    let accum = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("hits"),
        size: 16 * count,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut params = gpu_scene.params;
    params.pass_samples = rays.len() as u32;
    let params_buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("parameters"),
        size: std::mem::size_of::<crate::records::Params>() as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(&params_buffer, 0, bytemuck::bytes_of(&params));
    gpu.checked("tracing rays", || {
        let kernels = Kernels::new(gpu);
        // trace_rays reports no faults, but the layout has a place for them.
        let faults = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("unused faults"),
            size: 8,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        let bind_group = kernels.bind(gpu, &gpu_scene, &params_buffer, [&samples, &accum, &faults]);
        let pipeline = kernels.pipeline(gpu, "trace_rays", scene);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut cpass = encoder.begin_compute_pass(&Default::default());
            cpass.set_bind_group(0, &bind_group, &[]);
            cpass.set_pipeline(&pipeline);
            let groups = (rays.len() as u32).div_ceil(64);
            cpass.dispatch_workgroups(groups.min(65535), groups.div_ceil(65535), 1);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
    let hits: Vec<[f32; 4]> = read_buffer(gpu, &accum)?;
    Ok(hits
        .iter()
        .take(rays.len())
        .map(|&[t, instance, part, found]| {
            (found == 1.0).then(|| RayHit { t, instance: instance.to_bits(), part: part.to_bits() })
        })
        .collect())
}

/// Runs a loop of [`crate::device::LOOP_CAP`] + 1000 iterations, then one of 10: on a
/// driver that caps a kernel's loop iterations the second stops short.
pub(crate) fn loop_iterations_capped(gpu: &Gpu) -> Result<bool, GpuError> {
    let source = format!(
        "@group(0) @binding(0) var<storage, read_write> out: array<u32, 2>;
        @compute @workgroup_size(1)
        fn probe() {{
            var n = 0u;
            loop {{ if n >= {long}u + out[0] {{ break; }} n += 1u; }}
            var m = 0u;
            loop {{ if m >= 10u + out[0] {{ break; }} m += 1u; }}
            out[1] = m;
        }}",
        long = crate::device::LOOP_CAP + 1000
    );
    let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("loop probe"),
        size: 8,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    gpu.checked("probing the driver's loops", || {
        let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("loop probe"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("loop probe"),
            layout: None,
            module: &module,
            entry_point: Some("probe"),
            compilation_options: Default::default(),
            cache: None,
        });
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("loop probe"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: out.as_entire_binding() }],
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut cpass = encoder.begin_compute_pass(&Default::default());
            cpass.set_pipeline(&pipeline);
            cpass.set_bind_group(0, &bind_group, &[]);
            cpass.dispatch_workgroups(1, 1, 1);
        }
        gpu.queue.submit([encoder.finish()]);
    })?;
    let counts: Vec<u32> = read_buffer(gpu, &out)?;
    Ok(counts[1] != 10)
}

/// Copies a device buffer back and reads it as `T`s.
fn read_buffer<T: bytemuck::Pod>(gpu: &Gpu, buffer: &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
    let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    encoder.copy_buffer_to_buffer(buffer, 0, &readback, 0, buffer.size());
    gpu.queue.submit([encoder.finish()]);
    map_read(gpu, &readback)
}

fn map_read<T: bytemuck::Pod>(gpu: &Gpu, readback: &wgpu::Buffer) -> Result<Vec<T>, GpuError> {
    let slice = readback.slice(..);
    let (sender, receiver) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |result| {
        let _ = sender.send(result);
    });
    gpu.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Device(format!("waiting for the device: {e}")))?;
    receiver
        .recv()
        .map_err(|e| GpuError::Device(e.to_string()))?
        .map_err(|e| GpuError::Device(format!("reading a buffer back: {e}")))?;
    let values = {
        let view = slice.get_mapped_range().map_err(|e| GpuError::Device(format!("{e:?}")))?;
        bytemuck::cast_slice(&view).to_vec()
    };
    readback.unmap();
    Ok(values)
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
    for b in binding::INSTANCES..=binding::LIGHTS {
        entries.push(entry(b, wgpu::BufferBindingType::Storage { read_only: true }));
    }
    for b in [binding::SAMPLES, binding::ACCUM, binding::FAULTS] {
        entries.push(entry(b, wgpu::BufferBindingType::Storage { read_only: false }));
    }
    for b in [binding::MOTIONS, binding::CSG_NODES] {
        entries.push(entry(b, wgpu::BufferBindingType::Storage { read_only: true }));
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

/// Renders `scene` to completion on `gpu`, as the CPU's `glint_core::render::render`
/// does: uniformly, reporting progress in samples per pixel (`done`, `total`) after
/// each pass, or adaptively, reporting finished pixels after each round; stops between
/// passes when `cancel` is set. The statistics count no rays (the GPU does not).
pub fn render(
    gpu: &Gpu,
    scene: &RenderScene,
    progress: &dyn Fn(usize, usize),
    cancel: &AtomicBool,
) -> Result<(Image, RenderStats), GpuRenderError> {
    let mut film = Progressive::new(gpu, scene)?;
    if scene.settings.adaptive.is_some() {
        film.sample_adaptively(progress, cancel)?;
    } else {
        let total = scene.settings.spp;
        while film.samples_done() < total {
            if cancel.load(Ordering::Relaxed) {
                return Err(GpuRenderError::Cancelled);
            }
            film.add_samples((total - film.samples_done()).min(film.capacity))?;
            progress(film.samples_done() as usize, total as usize);
        }
    }
    let stats = RenderStats {
        rays: 0,
        samples_per_pixel: film.samples_per_pixel()?,
        aovs: film.aovs()?,
        non_finite: film.non_finite()?,
    };
    Ok((film.image()?, stats))
}
