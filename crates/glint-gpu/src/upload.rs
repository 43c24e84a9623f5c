//! The compiled scene in GPU buffers, built from the same arrays the CPU renders:
//! records uploaded as they are, meshes concatenated (their BVH nodes after the
//! instance BVH's, their packets, vertices and indices one after another) with
//! per-mesh offsets, and every plain number array in one float or one word buffer.

use bytemuck::{NoUninit, Zeroable};
use glam::{Mat3, Mat4, Vec3};
use glint_core::desc::{Features, IntegratorDesc, SamplerKind};
use glint_core::sampling::SamplePattern;
use glint_core::scene::RenderScene;
use glint_core::shape::{CsgOp, ShapeKind};
use wgpu::util::DeviceExt;

use crate::device::{Gpu, GpuError};
use crate::records::{self, GpuMesh, NONE, Params};

/// The scene's buffers on the device, and the parameters every pass starts from.
pub struct GpuScene {
    pub(crate) buffers: SceneBuffers,
    pub(crate) params: Params,
}

pub(crate) struct SceneBuffers {
    pub instances: wgpu::Buffer,
    pub nodes: wgpu::Buffer,
    pub packets: wgpu::Buffer,
    pub meshes: wgpu::Buffer,
    pub bsdfs: wgpu::Buffer,
    pub emitters: wgpu::Buffer,
    pub floats: wgpu::Buffer,
    pub words: wgpu::Buffer,
    pub textures: wgpu::Buffer,
    pub motions: wgpu::Buffer,
    pub csg_nodes: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    pub lights: wgpu::Buffer,
}

/// What this adapter cannot render of a scene the GPU backend renders, as a clause;
/// `None` when it can: implicit surfaces and blobs need more loop iterations than a
/// driver that caps them allows ([`Gpu::caps_loop_iterations`]).
pub fn beyond_adapter(gpu: &Gpu, scene: &RenderScene) -> Option<String> {
    let solved = shape_kinds(scene).any(|k| matches!(k, ShapeKind::Implicit | ShapeKind::Blob));
    (solved && gpu.caps_loop_iterations()).then(|| {
        format!(
            "its driver stops a kernel's loops after {} iterations in all, fewer than implicit surfaces and \
             blobs need; render with --device cpu",
            crate::device::LOOP_CAP
        )
    })
}

/// The kind of every shape the kernels may meet: each instance's and each CSG leaf's.
pub(crate) fn shape_kinds(scene: &RenderScene) -> impl Iterator<Item = ShapeKind> + '_ {
    let leaves = scene.shape_tables.csg_nodes.iter().filter(|n| n.op == CsgOp::Leaf).map(|n| n.shape.kind);
    scene.instances.iter().map(|i| i.shape.kind).chain(leaves)
}

/// The flat arrays before upload.
#[derive(Default)]
struct Arrays {
    nodes: Vec<u8>,
    packets: Vec<u8>,
    meshes: Vec<GpuMesh>,
    floats: Vec<f32>,
    words: Vec<u32>,
}

impl Arrays {
    fn push_floats(&mut self, values: impl IntoIterator<Item = f32>) -> u32 {
        let at = self.floats.len() as u32;
        self.floats.extend(values);
        at
    }

    fn push_vec3s(&mut self, values: &[Vec3]) -> u32 {
        self.push_floats(values.iter().flat_map(|v| v.to_array()))
    }
}

