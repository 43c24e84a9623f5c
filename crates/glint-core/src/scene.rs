//! The compiled render scene and [`compile`], which builds it from a [`SceneDesc`].

use std::borrow::Cow;

use bytemuck::NoUninit;
use glam::{Mat4, Vec2, Vec3};

use crate::accel::lanes::{Lanes, Portable};
use crate::accel::{Bvh, Order, WideBvh};
use crate::bsdf::Bsdf;
use crate::camera::Camera;
use crate::desc::{
    AdaptiveDesc, Features, IntegratorDesc, NodeDesc, NodeKind, SceneDesc, ShapeDesc, TextureDesc, TransformOp,
};
use crate::emitter::{Emitter, Environment};
use crate::footprint::PixelSpacing;
use crate::light::Light;
use crate::material::{Material, NO_TEXTURE};
use crate::math::{Aabb, Ray, Transform, offset_ray_origin};
use crate::mesh::Mesh;
use crate::sampling::{Filter, PixelSampler};
use crate::shape::{Primitive, Shape, ShapeKind, ShapeTables};

mod few;
mod lighting;
mod motion;
mod packet;
mod solids;

use crate::texture::Texture;
pub use few::{FewObjects, NO_OBJECT, RayWave, WAVE, WaveHits};
pub use motion::{Motion, NO_MOTION, Pose};

/// One placed primitive: the shape, where it is (`M` and `M⁻¹`) and what it is made of.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, NoUninit)]
pub struct Instance {
    pub transform: Transform,
    pub shape: Shape,
    pub material: u32,
    /// Index into [`RenderScene::motions`], or [`NO_MOTION`] for an instance that stays put.
    pub motion: u32,
}

/// The render settings after validation.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    pub width: u32,
    pub height: u32,
    pub samples_per_axis: u32,
    pub max_depth: u32,
    pub min_contribution: f32,
    pub background: Vec3,
    pub ambient_light: Vec3,
    pub features: Features,
    pub sampler: PixelSampler,
    pub filter: Filter,
    pub adaptive: Option<AdaptiveDesc>,
    pub seed: u32,
    /// Which light-transport algorithm renders the image.
    pub integrator: IntegratorDesc,
    /// Camera samples per pixel (before adaptive refinement).
    pub spp: u32,
    /// Also accumulate albedo, normal and depth images (off unless a caller asks).
    pub aovs: bool,
    /// The pixel footprint filtered textures average over, as a fraction of a pixel
    /// ([`crate::footprint::footprint_scale`] of `spp`). A renderer that accumulates
    /// passes of one sample each narrows it pass by pass, as if they were one image's
    /// samples.
    pub footprint_scale: f32,
}

impl Settings {
    /// The footprint for sample `index` of a pixel. Adaptive sampling cannot know how
    /// many samples a pixel will take, so sample k is filtered as one of k + 1: a pixel
    /// that stops at one sample is filtered over its whole area, one that goes on to
    /// many converges to the narrow footprint of many samples.
    pub fn sample_footprint(&self, index: u32) -> f32 {
        match self.adaptive {
            Some(_) => crate::footprint::footprint_scale(index + 1),
            None => self.footprint_scale,
        }
    }
}

/// Everything a backend needs, as flat arrays of plain records.
///
/// `instances[..bounded_count]` are ordered as the BVH's leaves expect; the rest are
/// unbounded (infinite planes) and tested against every ray.
#[derive(Clone, Debug)]
pub struct RenderScene {
    pub settings: Settings,
    pub camera: Camera,
    pub instances: Vec<Instance>,
    pub bounded_count: usize,
    pub bvh: WideBvh,
    /// Triangle meshes, each stored once; instances of kind `Mesh` index into it.
    pub meshes: Vec<Mesh>,
    /// Flat records of CSG trees, blobs, implicit surfaces, quadrics and
    /// superellipsoids; their instances' shapes index into it.
    pub shape_tables: ShapeTables,
    /// How moving instances move; `Instance::motion` indexes into it.
    pub motions: Vec<Motion>,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub textures: Vec<Texture>,
    pub texels: Vec<Vec3>,
    /// True when some material lets light through, so shadow rays must look past hits.
    pub has_transmissive: bool,
    /// True when some material casts no shadow, so shadow rays check each instance's.
    pub has_shadowless: bool,
    /// The physically based reading of each material (same index), with its emission.
    pub bsdfs: Vec<Bsdf>,
    /// Everything the path tracer samples light from: area emitters, point, spot and
    /// directional lights, and a record standing for the environment.
    pub emitters: Vec<Emitter>,
    /// Per instance, its first emitter or [`crate::emitter::NO_EMITTER`].
    pub instance_emitters: Vec<u32>,
    /// Chooses an emitter in proportion to its power; `None` without emitters.
    pub light_selection: Option<crate::sampling::Distribution1D>,
    pub environment: Option<Environment>,
    /// Index of the environment's record in `emitters`.
    pub environment_emitter: u32,
    /// The instances as eight-ray lanes read them, when the scene is a handful of
    /// analytic objects: the path tracer then traces waves of rays through them.
    pub few_objects: Option<FewObjects>,
}

