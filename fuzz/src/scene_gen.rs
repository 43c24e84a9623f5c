//! Small random scenes that are valid by construction (numbers in sane ranges, indices
//! in bounds), rendered at 8×8 with one or two samples a pixel: the renderer must not
//! panic and every pixel must be finite. Compile may still refuse a scene (a zero scale,
//! a camera looking along its up vector); that is an answer, not a failure.
//!
//! The work is bounded so an execution takes milliseconds: at most 6 objects (groups
//! two deep), 3 lights, path depth 6.

use std::sync::atomic::AtomicBool;

use arbitrary::Arbitrary;
use glam::{Vec2, Vec3};
use glint_core::desc::{
    AreaShape, BlobComponentDesc, BlobComponentShape, BlobDesc, BsdfDesc, CameraDesc, ColorParam, EnvironmentDesc,
    FilterDesc, FilterKind, ImplicitDesc, IntegratorDesc, LightDesc, MaterialDesc, MeshDesc, NodeDesc, NodeKind,
    PathDesc, RenderSettings, SamplePattern, SamplerKind, ScalarParam, SceneDesc, SetOp, ShapeDesc, SolidDesc,
    TextureDesc, TransformOp,
};

/// Image side in pixels.
const SIDE: u32 = 8;

/// A coordinate in [−128, 128) in steps of 1/256.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub struct Num(i16);

impl Num {
    fn get(self) -> f32 {
        f32::from(self.0) / 256.0
    }
}

/// A value in [0, 1].
#[derive(Arbitrary, Debug, Clone, Copy)]
pub struct Unit(u8);

impl Unit {
    fn get(self) -> f32 {
        f32::from(self.0) / 255.0
    }
}

/// A point or direction.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub struct Vec3Num(Num, Num, Num);

impl Vec3Num {
    fn get(self) -> Vec3 {
        Vec3::new(self.0.get(), self.1.get(), self.2.get())
    }
}

/// A colour with channels in [0, 1].
#[derive(Arbitrary, Debug, Clone, Copy)]
pub struct Color(Unit, Unit, Unit);

impl Color {
    fn get(self) -> Vec3 {
        Vec3::new(self.0.get(), self.1.get(), self.2.get())
    }
}

/// The whole random scene.
#[derive(Arbitrary, Debug)]
pub struct FuzzScene {
    path: Option<FuzzPath>,
    max_depth: u8,
    two_samples: bool,
    pattern: u8,
    filter: u8,
    filter_radius: Unit,
    seed: u32,
    camera: FuzzCamera,
    background: Color,
    ambient: Color,
    checker: Option<(Color, Color, u8)>,
    materials: Vec<FuzzMaterial>,
    objects: Vec<FuzzNode>,
    lights: Vec<FuzzLight>,
}

/// The path tracer's settings; absent means the Whitted integrator.
#[derive(Arbitrary, Debug)]
pub struct FuzzPath {
    max_depth: u8,
    rr_depth: u8,
    independent: bool,
}

#[derive(Arbitrary, Debug)]
pub struct FuzzCamera {
    eye: Vec3Num,
    look: Vec3Num,
    up: Vec3Num,
    fov: u8,
    aperture: Option<(Unit, Unit)>,
}

#[derive(Arbitrary, Debug)]
pub struct FuzzMaterial {
    k: [Unit; 4],
    diffuse: Color,
    specular: Color,
    transmissive: Color,
    shininess: u8,
    ior: Unit,
    textured: bool,
    bsdf: Option<FuzzBsdf>,
    emission: Option<Color>,
    two_sided: bool,
    beckmann: bool,
}

#[derive(Arbitrary, Debug)]
pub enum FuzzBsdf {
    Diffuse(Color),
    Conductor { eta: Color, k: Color, alpha: Unit },
    Dielectric { ior: Unit, alpha: Unit },
    ThinDielectric { ior: Unit },
    Plastic { diffuse: Color, ior: Unit, alpha: Unit, nonlinear: bool },
}