impl GpuScene {
    /// Uploads `scene`, or says why it cannot be rendered on this GPU.
    pub fn new(gpu: &Gpu, scene: &RenderScene) -> Result<GpuScene, GpuError> {
        let mut a = Arrays::default();
        a.nodes.extend_from_slice(bytemuck::cast_slice(&scene.bvh.nodes));
        let record = std::mem::size_of::<glint_core::accel::WideNode>();
        for mesh in &scene.meshes {
            let node_offset = (a.nodes.len() / record) as u32;
            a.nodes.extend_from_slice(bytemuck::cast_slice(&mesh.bvh.nodes));
            let packet_offset = (a.packets.len() / std::mem::size_of::<glint_core::mesh::Triangle4>()) as u32;
            a.packets.extend_from_slice(bytemuck::cast_slice(&mesh.packets));
            let position_offset = a.push_vec3s(&mesh.positions);
            let normal_offset = if mesh.normals.is_empty() { NONE } else { a.push_vec3s(&mesh.normals) };
            let uv_offset =
                if mesh.uvs.is_empty() { NONE } else { a.push_floats(mesh.uvs.iter().flat_map(|v| v.to_array())) };
            let color_offset = if mesh.colors.is_empty() { NONE } else { a.push_vec3s(&mesh.colors) };
            let index_offset = a.words.len() as u32;
            a.words.extend(mesh.triangles.iter().flatten());
            a.meshes.push(GpuMesh {
                node_offset,
                packet_offset,
                position_offset,
                index_offset,
                normal_offset,
                uv_offset,
                node_count: mesh.bvh.nodes.len() as u32,
                color_offset,
            });
        }
        let texel_offset = a.push_vec3s(&scene.texels);
        let instance_emitter_offset = a.words.len() as u32;
        a.words.extend_from_slice(&scene.instance_emitters);
        let params = params(scene, &mut a, texel_offset, instance_emitter_offset);

        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let buffer = |what: &'static str, bytes: &[u8]| -> Result<wgpu::Buffer, GpuError> {
            if bytes.len() as u64 > limit {
                return Err(GpuError::TooLarge { what, needed: bytes.len() as u64, limit });
            }
            // Bindings cannot be empty, and must hold one whole record: an unused
            // array gets zeros enough for the largest record.
            let padded;
            let contents = if bytes.is_empty() {
                padded = vec![0u8; crate::records::ALL.iter().map(|r| r.size).max().unwrap_or(0).max(256)];
                &padded[..]
            } else {
                bytes
            };
            Ok(gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(what),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            }))
        };
        let buffers = SceneBuffers {
            instances: buffer("instances", records_bytes(&scene.instances))?,
            nodes: buffer("BVH nodes", &a.nodes)?,
            packets: buffer("triangle packets", &a.packets)?,
            meshes: buffer("mesh records", bytemuck::cast_slice(&a.meshes))?,
            bsdfs: buffer("materials", records_bytes(&scene.bsdfs))?,
            emitters: buffer("emitters", records_bytes(&scene.emitters))?,
            floats: buffer("vertices, textures and tables", bytemuck::cast_slice(&a.floats))?,
            words: buffer("triangle indices, instance emitters and implicit programs", bytemuck::cast_slice(&a.words))?,
            textures: buffer("textures", records_bytes(&scene.textures))?,
            motions: buffer("motions", records_bytes(&scene.motions))?,
            csg_nodes: buffer("CSG nodes", records_bytes(&scene.shape_tables.csg_nodes))?,
            materials: buffer("Whitted materials", records_bytes(&scene.materials))?,
            lights: buffer("lights", records_bytes(&scene.lights))?,
        };
        Ok(GpuScene { buffers, params })
    }
}

/// The Whitted feature switches as [`Params::features`] bits.
fn features(f: Features) -> u32 {
    let bit = |on: bool, bit: u32| if on { bit } else { 0 };
    bit(f.shadows, records::FEATURE_SHADOWS)
        | bit(f.reflections, records::FEATURE_REFLECTIONS)
        | bit(f.refractions, records::FEATURE_REFRACTIONS)
        | bit(f.textures, records::FEATURE_TEXTURES)
        | bit(f.transparent_shadows, records::FEATURE_TRANSPARENT_SHADOWS)
}

fn records_bytes<T: NoUninit>(records: &[T]) -> &[u8] {
    bytemuck::cast_slice(records)
}

fn vec4(v: Vec3) -> [f32; 4] {
    v.extend(0.0).to_array()
}

fn mat4(m: Mat3) -> Mat4 {
    Mat4::from_mat3(m)
}

/// The per-scene part of the pass parameters; the light and environment tables go
/// into the float array on the way.
fn params(scene: &RenderScene, a: &mut Arrays, texel_offset: u32, instance_emitter_offset: u32) -> Params {
    let s = &scene.settings;
    let (emitter_count, light_cdf_offset) = match &scene.light_selection {
        Some(selection) => (selection.len() as u32, a.push_floats(selection.cdf().iter().copied())),
        None => (0, 0),
    };
    let mut p = Params {
        width: s.width,
        height: s.height,
        sample_offset: 0,
        pass_samples: 0,
        bounded_count: scene.bounded_count as u32,
        instance_count: scene.instances.len() as u32,
        emitter_count,
        light_cdf_offset,
        environment_emitter: scene.environment_emitter,
        environment_kind: 0,
        env_width: 0,
        env_height: 0,
        env_texel_offset: 0,
        env_cdf_offset: 0,
        filter_kind: s.filter.kind as u32,
        filter_radius: s.filter.radius,
        filter_scale: s.filter.normalization(),
        node_count: scene.bvh.nodes.len() as u32,
        texel_offset,
        instance_emitter_offset,
        has_transmissive: scene.has_transmissive as u32,
        light_count: scene.lights.len() as u32,
        quadric_offset: a.push_floats(
            scene
                .shape_tables
                .quadrics
                .iter()
                .flat_map(|q| q.coefficients.into_iter().chain(q.min.to_array()).chain(q.max.to_array())),
        ),
        has_motion: (!scene.motions.is_empty()) as u32,
        superellipsoid_offset: a.push_floats(scene.shape_tables.superellipsoids.iter().flat_map(|s| [s.e1, s.e2])),
        implicit_offset: push_implicits(scene, a),
        blob_offset: push_blobs(scene, a),
        aovs: s.aovs as u32,
        env_scale: [0.0; 4],
        env_from_world: Mat4::IDENTITY,
        world_from_env: Mat4::IDENTITY,
        ..Params::zeroed()
    };
    set_view(&mut p, scene);
    if let Some(env) = &scene.environment {
        p.env_scale = vec4(env.scale);
        p.env_from_world = mat4(env.env_from_world);
        p.world_from_env = mat4(env.world_from_env);
        p.environment_kind = 1;
        if let Some(dist) = env.distribution() {
            p.environment_kind = 2;
            p.env_width = env.width as u32;
            p.env_height = env.height as u32;
            p.env_texel_offset = a.push_vec3s(&env.texels);
            let (marginal, rows) = dist.parts();
            p.env_cdf_offset = a.push_floats(marginal.cdf().iter().copied());
            for row in rows {
                a.push_floats(row.cdf().iter().copied());
            }
        }
    }
    p
}

