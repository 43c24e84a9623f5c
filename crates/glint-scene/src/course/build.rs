//! The course model → [`SceneDesc`], with the course's meaning.
//!
//! The course's lighting equation (CS1230 "Illuminate", as its reference renderer
//! evaluates it) is
//!
//! `I = k_a·O_a + O_e + Σ f_att·L·[(1−b)·k_d·O_d + b·T)·(n·l) + k_s·O_s·(r·v)^n] + k_s·O_r·I_r + k_t·O_t·I_t`
//!
//! with display-referred colours and no ambient light term. glint's material is the
//! same equation with `k` factors of its own, so every course `k` is folded into the
//! colour it multiplies and glint's factors are 1; `L_a = 1`; and textures are read
//! without sRGB decoding, the image written without sRGB encoding.

use std::collections::HashMap;

use glam::{Mat4, Vec2, Vec3};
use glint_core::desc::{
    CameraDesc, Features, LightDesc, MaterialDesc, NodeDesc, NodeKind, RenderSettings, SceneDesc, ShapeDesc, Transfer,
    TransformOp,
};

use super::model::{Child, CourseScene, Group, Light, LightKind, Material, Primitive, Shape};
use super::textures::TextureCache;
use super::{CourseOptions, Pos, Result, Source, Warnings};
use crate::error::SceneErrorKind;
use glint_core::desc::matrix_of;

/// The image size the course renders its reference images at.
pub const COURSE_WIDTH: u32 = 1024;
pub const COURSE_HEIGHT: u32 = 768;
/// The course's recursion depth (`maximum-recursive-depth` of its render settings).
pub const COURSE_MAX_DEPTH: u32 = 4;

/// Samples per pixel along each axis when the camera has an open aperture.
pub const DEPTH_OF_FIELD_SAMPLES_PER_AXIS: u32 = 4;

/// The most scene nodes one scene may expand to once templates are written out, so that
/// nested templates cannot blow up memory exponentially.
pub const MAX_NODES: usize = 1_000_000;

/// The course's unit primitives fit in [−0.5, 0.5]³; glint's canonical shapes have
/// radius (or half-size) 1.
const UNIT_SCALE: f32 = 0.5;

/// The course's torus is not part of its ray tracer; glint reads it as the ring whose
/// outer radius is 0.5 (major radius 0.375, tube radius 0.125), inside the unit cube.
const TORUS_MAJOR: f32 = 0.375;
const TORUS_MINOR_RATIO: f32 = 1.0 / 3.0;

/// Builds the scene: settings, camera, lights placed in world space, materials (shared
/// when equal), textures (each file loaded once) and the object tree with templates
/// written out.
pub fn build(model: &CourseScene, src: &Source, options: CourseOptions, warnings: &mut Warnings) -> Result<SceneDesc> {
    let mut builder = Builder {
        model,
        src,
        options,
        warnings,
        desc: SceneDesc::default(),
        textures: TextureCache::default(),
        material_index: HashMap::new(),
        mesh_index: HashMap::new(),
        in_progress: Vec::new(),
        node_count: 0,
    };
    builder.desc.settings = course_settings();
    builder.desc.camera = builder.camera()?;
    for light in &model.lights {
        let placed = builder.light(light, &Mat4::IDENTITY)?;
        builder.desc.lights.extend(placed);
    }
    let root = builder.group(&model.root, &Mat4::IDENTITY)?;
    // The root group has no transform of its own: its children are the scene's roots.
    builder.desc.objects = match root.kind {
        NodeKind::Group(children) if root.transform.is_empty() => children,
        _ => vec![root],
    };
    builder.desc.textures = std::mem::take(&mut builder.textures.textures);
    Ok(builder.desc)
}