#[derive(Arbitrary, Debug)]
pub enum FuzzLight {
    Point { position: Vec3Num, color: Color, attenuation: Color },
    Directional { direction: Vec3Num, color: Color },
    Spot { position: Vec3Num, direction: Vec3Num, color: Color, angle: u8, penumbra: u8 },
    Rectangle { corner: Vec3Num, u: Vec3Num, v: Vec3Num, color: Color, samples: u8 },
    Disk { center: Vec3Num, normal: Vec3Num, radius: Unit, color: Color, samples: u8 },
    Sphere { center: Vec3Num, radius: Unit, color: Color, samples: u8 },
    Environment(Color),
}

#[derive(Arbitrary, Debug)]
pub enum FuzzOp {
    Translate(Vec3Num),
    Scale(Vec3Num),
    Rotate(Vec3Num, i16),
}

#[derive(Arbitrary, Debug)]
pub struct FuzzNode {
    transform: Vec<FuzzOp>,
    kind: FuzzKind,
}

#[derive(Arbitrary, Debug)]
pub enum FuzzKind {
    Shape(FuzzShape, u8),
    Group(Vec<FuzzNode>),
    Csg(u8, FuzzShape, FuzzShape, u8),
    Blob { threshold: Unit, components: Vec<(Vec3Num, Unit, i8)>, material: u8 },
    Implicit { function: u8, material: u8 },
    Quadric { coefficients: [i8; 10], bounded: bool, material: u8 },
    Superellipsoid { e1: Unit, e2: Unit, material: u8 },
    Moving { close: Vec<FuzzOp>, shape: FuzzShape, material: u8 },
}

#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum FuzzShape {
    Sphere,
    Cube,
    Cylinder,
    Cone,
    Plane,
    Disk,
    Rectangle,
    Torus(Unit),
    /// A tetrahedron with these corners.
    Mesh([Vec3Num; 4]),
}

/// Compiles and renders `scene`; panics if the renderer panics or a pixel is not finite.
pub fn render_checked(scene: &FuzzScene) {
    let desc = scene.desc();
    let Ok(compiled) = glint_core::scene::compile(&desc) else { return };
    let cancel = AtomicBool::new(false);
    let (image, _) = glint_core::render::render(&compiled, &|_, _| {}, &cancel).expect("not cancelled");
    for (i, p) in image.pixels.iter().enumerate() {
        assert!(p.is_finite(), "pixel {i} is {p} in {desc:#?}");
    }
}

/// The implicit functions to choose from (the expression parser has its own target
/// through the native reader; here the solver is what is exercised).
const FUNCTIONS: [&str; 3] = [
    "x^2 + y^2 + z^2 - 1",
    "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8",
    "max(abs(sin(4*x)*cos(4*y) + sin(4*y)*cos(4*z) + sin(4*z)*cos(4*x)) - 0.4, x^2 + y^2 + z^2 - 1)",
];

impl FuzzScene {
    /// The scene description this stands for.
    pub fn desc(&self) -> SceneDesc {
        let mut out = Build { materials: self.materials.len().clamp(1, 4), meshes: Vec::new(), objects: 0 };
        let objects = self.objects.iter().filter_map(|n| out.node(n, 0)).collect();
        let mut materials: Vec<MaterialDesc> =
            self.materials.iter().take(4).map(|m| m.desc(self.checker.is_some())).collect();
        if materials.is_empty() {
            materials.push(MaterialDesc::default());
        }
        SceneDesc {
            settings: self.settings(),
            camera: self.camera.desc(),
            lights: self.lights.iter().take(3).map(FuzzLight::desc).collect(),
            materials,
            textures: self.checker.iter().map(checker).collect(),
            objects,
            meshes: out.meshes,
            views: Vec::new(),
        }
    }