/// The implicit surfaces' programs into the word array as (opcode, argument bits)
/// pairs, then their records (implicit.wgsl's `ImplicitRecord`: min, max and the
/// Lipschitz bound as float bits, the first pair's word index, the pair count);
/// returns the records' word index.
fn push_implicits(scene: &RenderScene, a: &mut Arrays) -> u32 {
    let tables = &scene.shape_tables;
    let code_at = a.words.len() as u32;
    a.words.extend(tables.implicit_code.iter().flat_map(|op| [op.code as u32, op.arg.to_bits()]));
    let records_at = a.words.len() as u32;
    for r in &tables.implicits {
        push_box_record(a, (r.min, r.max, r.lipschitz), code_at + 2 * r.first, r.len);
    }
    records_at
}

/// One record of a shape solved in its box, as implicit.wgsl reads it from the word
/// array: the box and one parameter as float bits, then where its run of data starts
/// and how long it is (integers stay words: as floats, small ones would be denormals,
/// which a device may flush to zero).
fn push_box_record(a: &mut Arrays, (min, max, parameter): (Vec3, Vec3, f32), first: u32, count: u32) {
    let floats = min.to_array().into_iter().chain(max.to_array()).chain([parameter]);
    a.words.extend(floats.map(f32::to_bits));
    a.words.extend([first, count]);
}

/// The blobs' components into the float array (implicit.wgsl's `BlobComponent`), then
/// their records into the word array (`BlobRecord`: min, max and threshold as float
/// bits, the first component's float index, the component count); returns the
/// records' word index.
fn push_blobs(scene: &RenderScene, a: &mut Arrays) -> u32 {
    let tables = &scene.shape_tables;
    let components = tables.blob_components.iter().flat_map(|c| {
        let m = c.component_from_blob.to_cols_array();
        m.into_iter().chain(c.offset.to_array()).chain([c.strength, c.half_length])
    });
    let components_at = a.push_floats(components.collect::<Vec<_>>());
    let records_at = a.words.len() as u32;
    for b in &tables.blobs {
        push_box_record(a, (b.min, b.max, b.threshold), components_at + 14 * b.first, b.count);
    }
    records_at
}

/// The pass parameters a viewer changes between renders of one uploaded scene: the
/// camera, the integrator and its depth, the sampler and seed, the effect switches and
/// the background.
pub(crate) fn set_view(p: &mut Params, scene: &RenderScene) {
    let s = &scene.settings;
    let (integrator, path, max_depth) = match s.integrator {
        IntegratorDesc::Path(path) => (records::INTEGRATOR_PATH, path, path.max_depth),
        IntegratorDesc::Whitted => (records::INTEGRATOR_WHITTED, Default::default(), s.max_depth),
    };
    p.integrator = integrator;
    p.seed = s.seed;
    p.sampler = (path.sampler == SamplerKind::Independent) as u32;
    p.max_depth = max_depth;
    p.rr_depth = path.rr_depth;
    p.min_contribution = s.min_contribution;
    p.features = features(s.features);
    // Adaptive sampling stops a pixel after any doubling: only Sobol points stay
    // stratified at every power of two (glint_core::render::adaptive_tile).
    let pattern = if s.adaptive.is_some() { SamplePattern::Sobol } else { s.sampler.pattern };
    p.pattern = match pattern {
        SamplePattern::Grid => records::PATTERN_GRID,
        SamplePattern::CornersAndCentre => records::PATTERN_CORNERS,
        SamplePattern::Jittered => records::PATTERN_JITTERED,
        SamplePattern::Sobol => records::PATTERN_SOBOL,
    };
    p.per_axis = s.sampler.per_axis;
    p.pattern_seed = s.sampler.seed;
    p.background = vec4(s.background);
    p.ambient = vec4(s.ambient_light);
    let c = &scene.camera;
    (p.aperture_radius, p.focal_distance) = (c.aperture_radius, c.focal_distance);
    (p.eye, p.right, p.up, p.forward) = (vec4(c.eye), vec4(c.right), vec4(c.up), vec4(c.forward));
    p.world_from_canonical = c.world_from_canonical;
    let spacing = glint_core::footprint::PixelSpacing::new(c, s.width, s.height, 1.0);
    (p.pixel_dx, p.pixel_dy) = (spacing.dx.extend(s.footprint_scale).to_array(), vec4(spacing.dy));
}