/// The closest intersection, with world-space surface data.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    /// The hit point, computed as `M·Q` from the refined object-space point `Q`.
    pub point: Vec3,
    /// Unit world-space normal `(M⁻¹)ᵀ∇f`, pointing out of the solid: the shading
    /// normal (interpolated on meshes), for lighting.
    pub normal: Vec3,
    /// Unit normal of the true surface (the triangle's plane on meshes), on the same
    /// side as `normal`: for offsetting secondary rays and deciding inside/outside.
    pub geometric_normal: Vec3,
    /// Where shadow rays leaving the outside should start: `point`, except on smooth
    /// meshes, where it is lifted toward the surface the normals describe
    /// ([`crate::mesh::MeshSurface::shadow_point`]).
    pub shadow_point: Vec3,
    pub uv: Vec2,
    /// The vertex colour at the hit (white where the surface has none): it multiplies
    /// the material's diffuse or base colour.
    pub color: Vec3,
    pub material: u32,
    /// Which instance was hit, and which part of it (a mesh's triangle, a cube's face).
    pub instance: u32,
    pub part: u32,
}

/// Why a scene description cannot be rendered; `origin` says where it came from.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CompileError {
    #[error("{origin}: {message}")]
    Invalid { origin: String, message: String },
}

fn invalid(origin: &str, message: impl Into<String>) -> CompileError {
    CompileError::Invalid {
        origin: if origin.is_empty() { "scene".into() } else { origin.into() },
        message: message.into(),
    }
}

/// Largest image side and pixel count accepted: beyond this the film alone would not fit
/// in memory of any machine we target.
pub const MAX_IMAGE_SIDE: u32 = 65_536;
pub const MAX_PIXELS: u64 = 1 << 28;

/// Flattens the transform tree, resolves indices, validates every number and builds the
/// BVH. Degenerate input (zero scale, NaN, a camera looking along its up vector, …) is
/// rejected here with a message naming the object, never discovered mid-render.
pub fn compile(desc: &SceneDesc) -> Result<RenderScene, CompileError> {
    let settings = compile_settings(desc)?;
    let camera = Camera::new(&desc.camera, settings.width as f32 / settings.height as f32)
        .filter(|_| finite_camera(desc))
        .ok_or_else(|| {
            invalid(
                "camera",
                "eye, look and up must be finite, look and up non-zero and not parallel, and 0 < fov < 180",
            )
        })?;

    for t in &desc.textures {
        if let TextureDesc::Image { name, width, height, texels, .. } = t
            && (*width == 0 || *height == 0 || texels.len() as u64 != u64::from(*width) * u64::from(*height))
        {
            let message = format!("image texture of {width}×{height} texels holds {} of them", texels.len());
            return Err(invalid(name, message));
        }
    }
    let mut texels = Vec::new();
    let textures: Vec<Texture> = desc.textures.iter().map(|t| Texture::compile(t, &mut texels)).collect();
    let materials: Vec<Material> = desc
        .materials
        .iter()
        .map(|m| {
            let texture = m.texture.map(|i| i as u32);
            if texture.is_some_and(|i| i as usize >= textures.len()) {
                return Err(invalid(&m.name, "texture index out of range"));
            }
            if m.emission_texture.is_some_and(|t| t >= textures.len()) {
                return Err(invalid(&m.name, "its emission texture index is out of range"));
            }
            if m.normal_map.is_some_and(|n| n.texture >= textures.len() || !n.scale.is_finite()) {
                return Err(invalid(&m.name, "its normal map names no texture, or its scale is not finite"));
            }
            let mat = Material::compile(m, texture);
            let numbers = [mat.ambient, mat.diffuse, mat.specular, mat.reflective, mat.transmissive];
            let finite = numbers.iter().all(|v| v.is_finite()) && mat.shininess.is_finite() && mat.ior.is_finite();
            if !(finite && mat.ior > 0.0) {
                return Err(invalid(&m.name, "material values must be finite numbers and ior > 0"));
            }
            Ok(mat)
        })
        .collect::<Result<_, _>>()?;
    let lights = desc.lights.iter().filter_map(Light::compile).collect::<Vec<_>>();
    if lights.iter().any(|l| {
        !(l.color.is_finite()
            && l.position.is_finite()
            && l.direction.is_finite()
            && l.attenuation.is_finite()
            && l.outer_angle.is_finite()
            && l.inner_angle.is_finite())
    }) {
        return Err(invalid("lights", "light values must be finite and directions non-zero"));
    }

    let meshes: Vec<Mesh> = desc
        .meshes
        .iter()
        .map(|m| Mesh::compile(m).map_err(|e| invalid(&format!("mesh '{}'", m.name), e.to_string())))
        .collect::<Result<_, _>>()?;
    let mut shape_tables = ShapeTables::default();
    let mut flattener = Flattener {
        material_count: desc.materials.len(),
        instances: Vec::new(),
        motions: Vec::new(),
        tables: &mut shape_tables,
    };
    for node in &desc.objects {
        flattener.flatten(node, &Transform::IDENTITY, None)?;
    }
    let Flattener { instances: flat, motions, .. } = flattener;
    if let Some(inst) =
        flat.iter().find(|i| i.shape.kind == ShapeKind::Mesh && i.shape.mesh_index() as usize >= meshes.len())
    {
        let message = format!("mesh index {} out of range ({} meshes)", inst.shape.mesh_index(), meshes.len());
        return Err(invalid("mesh instance", message));
    }
    let world_bounds = |inst: &Instance| instance_bounds(inst, &meshes, &shape_tables, &motions);
    let (bounded, unbounded): (Vec<_>, Vec<_>) = flat.into_iter().partition(|inst| world_bounds(inst).is_finite());
    let boxes: Vec<Aabb> = bounded.iter().map(world_bounds).collect();
    let (binary, order) = Bvh::build(&boxes);
    let bvh = WideBvh::from_binary(&binary);
    let bounded_count = bounded.len();
    let mut instances: Vec<Instance> = order.iter().map(|&i| bounded[i as usize]).collect();
    instances.extend(unbounded);

    let has_transmissive = materials.iter().any(Material::is_transmissive);
    for m in &desc.materials {
        validate_bsdf(m, desc.textures.len())?;
    }
    let bsdfs: Vec<Bsdf> = desc.materials.iter().map(Bsdf::compile).collect();
    let has_shadowless = desc.materials.iter().any(|m| !m.casts_shadows);
    let lighting = lighting::compile(desc, &instances, &meshes, &bsdfs, bvh.bounds())?;
    let mut scene = RenderScene {
        settings,
        camera,
        instances,
        bounded_count,
        bvh,
        meshes,
        shape_tables,
        motions,
        materials,
        lights,
        textures,
        texels,
        has_transmissive,
        has_shadowless,
        bsdfs,
        emitters: lighting.emitters,
        instance_emitters: lighting.instance_emitters,
        light_selection: lighting.selection,
        environment: lighting.environment,
        environment_emitter: lighting.environment_emitter,
        few_objects: None,
    };
    scene.few_objects = FewObjects::of(&scene);
    Ok(scene)
}