    fn settings(&self) -> RenderSettings {
        let integrator = match &self.path {
            None => IntegratorDesc::Whitted,
            Some(p) => IntegratorDesc::Path(PathDesc {
                max_depth: u32::from(p.max_depth % 7),
                rr_depth: u32::from(p.rr_depth % 7),
                sampler: if p.independent { SamplerKind::Independent } else { SamplerKind::Sobol },
            }),
        };
        let patterns =
            [SamplePattern::Grid, SamplePattern::CornersAndCentre, SamplePattern::Jittered, SamplePattern::Sobol];
        let filters =
            [FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell, FilterKind::Lanczos];
        RenderSettings {
            width: SIDE,
            height: SIDE,
            max_depth: u32::from(self.max_depth % 6),
            background: self.background.get(),
            ambient_light: self.ambient.get(),
            pattern: patterns[usize::from(self.pattern) % patterns.len()],
            filter: FilterDesc {
                kind: filters[usize::from(self.filter) % filters.len()],
                radius: 0.5 + 1.5 * self.filter_radius.get(),
            },
            seed: self.seed,
            integrator,
            spp: Some(if self.two_samples { 2 } else { 1 }),
            ..Default::default()
        }
    }
}

/// The byte's low bits give the cell count, its top bit the footprint filter.
fn checker((even, odd, bits): &(Color, Color, u8)) -> TextureDesc {
    let cells = Vec2::splat(f32::from(bits % 16 + 1));
    TextureDesc::Checker { name: "checks".into(), even: even.get(), odd: odd.get(), cells, filtered: bits & 0x80 != 0 }
}

impl FuzzCamera {
    fn desc(&self) -> CameraDesc {
        let (aperture_radius, focal_distance) =
            self.aperture.map_or((0.0, 1.0), |(a, f)| (a.get(), 0.1 + 10.0 * f.get()));
        CameraDesc {
            eye: self.eye.get(),
            look: self.look.get(),
            up: self.up.get(),
            fov_y_degrees: 1.0 + f32::from(self.fov) * (178.0 / 255.0),
            aperture_radius,
            focal_distance,
            ..Default::default()
        }
    }
}

impl FuzzMaterial {
    fn desc(&self, has_texture: bool) -> MaterialDesc {
        let [ka, kd, ks, kt] = self.k.map(Unit::get);
        MaterialDesc {
            ka,
            kd,
            ks,
            kt,
            diffuse: self.diffuse.get(),
            specular: self.specular.get(),
            transmissive: self.transmissive.get(),
            shininess: f32::from(self.shininess),
            ior: 1.0 + 2.0 * self.ior.get(),
            texture: (has_texture && self.textured).then_some(0),
            bsdf: self.bsdf.as_ref().map(|b| b.desc(self.textured && has_texture)),
            emission: self.emission.map_or(Vec3::ZERO, |c| 4.0 * c.get()),
            two_sided: self.two_sided,
            microfacet: if self.beckmann {
                glint_core::desc::MicrofacetKind::Beckmann
            } else {
                glint_core::desc::MicrofacetKind::Ggx
            },
            ..Default::default()
        }
    }
}

impl FuzzBsdf {
    fn desc(&self, textured: bool) -> BsdfDesc {
        let texture = textured.then_some(0);
        let colour = |c: &Color| ColorParam { value: c.get(), texture };
        let ior = |u: &Unit| 1.0 + 2.0 * u.get();
        match self {
            FuzzBsdf::Diffuse(c) => BsdfDesc::Diffuse { reflectance: colour(c) },
            FuzzBsdf::Conductor { eta, k, alpha } => BsdfDesc::Conductor {
                eta: 0.1 + 3.0 * eta.get(),
                k: 5.0 * k.get(),
                specular: ColorParam::constant(Vec3::ONE),
                alpha: ScalarParam { value: alpha.get(), texture },
            },
            FuzzBsdf::Dielectric { ior: i, alpha } => BsdfDesc::Dielectric {
                int_ior: ior(i),
                ext_ior: 1.0,
                reflectance: Vec3::ONE,
                transmittance: Vec3::ONE,
                alpha: ScalarParam::constant(alpha.get()),
            },
            FuzzBsdf::ThinDielectric { ior: i } => BsdfDesc::ThinDielectric {
                int_ior: ior(i),
                ext_ior: 1.0,
                reflectance: Vec3::ONE,
                transmittance: Vec3::ONE,
            },
            FuzzBsdf::Plastic { diffuse, ior: i, alpha, nonlinear } => BsdfDesc::Plastic {
                diffuse: colour(diffuse),
                int_ior: ior(i),
                ext_ior: 1.0,
                specular: Vec3::ONE,
                alpha: ScalarParam::constant(alpha.get()),
                nonlinear: *nonlinear,
            },
        }
    }
}