/// Render settings as the course renders: 1024×768, one sample per pixel, recursion
/// depth 4, black background, `L_a = 1` (the course's ambient term is `k_a·O_a`), and
/// colours written as they are computed.
pub fn course_settings() -> RenderSettings {
    RenderSettings {
        width: COURSE_WIDTH,
        height: COURSE_HEIGHT,
        samples_per_axis: 1,
        max_depth: COURSE_MAX_DEPTH,
        background: Vec3::ZERO,
        ambient_light: Vec3::ONE,
        output_transfer: Transfer::Identity,
        // The course's shadow rays stop at any object, transparent or not.
        features: Features { transparent_shadows: false, ..Features::default() },
        ..RenderSettings::default()
    }
}

struct Builder<'a> {
    model: &'a CourseScene,
    src: &'a Source,
    options: CourseOptions,
    warnings: &'a mut Warnings,
    desc: SceneDesc,
    textures: TextureCache,
    /// Materials already made, by their exact values, so equal ones are shared.
    material_index: HashMap<Vec<u32>, usize>,
    /// Meshes already loaded, by the path as written (`None`: not found, warned once).
    mesh_index: HashMap<String, Option<usize>>,
    /// Templates being written out, outermost first (to catch a template inside itself).
    in_progress: Vec<usize>,
    node_count: usize,
}