/// A material's physically based parameters make sense: finite, non-negative colours and
/// roughness, positive indices, textures that exist, emission that is finite and ≥ 0.
fn validate_bsdf(m: &crate::desc::MaterialDesc, texture_count: usize) -> Result<(), CompileError> {
    use crate::desc::BsdfDesc;
    let colour = |c: Vec3| c.is_finite() && c.min_element() >= 0.0;
    let texture_ok = |t: Option<usize>| t.is_none_or(|i| i < texture_count);
    let ior_ok = |a: f32, b: f32| a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0;
    let alpha_ok = |a: crate::desc::ScalarParam| a.value.is_finite() && a.value >= 0.0 && texture_ok(a.texture);
    let valid = match m.bsdf {
        None => true,
        Some(BsdfDesc::Diffuse { reflectance }) => colour(reflectance.value) && texture_ok(reflectance.texture),
        Some(BsdfDesc::Conductor { eta, k, specular, alpha }) => {
            colour(eta) && colour(k) && colour(specular.value) && texture_ok(specular.texture) && alpha_ok(alpha)
        }
        Some(BsdfDesc::Dielectric { int_ior, ext_ior, reflectance, transmittance, alpha }) => {
            ior_ok(int_ior, ext_ior) && colour(reflectance) && colour(transmittance) && alpha_ok(alpha)
        }
        Some(BsdfDesc::ThinDielectric { int_ior, ext_ior, reflectance, transmittance }) => {
            ior_ok(int_ior, ext_ior) && colour(reflectance) && colour(transmittance)
        }
        Some(BsdfDesc::Plastic { diffuse, int_ior, ext_ior, specular, alpha, .. }) => {
            colour(diffuse.value)
                && texture_ok(diffuse.texture)
                && ior_ok(int_ior, ext_ior)
                && colour(specular)
                && alpha_ok(alpha)
        }
        Some(BsdfDesc::MetallicRoughness { base, metallic, alpha, ior }) => {
            colour(base.value)
                && texture_ok(base.texture)
                && (0.0..=1.0).contains(&metallic.value)
                && texture_ok(metallic.texture)
                && alpha_ok(alpha)
                && ior_ok(ior, 1.0)
        }
    };
    if !valid {
        return Err(invalid(
            &m.name,
            "BSDF values must be finite, colours and roughness >= 0, metallic in [0, 1], indices of refraction > 0, and textures must exist",
        ));
    }
    if !colour(m.emission) {
        return Err(invalid(&m.name, "emission must be finite and >= 0"));
    }
    Ok(())
}

/// The thin-lens parameters make sense.
fn lens_valid(desc: &SceneDesc) -> bool {
    let c = &desc.camera;
    c.aperture_radius >= 0.0 && c.aperture_radius.is_finite() && c.focal_distance > 0.0 && c.focal_distance.is_finite()
}

fn finite_camera(desc: &SceneDesc) -> bool {
    let c = &desc.camera;
    c.eye.is_finite() && c.look.is_finite() && c.up.is_finite() && c.fov_y_degrees > 0.0 && c.fov_y_degrees < 180.0
}