impl FuzzLight {
    fn desc(&self) -> LightDesc {
        let samples = |s: &u8| u32::from(s % 3 + 1);
        let radius = |r: &Unit| 0.01 + 2.0 * r.get();
        match self {
            FuzzLight::Point { position, color, attenuation } => {
                LightDesc::Point { position: position.get(), color: color.get(), attenuation: attenuation.get() }
            }
            FuzzLight::Directional { direction, color } => {
                LightDesc::Directional { direction: direction.get(), color: color.get() }
            }
            FuzzLight::Spot { position, direction, color, angle, penumbra } => LightDesc::Spot {
                position: position.get(),
                direction: direction.get(),
                color: color.get(),
                attenuation: Vec3::X,
                angle_degrees: f32::from(*angle) * (90.0 / 255.0),
                penumbra_degrees: f32::from(*penumbra) * (90.0 / 255.0),
                falloff: Default::default(),
            },
            FuzzLight::Rectangle { corner, u, v, color, samples: s } => LightDesc::Area {
                shape: AreaShape::Rectangle { corner: corner.get(), edge_u: u.get(), edge_v: v.get() },
                color: color.get(),
                attenuation: Vec3::X,
                samples: samples(s),
            },
            FuzzLight::Disk { center, normal, radius: r, color, samples: s } => LightDesc::Area {
                shape: AreaShape::Disk { center: center.get(), normal: normal.get(), radius: radius(r) },
                color: color.get(),
                attenuation: Vec3::X,
                samples: samples(s),
            },
            FuzzLight::Sphere { center, radius: r, color, samples: s } => LightDesc::Area {
                shape: AreaShape::Sphere { center: center.get(), radius: radius(r) },
                color: color.get(),
                attenuation: Vec3::X,
                samples: samples(s),
            },
            FuzzLight::Environment(c) => {
                LightDesc::Environment(EnvironmentDesc { radiance: c.get(), texture: None, transform: Vec::new() })
            }
        }
    }
}

impl FuzzOp {
    fn desc(&self) -> TransformOp {
        match self {
            FuzzOp::Translate(t) => TransformOp::Translate(t.get()),
            FuzzOp::Scale(s) => TransformOp::Scale(s.get()),
            FuzzOp::Rotate(axis, degrees) => {
                TransformOp::Rotate { axis: axis.get(), degrees: f32::from(*degrees) / 64.0 }
            }
        }
    }
}

fn ops(list: &[FuzzOp]) -> Vec<TransformOp> {
    list.iter().take(3).map(FuzzOp::desc).collect()
}

/// The scene's meshes and how many objects have been placed, while nodes are built.
struct Build {
    materials: usize,
    meshes: Vec<MeshDesc>,
    objects: usize,
}

impl Build {
    /// The node, or `None` once the scene has its 6 objects.
    fn node(&mut self, node: &FuzzNode, depth: u32) -> Option<NodeDesc> {
        if self.objects >= 6 {
            return None;
        }
        self.objects += 1;
        let kind = self.kind(&node.kind, depth);
        Some(NodeDesc { transform: ops(&node.transform), kind, origin: format!("fuzz object {}", self.objects) })
    }

    fn material(&self, m: u8) -> usize {
        usize::from(m) % self.materials
    }