impl Builder<'_> {
    fn camera(&mut self) -> Result<CameraDesc> {
        let c = &self.model.camera;
        if !(c.height_angle > 0.0 && c.height_angle < 180.0) {
            return Err(self.src.invalid(
                c.pos,
                format!("the camera's height angle is {} degrees; it must be between 0 and 180", c.height_angle),
            ));
        }
        if c.look.length_squared() == 0.0 {
            return Err(self.src.invalid(
                c.pos,
                "the camera looks nowhere: its look vector is zero (or its focus point is its position)",
            ));
        }
        if c.up.cross(c.look).length_squared() <= 1e-12 * c.up.length_squared() * c.look.length_squared() {
            return Err(self.src.invalid(
                c.pos,
                format!("the camera's up vector {} is zero or parallel to its look vector {}", c.up, c.look),
            ));
        }
        let mut camera = CameraDesc {
            eye: c.position,
            look: c.look,
            up: c.up,
            fov_y_degrees: c.height_angle,
            ..CameraDesc::default()
        };
        // The course's depth of field: `aperture` is the radius of the lens, `focalLength`
        // the distance of the plane in focus (the references match best read this way).
        if let Some((aperture, focal_length, pos)) = c.depth_of_field {
            if aperture > 0.0 && focal_length > 0.0 {
                camera.aperture_radius = aperture;
                camera.focal_distance = focal_length;
                // One sample per pixel would show the lens as noise.
                self.desc.settings.samples_per_axis = DEPTH_OF_FIELD_SAMPLES_PER_AXIS;
            } else if aperture > 0.0 {
                self.warnings.at(
                    self.src,
                    pos,
                    format!("focal length {focal_length} is not positive; depth of field is off (a pinhole camera)"),
                );
            }
        }
        Ok(camera)
    }

    /// A light placed by `world_from_group`; `None` (with a warning) when it cannot shine.
    fn light(&mut self, light: &Light, world_from_group: &Mat4) -> Result<Option<LightDesc>> {
        let position = world_from_group.transform_point3(light.position);
        let direction = world_from_group.transform_vector3(light.direction);
        let color = light.color;
        let attenuation = light.attenuation;
        let needs_direction = matches!(light.kind, LightKind::Directional | LightKind::Spot { .. });
        if needs_direction && direction.length_squared() == 0.0 {
            return Err(self.src.invalid(light.pos, "this light needs a non-zero direction"));
        }
        Ok(Some(match light.kind {
            LightKind::Point => LightDesc::Point { position, color, attenuation },
            LightKind::Directional => LightDesc::Directional { direction, color },
            LightKind::Spot { angle, penumbra } => LightDesc::Spot {
                position,
                direction,
                color,
                attenuation,
                angle_degrees: angle,
                penumbra_degrees: penumbra.max(0.0).min(angle),
                falloff: glint_core::desc::SpotFalloff::Smooth,
            },
            LightKind::Area { width, height } => {
                self.warnings.at(
                    self.src,
                    light.pos,
                    format!("area lights ({width} x {height}) are read as a point light at their centre"),
                );
                LightDesc::Point { position, color, attenuation }
            }
        }))
    }

    /// A group and everything below it; `world_from_parent` places its lights.
    fn group(&mut self, group: &Group, world_from_parent: &Mat4) -> Result<NodeDesc> {
        self.count(group.pos)?;
        let world_from_group = *world_from_parent * matrix_of(&group.transform);
        for light in &group.lights {
            let placed = self.light(light, &world_from_group)?;
            self.desc.lights.extend(placed);
        }
        let mut children = Vec::new();
        for primitive in &group.primitives {
            children.extend(self.primitive(primitive)?);
        }
        for child in &group.children {
            match child {
                Child::Group(g) => children.push(self.group(g, &world_from_group)?),
                Child::Template { index, pos } => children.push(self.template(*index, *pos, &world_from_group)?),
            }
        }
        Ok(NodeDesc {
            transform: group.transform.clone(),
            kind: NodeKind::Group(children),
            origin: self.src.origin(group.pos),
        })
    }

    /// A use of a template: a fresh copy of its tree, placed where it is used.
    fn template(&mut self, index: usize, pos: Pos, world_from_parent: &Mat4) -> Result<NodeDesc> {
        let template = &self.model.templates[index];
        if let Some(start) = self.in_progress.iter().position(|&i| i == index) {
            let mut chain: Vec<&str> =
                self.in_progress[start..].iter().map(|&i| self.model.templates[i].name.as_str()).collect();
            chain.push(&template.name);
            return Err(self.src.invalid(pos, format!("'{}' contains itself: {}", template.name, chain.join(" -> "))));
        }
        self.in_progress.push(index);
        let mut node = self.group(&template.group, world_from_parent)?;
        self.in_progress.pop();
        node.origin = self.src.origin(pos);
        Ok(node)
    }

    fn count(&mut self, pos: Pos) -> Result<()> {
        self.node_count += 1;
        if self.node_count > MAX_NODES {
            return Err(self.src.invalid(
                pos,
                format!("the scene expands to more than {MAX_NODES} objects once its templates are written out"),
            ));
        }
        Ok(())
    }

    /// A primitive as a glint shape scaled to the course's unit size (meshes keep their
    /// own coordinates); `None` for a mesh file that cannot be found in lenient mode.
    fn primitive(&mut self, p: &Primitive) -> Result<Option<NodeDesc>> {
        self.count(p.pos)?;
        if let Shape::Mesh(file) = &p.shape {
            let Some(index) = self.mesh(p.pos, file)? else { return Ok(None) };
            let material = self.material(&p.material)?;
            return Ok(Some(NodeDesc {
                transform: Vec::new(),
                kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index }, material },
                origin: self.src.origin(p.pos),
            }));
        }
        let (shape, size) = match &p.shape {
            Shape::Cube => (ShapeDesc::Cube, UNIT_SCALE),
            Shape::Sphere => (ShapeDesc::Sphere, UNIT_SCALE),
            Shape::Cylinder => (ShapeDesc::Cylinder, UNIT_SCALE),
            Shape::Cone => (ShapeDesc::Cone, UNIT_SCALE),
            Shape::Torus => (ShapeDesc::Torus { minor_radius: TORUS_MINOR_RATIO }, TORUS_MAJOR),
            Shape::Mesh(_) => unreachable!("handled above"),
        };
        let material = self.material(&p.material)?;
        Ok(Some(NodeDesc {
            transform: vec![TransformOp::Scale(Vec3::splat(size))],
            kind: NodeKind::Shape { shape, material },
            origin: self.src.origin(p.pos),
        }))
    }

    /// The index of the mesh file `written` in the scene, loading it the first time. Found
    /// the way textures are; a file found nowhere is an error, or with lenient textures a
    /// warning and no object (what the course's renderer shows).
    fn mesh(&mut self, pos: Pos, written: &str) -> Result<Option<usize>> {
        if let Some(&known) = self.mesh_index.get(written) {
            return Ok(known);
        }
        let (primary, found) = super::textures::resolve(&self.src.dir, written);
        let index = match found {
            Some(path) => {
                let import = crate::mesh::load_mesh(&path).map_err(|e| {
                    self.src.error(SceneErrorKind::Io, pos, format!("cannot load mesh '{written}': {e}"))
                })?;
                self.desc.meshes.push(crate::mesh::merged(&import, written, &path.display().to_string()));
                Some(self.desc.meshes.len() - 1)
            }
            None if self.options.strict_textures => {
                let message = format!("mesh file '{written}' not found (looked first at {})", primary.display());
                return Err(self.src.error(SceneErrorKind::Io, pos, message));
            }
            None => {
                let message =
                    format!("mesh file '{written}' not found (looked first at {}); skipped", primary.display());
                self.warnings.at(self.src, pos, message);
                None
            }
        };
        self.mesh_index.insert(written.to_owned(), index);
        Ok(index)
    }

    /// The glint material for a course material, with the global `k` folded in.
    fn material(&mut self, m: &Material) -> Result<usize> {
        let g = self.model.global;
        let texture = match &m.texture {
            Some(map) => self
                .textures
                .get(self.src, map.pos, &map.file, self.options.strict_textures, self.warnings)?
                .map(|index| (index, map.repeat)),
            None => None,
        };
        let transmissive = g.kt * m.transparent;
        let ior = if m.ior > 0.0 { m.ior } else { 1.0 };
        let desc = MaterialDesc {
            name: String::new(),
            ka: 1.0,
            kd: 1.0,
            ks: 1.0,
            kt: 1.0,
            // With L_a = 1 glint's ambient term is this colour; the emissive colour is
            // a constant added to the same sum.
            ambient: Some(g.ka * m.ambient + m.emissive),
            diffuse: g.kd * m.diffuse,
            // The course's renderer has no highlight for shininess 0 (rather than the
            // constant (r·v)⁰ = 1).
            specular: if m.shininess > 0.0 { g.ks * m.specular } else { Vec3::ZERO },
            reflective: Some(g.ks * m.reflective),
            transmissive,
            shininess: m.shininess.max(0.0),
            ior,
            texture: texture.map(|(index, _)| index),
            // glint blends `(1 − b)·k_d·O_d + b·k_d·T`; with k_d = 1 and k_d·O_d folded
            // into the diffuse colour this is the course's `(1 − b)·k_d·O_d + b·T`.
            blend: if texture.is_some() { m.blend.clamp(0.0, 1.0) } else { 0.0 },
            texture_repeat: texture.map_or(Vec2::ONE, |(_, repeat)| repeat),
            ..MaterialDesc::default()
        };
        let key = material_key(&desc);
        if let Some(&index) = self.material_index.get(&key) {
            return Ok(index);
        }
        let index = self.desc.materials.len();
        self.desc.materials.push(MaterialDesc { name: format!("course-{index}"), ..desc });
        self.material_index.insert(key, index);
        Ok(index)
    }
}

/// The exact values of a material, as a hashable key.
fn material_key(m: &MaterialDesc) -> Vec<u32> {
    let mut key = Vec::with_capacity(24);
    let ambient = m.ambient.unwrap_or(Vec3::NAN);
    let reflective = m.reflective.unwrap_or(Vec3::NAN);
    for v in [ambient, m.diffuse, m.specular, reflective, m.transmissive] {
        key.extend(v.to_array().map(f32::to_bits));
    }
    for x in [m.shininess, m.ior, m.blend, m.texture_repeat.x, m.texture_repeat.y] {
        key.push(x.to_bits());
    }
    key.push(m.texture.map_or(u32::MAX, |t| t as u32));
    key
}