fn compile_settings(desc: &SceneDesc) -> Result<Settings, CompileError> {
    let s = &desc.settings;
    let pixels = s.width as u64 * s.height as u64;
    if s.width == 0 || s.height == 0 || s.width > MAX_IMAGE_SIDE || s.height > MAX_IMAGE_SIDE || pixels > MAX_PIXELS {
        return Err(invalid(
            "settings",
            format!(
                "image size {}x{} is out of range (1..={MAX_IMAGE_SIDE} per side, at most {MAX_PIXELS} pixels)",
                s.width, s.height
            ),
        ));
    }
    if !(1..=64).contains(&s.samples_per_axis) {
        return Err(invalid("settings", format!("samples per axis {} is out of range 1..=64", s.samples_per_axis)));
    }
    if !(s.background.is_finite() && s.ambient_light.is_finite() && s.min_contribution.is_finite()) {
        return Err(invalid("settings", "background, ambient and min_contribution must be finite"));
    }
    let filter = Filter::new(s.filter.kind, s.filter.radius).ok_or_else(|| {
        invalid("settings", format!("filter radius {} is out of range (0, 8] pixels", s.filter.radius))
    })?;
    if let Some(a) = s.adaptive
        && !(a.min_samples >= 1 && a.max_samples >= a.min_samples && a.max_samples <= 4096 && a.threshold >= 0.0)
    {
        return Err(invalid(
            "settings",
            "adaptive sampling needs 1 <= min_samples <= max_samples <= 4096 and a threshold >= 0",
        ));
    }
    if !lens_valid(desc) {
        return Err(invalid("camera", "aperture_radius must be >= 0 and focal_distance > 0"));
    }
    let (pattern, per_axis, spp) = sample_counts(s)?;
    Ok(Settings {
        width: s.width,
        height: s.height,
        samples_per_axis: per_axis,
        max_depth: s.max_depth.min(64),
        min_contribution: s.min_contribution.max(0.0),
        background: s.background,
        ambient_light: s.ambient_light,
        features: s.features,
        sampler: PixelSampler { pattern, per_axis, seed: s.seed },
        filter,
        adaptive: s.adaptive,
        seed: s.seed,
        integrator: s.integrator,
        spp,
        aovs: false,
        footprint_scale: crate::footprint::footprint_scale(spp),
    })
}

/// Most samples per pixel `spp` accepts.
pub const MAX_SPP: u32 = 1 << 20;

/// The pixel pattern, samples per axis and samples per pixel. `spp`, when set, wins:
/// a square count keeps the pattern as an n×n grid, any other count takes Sobol points.
fn sample_counts(s: &crate::desc::RenderSettings) -> Result<(crate::sampling::SamplePattern, u32, u32), CompileError> {
    use crate::sampling::SamplePattern;
    let Some(spp) = s.spp else {
        let count =
            if s.pattern == SamplePattern::CornersAndCentre { 5 } else { s.samples_per_axis * s.samples_per_axis };
        return Ok((s.pattern, s.samples_per_axis, count));
    };
    if !(1..=MAX_SPP).contains(&spp) {
        return Err(invalid("settings", format!("spp {spp} is out of range 1..={MAX_SPP}")));
    }
    let root = (spp as f64).sqrt().round() as u32;
    if root * root == spp && root <= 64 && s.pattern != SamplePattern::CornersAndCentre {
        Ok((s.pattern, root, spp))
    } else {
        Ok((SamplePattern::Sobol, root.clamp(1, 64), spp))
    }
}

/// The transform a node's ops make, first op acting on the object first.
fn node_transform(ops: &[TransformOp], origin: &str) -> Result<Transform, CompileError> {
    ops.iter().try_fold(Transform::IDENTITY, |acc, op| {
        let t = match *op {
            TransformOp::Translate(v) => v.is_finite().then(|| Transform::translate(v)),
            TransformOp::Scale(s) => Transform::scale(s),
            TransformOp::Rotate { axis, degrees } => {
                if degrees.is_finite() && axis.is_finite() {
                    Transform::rotate(axis, degrees)
                } else {
                    None
                }
            }
            TransformOp::Matrix(rows) => Transform::from_matrix(Mat4::from_cols_array_2d(&rows).transpose()),
        };
        let t = t.ok_or_else(|| invalid(origin, format!("transform {op:?} is not invertible or not finite")))?;
        Ok(acc.then(&t))
    })
}

/// Collects the instances of the transform tree.
struct Flattener<'a> {
    material_count: usize,
    instances: Vec<Instance>,
    motions: Vec<Motion>,
    tables: &'a mut ShapeTables,
}

/// A moving node the nodes being flattened are inside: where it is and its two poses.
struct MovingNode {
    outer: Transform,
    open: Transform,
    open_pose: Pose,
    close_pose: Pose,
}