    fn kind(&mut self, kind: &FuzzKind, depth: u32) -> NodeKind {
        match kind {
            FuzzKind::Shape(shape, m) => NodeKind::Shape { shape: self.shape(*shape), material: self.material(*m) },
            FuzzKind::Group(children) if depth < 2 => {
                NodeKind::Group(children.iter().filter_map(|c| self.node(c, depth + 1)).collect())
            }
            FuzzKind::Group(_) => NodeKind::Group(Vec::new()),
            FuzzKind::Csg(op, a, b, m) => {
                let op = [SetOp::Union, SetOp::Intersection, SetOp::Difference][usize::from(*op % 3)];
                let leaf = |shape: ShapeDesc, offset: f32| NodeDesc {
                    transform: vec![TransformOp::Translate(Vec3::splat(offset))],
                    kind: NodeKind::Shape { shape, material: self.material(*m) },
                    origin: "fuzz csg leaf".into(),
                };
                let children = vec![leaf(solid_shape(*a), 0.0), leaf(solid_shape(*b), 0.5)];
                SolidDesc::Csg { op, children }.into()
            }
            FuzzKind::Blob { threshold, components, material } => {
                let components = components
                    .iter()
                    .take(4)
                    .map(|(center, radius, strength)| BlobComponentDesc {
                        shape: BlobComponentShape::Sphere {
                            center: center.get() / 32.0,
                            radius: 0.1 + 2.0 * radius.get(),
                        },
                        strength: if *strength == 0 { 1.0 } else { f32::from(*strength) / 32.0 },
                        transform: Vec::new(),
                    })
                    .collect();
                let blob = BlobDesc { threshold: 0.05 + threshold.get(), components };
                SolidDesc::Blob { blob, material: self.material(*material) }.into()
            }
            FuzzKind::Implicit { function, material } => {
                let function = FUNCTIONS[usize::from(*function) % FUNCTIONS.len()].to_owned();
                let bounds = [Vec3::splat(-2.5), Vec3::splat(2.5)];
                let implicit = ImplicitDesc { function, bounds, lipschitz: None };
                SolidDesc::Implicit { implicit, material: self.material(*material) }.into()
            }
            FuzzKind::Quadric { coefficients, bounded, material } => SolidDesc::Quadric {
                coefficients: coefficients.map(|c| f32::from(c) / 16.0),
                bounds: bounded.then_some([Vec3::splat(-2.0), Vec3::splat(2.0)]),
                material: self.material(*material),
            }
            .into(),
            FuzzKind::Superellipsoid { e1, e2, material } => SolidDesc::Superellipsoid {
                e1: 0.05 + 3.0 * e1.get(),
                e2: 0.05 + 3.0 * e2.get(),
                material: self.material(*material),
            }
            .into(),
            FuzzKind::Moving { close, shape, material } => {
                let child = NodeDesc {
                    transform: Vec::new(),
                    kind: NodeKind::Shape { shape: self.shape(*shape), material: self.material(*material) },
                    origin: "fuzz moving child".into(),
                };
                NodeKind::Moving { close: ops(close), children: vec![child] }
            }
        }
    }

    fn shape(&mut self, shape: FuzzShape) -> ShapeDesc {
        match shape {
            FuzzShape::Mesh(corners) => {
                let positions = corners.iter().map(|c| c.get() / 32.0).collect();
                let indices = vec![0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0];
                self.meshes.push(MeshDesc { name: "tetra".into(), positions, indices, ..Default::default() });
                ShapeDesc::Mesh { index: self.meshes.len() - 1 }
            }
            other => solid_shape(other),
        }
    }
}

/// The canonical shape `shape` names (a mesh becomes a sphere: CSG leaves must be solids).
fn solid_shape(shape: FuzzShape) -> ShapeDesc {
    match shape {
        FuzzShape::Sphere | FuzzShape::Mesh(_) => ShapeDesc::Sphere,
        FuzzShape::Cube => ShapeDesc::Cube,
        FuzzShape::Cylinder => ShapeDesc::Cylinder,
        FuzzShape::Cone => ShapeDesc::Cone,
        FuzzShape::Plane => ShapeDesc::Plane,
        FuzzShape::Disk => ShapeDesc::Disk,
        FuzzShape::Rectangle => ShapeDesc::Rectangle,
        FuzzShape::Torus(minor) => ShapeDesc::Torus { minor_radius: 0.05 + 0.9 * minor.get() },
    }
}