impl Flattener<'_> {
    /// Flattens `node` under `parent`: the accumulated transform to world space, or to
    /// the enclosing moving node's space when `moving` is set.
    fn flatten(
        &mut self,
        node: &NodeDesc,
        parent: &Transform,
        moving: Option<&MovingNode>,
    ) -> Result<(), CompileError> {
        let local = node_transform(&node.transform, &node.origin)?;
        let transform = local.then(parent);
        if !(transform.world_from_object.is_finite() && transform.object_from_world.is_finite()) {
            return Err(invalid(&node.origin, "the accumulated transform overflows"));
        }
        match &node.kind {
            NodeKind::Group(children) => {
                for child in children {
                    self.flatten(child, &transform, moving)?;
                }
            }
            NodeKind::Shape { shape, material } => {
                if *material >= self.material_count {
                    return Err(invalid(&node.origin, format!("material index {material} out of range")));
                }
                let shape = shape_record(shape, &node.origin)?;
                self.place(Instance { transform, shape, material: *material as u32, motion: NO_MOTION }, moving);
            }
            NodeKind::Solid(solid) => {
                // An empty solid (disjoint intersection) places nothing.
                if let Some((shape, material)) =
                    solids::compile_solid(solid, &node.origin, self.material_count, self.tables)?
                {
                    self.place(Instance { transform, shape, material, motion: NO_MOTION }, moving);
                }
            }
            NodeKind::Moving { close, children } => {
                if moving.is_some() {
                    return Err(invalid(&node.origin, "a moving node cannot be inside another moving node"));
                }
                let close = node_transform(close, &node.origin)?;
                let (Some(open_pose), Some(close_pose)) = (Pose::from_transform(&local), Pose::from_transform(&close))
                else {
                    return Err(invalid(
                        &node.origin,
                        "a moving node's poses must be scale, rotation and translation (no shear)",
                    ));
                };
                if (open_pose.scale * close_pose.scale).cmple(Vec3::ZERO).any() {
                    return Err(invalid(
                        &node.origin,
                        "a moving node's scale cannot change sign (it would pass through zero)",
                    ));
                }
                let frame = MovingNode { outer: *parent, open: local, open_pose, close_pose };
                for child in children {
                    self.flatten(child, &Transform::IDENTITY, Some(&frame))?;
                }
            }
        }
        Ok(())
    }

    /// Adds an instance whose transform is relative to `moving` (if any).
    fn place(&mut self, mut instance: Instance, moving: Option<&MovingNode>) {
        if let Some(m) = moving {
            let inner = instance.transform;
            instance.transform = inner.then(&m.open).then(&m.outer);
            instance.motion = self.motions.len() as u32;
            self.motions.push(Motion { inner, outer: m.outer, open: m.open_pose, close: m.close_pose });
        }
        self.instances.push(instance);
    }
}

/// The record of a canonical primitive, its parameters validated.
fn shape_record(shape: &ShapeDesc, origin: &str) -> Result<Shape, CompileError> {
    Ok(match *shape {
        ShapeDesc::Sphere => Shape::new(ShapeKind::Sphere),
        ShapeDesc::Cube => Shape::new(ShapeKind::Cube),
        ShapeDesc::Cylinder => Shape::new(ShapeKind::Cylinder),
        ShapeDesc::Cone => Shape::new(ShapeKind::Cone),
        ShapeDesc::Plane => Shape::new(ShapeKind::Plane),
        ShapeDesc::Disk => Shape::new(ShapeKind::Disk),
        ShapeDesc::Rectangle => Shape::new(ShapeKind::Rectangle),
        ShapeDesc::Torus { minor_radius } => {
            if !(minor_radius > 0.0 && minor_radius < 1.0) {
                return Err(invalid(origin, format!("torus minor radius {minor_radius} must be in (0, 1)")));
            }
            Shape::torus(minor_radius)
        }
        ShapeDesc::Mesh { index } => Shape::mesh(u32::try_from(index).unwrap_or(u32::MAX)),
    })
}

/// The segment `0 < t < t_left` of the shadow ray `ray` moved past the surface it
/// crosses at `point` (true normal `normal`): its origin offset to the far side, its far
/// end kept fixed (the same direction, the parameter measured from the new origin; an
/// infinite segment, toward a directional light, stays infinite).
pub(crate) fn past_surface(ray: &Ray, t_left: f32, point: Vec3, normal: Vec3) -> (Ray, f32) {
    let side = if normal.dot(ray.dir) > 0.0 { normal } else { -normal };
    let origin = offset_ray_origin(point, side);
    let t_left =
        if t_left.is_finite() { (ray.at(t_left) - origin).dot(ray.dir) / ray.dir.length_squared() } else { t_left };
    (Ray { origin, ..*ray }, t_left)
}

fn instance_bounds(inst: &Instance, meshes: &[Mesh], tables: &ShapeTables, motions: &[Motion]) -> Aabb {
    let b = match inst.shape.kind {
        ShapeKind::Mesh => meshes[inst.shape.mesh_index() as usize].bounds(),
        _ => inst.shape.bounds_with(tables),
    };
    if !b.is_finite() {
        return Aabb::new(Vec3::NEG_INFINITY, Vec3::INFINITY);
    }
    match motions.get(inst.motion as usize) {
        Some(motion) => motion.bounds(&b),
        None => b.transformed(&inst.transform.world_from_object),
    }
}

impl RenderScene {
    /// The closest hit with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.intersect_avx2(avx, ray, t_max),
            self.intersect_on(Portable, ray, t_max)
        )
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn intersect_avx2(&self, avx: crate::accel::lanes::Avx2, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.intersect_on(avx, ray, t_max)
    }

    /// [`RenderScene::intersect`] with the instance BVH traversed on the lanes `L`.
    #[inline(always)]
    fn intersect_on<L: Lanes>(&self, lanes: L, ray: &Ray, t_max: f32) -> Option<Hit> {
        // The closest hit so far, with the ray in its instance's object space (reused
        // for the hit's surface rather than transformed again).
        let mut best: Option<(u32, crate::shape::ShapeHit, Ray)> = None;
        let mut t_max = t_max;
        let mut test = |index: u32, t_max: &mut f32| {
            let inst = &self.instances[index as usize];
            let local = self.transform_at(inst, ray.time).ray_to_object(ray);
            if let Some(hit) = self.intersect_shape(inst, &local, *t_max) {
                *t_max = hit.t;
                best = Some((index, hit, local));
            }
            false
        };
        self.bvh.traverse_with(lanes, Order::NearestFirst, &self.instances, ray, &mut t_max, &mut test);
        for index in self.bounded_count..self.instances.len() {
            test(index as u32, &mut t_max);
        }
        let (index, hit, local) = best?;
        Some(self.hit_in_object_space(ray, &local, index, hit))
    }

    /// How much work finding `ray`'s closest hit takes: the shapes it is tested against,
    /// a mesh counting the packets of four triangles tested inside it (a traversal-cost
    /// view; not the timed path).
    pub fn traversal_cost(&self, ray: &Ray) -> u32 {
        let mut tests = 0;
        let mut test = |index: u32, t_max: &mut f32| {
            let inst = &self.instances[index as usize];
            let local = self.transform_at(inst, ray.time).ray_to_object(ray);
            tests += match inst.shape.kind {
                ShapeKind::Mesh => self.meshes[inst.shape.mesh_index() as usize].packets_tested(&local, *t_max),
                _ => 1,
            };
            if let Some(hit) = self.intersect_shape(inst, &local, *t_max) {
                *t_max = hit.t;
            }
            false
        };
        let mut t_max = f32::INFINITY;
        self.bvh.traverse(ray, &mut t_max, &mut test);
        for index in self.bounded_count..self.instances.len() {
            test(index as u32, &mut t_max);
        }
        tests
    }

    /// The full [`Hit`] of `ray` from its closest hit `hit` on instance `index`.
    fn hit_from(&self, ray: &Ray, index: u32, hit: crate::shape::ShapeHit) -> Hit {
        let inst = &self.instances[index as usize];
        let local = self.transform_at(inst, ray.time).ray_to_object(ray);
        self.hit_in_object_space(ray, &local, index, hit)
    }

    /// [`RenderScene::hit_from`] given `local`, the ray already in the instance's object
    /// space.
    #[inline]
    fn hit_in_object_space(&self, ray: &Ray, local: &Ray, index: u32, hit: crate::shape::ShapeHit) -> Hit {
        let inst = &self.instances[index as usize];
        if inst.shape.kind != ShapeKind::Mesh {
            return self.hit_on_analytic(ray, local, index, hit);
        }
        let xf = self.transform_at(inst, ray.time);
        let material = inst.shape.hit_material(&self.shape_tables, hit).unwrap_or(inst.material);
        let mesh = &self.meshes[inst.shape.mesh_index() as usize];
        let m = mesh.surface(local, hit);
        let (surface, geometric, shadow_point) = (m.surface, m.geometric, m.shadow_point);
        let mut normal = xf.normal_to_world(surface.normal).normalize_or(Vec3::Y);
        let shading = &self.materials[material as usize];
        if shading.normal_texture != NO_TEXTURE
            && let Some((dpdu, dpdv)) = mesh.uv_frame(hit.part as usize)
        {
            let texel = self.texture(shading.normal_texture, surface.uv * shading.texture_repeat);
            let frame = [xf.vector_to_world(dpdu), xf.vector_to_world(dpdv), normal];
            normal = crate::normal_map::bent_normal(frame, texel, shading.normal_scale);
        }
        Hit {
            t: hit.t,
            point: xf.point_to_world(surface.point),
            normal,
            geometric_normal: xf.normal_to_world(geometric).normalize_or(normal),
            shadow_point: xf.point_to_world(shadow_point),
            uv: surface.uv,
            color: m.color,
            material,
            instance: index,
            part: hit.part,
        }
    }

    /// [`RenderScene::hit_in_object_space`] on an analytic surface, where the true
    /// surface is the shading surface, so the normal and the point are transformed
    /// once. Inlined where the caller knows the instance is analytic.
    #[inline(always)]
    pub(crate) fn hit_on_analytic(&self, ray: &Ray, local: &Ray, index: u32, hit: crate::shape::ShapeHit) -> Hit {
        self.hit_on_analytic_with_normal(ray, local, index, hit, None)
    }

    /// [`RenderScene::hit_on_analytic`], its unit world normal `unit_normal` where the
    /// caller knows it (a plane's, the same everywhere).
    #[inline(always)]
    pub(crate) fn hit_on_analytic_with_normal(
        &self,
        ray: &Ray,
        local: &Ray,
        index: u32,
        hit: crate::shape::ShapeHit,
        unit_normal: Option<Vec3>,
    ) -> Hit {
        let inst = &self.instances[index as usize];
        let xf = self.transform_at(inst, ray.time);
        let material = inst.shape.hit_material(&self.shape_tables, hit).unwrap_or(inst.material);
        let surface = match inst.shape.kind {
            // The textured floor, inlined: through the shape dispatch, its surface came
            // back through memory, and the loads that read it stalled.
            ShapeKind::Plane => crate::shape::Plane.surface(local, hit),
            _ => inst.shape.surface_with(&self.shape_tables, local, hit),
        };
        let normal = unit_normal.unwrap_or_else(|| crate::math::unit_or(xf.normal_to_world(surface.normal), Vec3::Y));
        let point = xf.point_to_world(surface.point);
        Hit {
            t: hit.t,
            point,
            normal,
            geometric_normal: normal,
            shadow_point: point,
            uv: surface.uv,
            color: Vec3::ONE,
            material,
            instance: index,
            part: hit.part,
        }
    }

    /// Whether instance `index` lets shadow rays through (its material casts no shadow).
    #[inline]
    fn casts_no_shadow(&self, index: u32) -> bool {
        if !self.has_shadowless {
            return false;
        }
        let material = self.instances[index as usize].material as usize;
        self.bsdfs.get(material).is_some_and(|b| b.flags & crate::bsdf::CASTS_NO_SHADOW != 0)
    }

    /// Whether anything that casts shadows blocks the segment `0 < t < t_max`; stops at
    /// the first hit.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        crate::accel::lanes::on_avx2_or!(
            |avx| self.occluded_avx2(avx, ray, t_max),
            self.occluded_on(Portable, ray, t_max)
        )
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn occluded_avx2(&self, avx: crate::accel::lanes::Avx2, ray: &Ray, t_max: f32) -> bool {
        self.occluded_on(avx, ray, t_max)
    }

    /// [`RenderScene::occluded`] with the instance BVH traversed on the lanes `L`.
    #[inline(always)]
    fn occluded_on<L: Lanes>(&self, lanes: L, ray: &Ray, t_max: f32) -> bool {
        let hits = |index: u32, t_max: &mut f32| {
            if self.casts_no_shadow(index) {
                return false;
            }
            let inst = &self.instances[index as usize];
            let local = self.transform_at(inst, ray.time).ray_to_object(ray);
            match inst.shape.kind {
                ShapeKind::Mesh => self.meshes[inst.shape.mesh_index() as usize].occluded(&local, *t_max),
                _ => inst.shape.intersect_with(&self.shape_tables, &local, *t_max).is_some(),
            }
        };
        let mut blocked = false;
        self.bvh.traverse_with(lanes, Order::Any, &self.instances, ray, &mut t_max.clone(), |i, t| {
            blocked = hits(i, t);
            blocked
        });
        blocked || (self.bounded_count..self.instances.len()).any(|i| hits(i as u32, &mut t_max.clone()))
    }

    /// The fraction of light that crosses the segment `0 < t < t_max`: zero if an opaque
    /// surface blocks it, else the product of `k_t·O_t` of every surface crossed.
    pub fn transmittance(&self, ray: &Ray, t_max: f32) -> Vec3 {
        self.transmittance_counted(ray, t_max).0
    }

    /// [`RenderScene::transmittance`], and how many rays it traced past transparent
    /// surfaces after the first: each goes on from the surface it crossed and is a
    /// whole query of the scene, which POV-Ray counts as a shadow ray test of its own.
    pub fn transmittance_counted(&self, ray: &Ray, t_max: f32) -> (Vec3, u32) {
        if !self.has_transmissive {
            return (if self.occluded(ray, t_max) { Vec3::ZERO } else { Vec3::ONE }, 0);
        }
        let mut filter = Vec3::ONE;
        let mut ray = *ray;
        let mut t_left = t_max;
        // Each crossing moves the origin past one surface; the bound only guards
        // against pathological scenes.
        for crossed in 0..64 {
            let Some(hit) = self.intersect(&ray, t_left) else { return (filter, crossed) };
            if !self.casts_no_shadow(hit.instance) {
                filter *= self.materials[hit.material as usize].transmissive;
            }
            if filter.max_element() <= 0.0 {
                return (Vec3::ZERO, crossed);
            }
            (ray, t_left) = past_surface(&ray, t_left, hit.point, hit.geometric_normal);
        }
        (Vec3::ZERO, 63)
    }

    /// The closest hit of an object-space ray with an instance's shape or mesh.
    #[inline]
    fn intersect_shape(&self, inst: &Instance, local: &Ray, t_max: f32) -> Option<crate::shape::ShapeHit> {
        match inst.shape.kind {
            ShapeKind::Mesh => self.meshes[inst.shape.mesh_index() as usize].intersect(local, t_max),
            _ => inst.shape.intersect_with(&self.shape_tables, local, t_max),
        }
    }

    /// Where `inst` is at `time`: its fixed transform, or its pose interpolated.
    #[inline]
    fn transform_at<'a>(&self, inst: &'a Instance, time: f32) -> Cow<'a, Transform> {
        match self.motions.get(inst.motion as usize) {
            None => Cow::Borrowed(&inst.transform),
            Some(motion) => Cow::Owned(motion.at(time)),
        }
    }

    /// Samples texture `index` at `uv`.
    pub fn texture(&self, index: u32, uv: Vec2) -> Vec3 {
        self.textures[index as usize].sample(uv, &self.texels)
    }

    /// Whether adaptive sampling starts each pixel from a pilot sample at its centre, as
    /// one sample a pixel takes it: for Whitted renders that start from one sample, where
    /// textures are filtered over the footprint. A pixel that stops at its pilot then
    /// averages its textures over the pixel itself, not over a pixel-sized box around a
    /// random point in it. Without filtered textures the first samples stay random:
    /// centred ones alias coherently, neighbours agree on the same wrong moiré, and the
    /// pixels settle on it. Every backend follows this rule.
    pub fn adaptive_pilot(&self) -> bool {
        let s = &self.settings;
        s.adaptive.is_some_and(|a| a.min_samples == 1)
            && matches!(s.integrator, crate::desc::IntegratorDesc::Whitted)
            && self.textures.iter().any(|t| t.is_filtered())
    }

    /// Texture `index` where a ray at `time` met `hit`, its uv scaled by `repeat`: the
    /// texture's mean over the pixel's footprint (`footprint_scale` pixels across) when it
    /// is filtered, else its value at the point. Always inlined, so that the filtered
    /// lookup compiles into the AVX2 Whitted tile (on its own, built for any x86-64,
    /// each `floor` in it is a library call).
    #[inline(always)]
    pub fn texture_at_hit(&self, index: u32, hit: &Hit, repeat: Vec2, time: f32, footprint_scale: f32) -> Vec3 {
        let texture = &self.textures[index as usize];
        let uv = hit.uv * repeat;
        if !texture.is_filtered() {
            return texture.sample(uv, &self.texels);
        }
        let steps = self.uv_steps(hit, time, footprint_scale).map(|steps| steps.map(|step| step * repeat));
        texture.sample_over(uv, steps, &self.texels)
    }

    /// The steps in uv from `hit` to where the neighbouring pixels see its surface (see
    /// [`crate::footprint`]), the pixels `footprint_scale` of a pixel apart; `None` where
    /// the footprint is unbounded. The plane's case is inlined (a textured floor is the
    /// common one, and its answer no longer comes back through memory); the others are
    /// calls.
    #[inline(always)]
    pub fn uv_steps(&self, hit: &Hit, time: f32, footprint_scale: f32) -> Option<[Vec2; 2]> {
        let s = &self.settings;
        let spacing = PixelSpacing::new(&self.camera, s.width, s.height, footprint_scale);
        let steps = spacing.surface_steps(hit.point, hit.geometric_normal)?;
        let inst = &self.instances[hit.instance as usize];
        let steps = match inst.shape.kind {
            ShapeKind::Plane => {
                // The plane's uv is its object-space point's (x, −z): linear in the
                // point, so a step's uv is the step's own, carried into object space.
                let xf = self.transform_at(inst, time);
                steps.map(|step| {
                    let local = xf.object_from_world.transform_vector3(step);
                    Vec2::new(local.x, -local.z)
                })
            }
            // The hit's fields by value: a reference would make every caller keep its
            // hit in memory, where reading it back just after building it stalls.
            ShapeKind::Mesh => self.mesh_uv_steps(inst, hit.part, time, steps),
            _ => self.analytic_uv_steps(inst, (hit.point, hit.normal, hit.uv, hit.part), time, steps),
        };
        steps.iter().all(|d| d.is_finite()).then_some(steps)
    }

    /// [`RenderScene::uv_steps`] on a triangle, whose uv is linear in p: each step
    /// solved for `a·∂p/∂u + b·∂p/∂v` by least squares. Without uvs the texture sees one
    /// uv (no footprint).
    #[inline(never)]
    fn mesh_uv_steps(&self, inst: &Instance, part: u32, time: f32, steps: [Vec3; 2]) -> [Vec2; 2] {
        let mesh = &self.meshes[inst.shape.mesh_index() as usize];
        let Some((dpdu, dpdv)) = mesh.uv_frame(part as usize) else { return [Vec2::ZERO; 2] };
        let xf = self.transform_at(inst, time);
        let (u, v) = (xf.vector_to_world(dpdu), xf.vector_to_world(dpdv));
        let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
        let det = uu * vv - uv * uv;
        steps.map(|step| {
            let (su, sv) = (u.dot(step), v.dot(step));
            Vec2::new(vv * su - uv * sv, uu * sv - uv * su) / det
        })
    }

    /// [`RenderScene::uv_steps`] on an analytic shape other than the plane: the shapes
    /// give uv from the point (and the part of the surface), so the uv at each
    /// neighbour's point on the tangent plane is the shape's own answer.
    #[inline(never)]
    fn analytic_uv_steps(
        &self,
        inst: &Instance,
        (point, normal, uv, part): (Vec3, Vec3, Vec2, u32),
        time: f32,
        steps: [Vec3; 2],
    ) -> [Vec2; 2] {
        let xf = self.transform_at(inst, time);
        let uv_at = |step: Vec3| {
            let local = xf.ray_to_object(&Ray::new(point + step, -normal));
            let at = crate::shape::ShapeHit { t: 0.0, part };
            inst.shape.surface_with(&self.shape_tables, &local, at).uv
        };
        // Bounded shapes' uvs wrap at a seam (a sphere's u from 1 to 0): the step across
        // it is the short way round.
        steps.map(|step| {
            let d = uv_at(step) - uv;
            d - d.round()
        })
    }

    /// Radiance of a ray that leaves the scene along `dir`: the environment's, or the
    /// background colour.
    pub fn background(&self, dir: Vec3) -> Vec3 {
        self.environment.as_ref().map_or(self.settings.background, |env| env.radiance(dir))
    }

    /// The emitter record a hit on an emissive surface lies on, if it is sampled.
    pub fn emitter_of(&self, hit: &Hit) -> Option<u32> {
        let first = *self.instance_emitters.get(hit.instance as usize)?;
        if first == crate::emitter::NO_EMITTER {
            return None;
        }
        let kind = self.instances[hit.instance as usize].shape.kind;
        Some(if matches!(kind, ShapeKind::Mesh | ShapeKind::Cube) { first + hit.part } else { first })
    }
}
