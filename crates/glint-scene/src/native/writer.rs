//! [`SceneDesc`] → `.glint` text that reads back to the same description.
//!
//! Used by `glint convert` to turn a scene of any format into a native file. Everything
//! is written explicitly (no reliance on defaults), numbers in the shortest form that
//! reads back to the same `f32`, and the object tree as nested `group`s with the
//! transform statements in their original order. Image textures are referenced by their
//! file, relative to the output folder where possible.

use std::path::{Component, Path, PathBuf};

use glam::{Vec2, Vec3};
use glint_core::desc::{
    AreaShape, BlobComponentShape, BsdfDesc, CameraDesc, ColorParam, FilterKind, IntegratorDesc, LightDesc,
    MaterialDesc, MeshDesc, NodeDesc, NodeKind, RenderSettings, SamplePattern, SamplerKind, ScalarParam, SceneDesc,
    SetOp, ShapeDesc, SolidDesc, TextureDesc, Transfer, TransformOp,
};

use super::integrator::MAX_PATH_DEPTH;
use super::settings::MAX_SPP;
use super::tree::MAX_NESTING;

/// Why a scene cannot be written as `.glint`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct WriteError {
    /// What cannot be written and why.
    pub message: String,
}

fn fail<T>(message: impl Into<String>) -> Result<T, WriteError> {
    Err(WriteError { message: message.into() })
}

/// Where the text will live and what to say at its top.
#[derive(Clone, Debug, Default)]
pub struct WriteOptions {
    /// The folder the file will be written to: image textures are referenced relative to
    /// it when they share more than the file-system root with it, else by absolute path.
    /// `None` writes texture paths as they are stored.
    pub base_dir: Option<PathBuf>,
    /// A comment for the top of the file, such as where the scene came from.
    pub comment: Option<String>,
}

/// The written text and what it could not hold.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// The `.glint` source.
    pub text: String,
    /// Parts of the description the format cannot express yet (they are left out).
    pub warnings: Vec<String>,
}

/// Writes `desc` as `.glint` source.
///
/// # Errors
///
/// A [`WriteError`] when the scene holds something no `.glint` file can say: a number
/// that is not finite, an image texture without a source file, a material index out of
/// range, or groups nested deeper than the format allows.
pub fn write_scene(desc: &SceneDesc, options: &WriteOptions) -> Result<Written, WriteError> {
    let mut w = Writer { out: String::new(), warnings: Vec::new(), mesh_names: Vec::new() };
    if let Some(comment) = &options.comment {
        for line in comment.lines() {
            w.line(0, &format!("# {line}"));
        }
        w.out.push('\n');
    }
    w.settings(&desc.settings)?;
    w.camera(&desc.camera)?;
    let texture_names = unique_names(desc.textures.iter().map(texture_name), "texture");
    // Normal maps are data: their files are read back without sRGB decoding.
    let data: Vec<usize> = desc.materials.iter().filter_map(|m| m.normal_map.map(|n| n.texture)).collect();
    for (i, (texture, name)) in desc.textures.iter().zip(&texture_names).enumerate() {
        w.texture(texture, name, options.base_dir.as_deref(), data.contains(&i))?;
    }
    if !desc.textures.is_empty() {
        w.out.push('\n');
    }
    let material_names = unique_names(desc.materials.iter().map(|m| m.name.as_str()), "material");
    for (material, name) in desc.materials.iter().zip(&material_names) {
        w.material(material, name, &texture_names)?;
    }
    for light in &desc.lights {
        w.light(light, &texture_names)?;
    }
    if !desc.lights.is_empty() {
        w.out.push('\n');
    }
    w.mesh_names = unique_names(desc.meshes.iter().map(|m| m.name.as_str()), "mesh");
    for (index, mesh) in desc.meshes.iter().enumerate() {
        w.mesh(mesh, index, &desc.meshes, options.base_dir.as_deref())?;
    }
    if !desc.meshes.is_empty() {
        w.out.push('\n');
    }
    for node in &desc.objects {
        w.node(node, 0, &material_names)?;
    }
    Ok(Written { text: w.out, warnings: w.warnings })
}

struct Writer {
    out: String,
    warnings: Vec<String>,
    /// The names the meshes are written under, by index.
    mesh_names: Vec<String>,
}

impl Writer {
    fn line(&mut self, depth: usize, text: &str) {
        for _ in 0..depth {
            self.out.push_str("  ");
        }
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn settings(&mut self, s: &RenderSettings) -> Result<(), WriteError> {
        let transfer = match s.output_transfer {
            Transfer::Srgb => "srgb",
            Transfer::Identity => "identity",
        };
        let pattern = match s.pattern {
            SamplePattern::Grid => "grid",
            SamplePattern::CornersAndCentre => "corners",
            SamplePattern::Jittered => "jittered",
            SamplePattern::Sobol => "sobol",
        };
        let filter = match s.filter.kind {
            FilterKind::Box => "box",
            FilterKind::Tent => "tent",
            FilterKind::Gaussian => "gaussian",
            FilterKind::Mitchell => "mitchell",
            FilterKind::Lanczos => "lanczos",
        };
        let lines = [
            format!("width {}", s.width),
            format!("height {}", s.height),
            format!("samples {}", s.samples_per_axis),
            format!("max_depth {}", s.max_depth),
            format!("min_contribution {}", num(s.min_contribution, "min_contribution")?),
            format!("background {}", vec3(s.background, "background")?),
            format!("ambient {}", vec3(s.ambient_light, "ambient")?),
            format!("shadows {}", s.features.shadows),
            format!("reflections {}", s.features.reflections),
            format!("refractions {}", s.features.refractions),
            format!("textures {}", s.features.textures),
            format!("transparent_shadows {}", s.features.transparent_shadows),
            format!("output_transfer \"{transfer}\""),
            format!("pattern \"{pattern}\""),
            format!("filter \"{filter}\""),
            format!("filter_radius {}", num(s.filter.radius, "filter_radius")?),
            format!("seed {}", s.seed),
            self.integrator(&s.integrator),
        ];
        let mut lines = lines.to_vec();
        if let Some(spp) = s.spp {
            if !(1..=MAX_SPP).contains(&spp) {
                return fail(format!("spp {spp} is outside what a .glint file allows (1 to {MAX_SPP})"));
            }
            lines.push(format!("spp {spp}"));
        }
        if s.fps != defaults_fps() {
            lines.push(format!("fps {}", num(s.fps, "fps")?));
        }
        if let Some([first, last]) = s.frames {
            lines.push(format!("frames [{first} {last}]"));
        }
        if let Some(a) = s.adaptive {
            lines.push(format!(
                "adaptive [{} {} {}]",
                a.min_samples,
                a.max_samples,
                num(a.threshold, "adaptive threshold")?
            ));
        }
        self.line(0, "settings {");
        for l in &lines {
            self.line(1, l);
        }
        self.line(0, "}");
        // Settings added to the description after the format learnt them are compared
        // with their defaults, so nothing is dropped silently.
        let defaults = RenderSettings::default();
        #[allow(clippy::needless_update)] // fields the description may gain
        let rest = RenderSettings {
            width: defaults.width,
            height: defaults.height,
            samples_per_axis: defaults.samples_per_axis,
            max_depth: defaults.max_depth,
            min_contribution: defaults.min_contribution,
            background: defaults.background,
            ambient_light: defaults.ambient_light,
            features: defaults.features,
            output_transfer: defaults.output_transfer,
            pattern: defaults.pattern,
            filter: defaults.filter,
            adaptive: defaults.adaptive,
            seed: defaults.seed,
            integrator: defaults.integrator,
            spp: defaults.spp,
            fps: defaults.fps,
            frames: defaults.frames,
            ..s.clone()
        };
        if rest != defaults {
            self.warnings
                .push(format!("the .glint format cannot hold these render settings yet; they are left out: {rest:?}"));
        }
        Ok(())
    }

    /// `integrator whitted` or `integrator path { … }`. A depth beyond what a `.glint`
    /// number holds exactly is written as unlimited, with a warning.
    fn integrator(&mut self, integrator: &IntegratorDesc) -> String {
        let IntegratorDesc::Path(path) = integrator else {
            return "integrator whitted".to_owned();
        };
        let max_depth = match path.max_depth {
            u32::MAX => "-1".to_owned(),
            d if d <= MAX_PATH_DEPTH => d.to_string(),
            d => {
                self.warnings.push(format!(
                    "path max_depth {d} is beyond the largest a .glint file holds ({MAX_PATH_DEPTH}); \
                     it is written as unlimited (-1)"
                ));
                "-1".to_owned()
            }
        };
        let rr_depth = path.rr_depth.clamp(1, MAX_PATH_DEPTH);
        if rr_depth != path.rr_depth {
            self.warnings.push(format!(
                "path rr_depth {} is outside what a .glint file holds (1 to {MAX_PATH_DEPTH}); it is written as {rr_depth}",
                path.rr_depth
            ));
        }
        let sampler = match path.sampler {
            SamplerKind::Sobol => "sobol",
            SamplerKind::Independent => "independent",
        };
        format!("integrator path {{ max_depth {max_depth}  rr_depth {rr_depth}  sampler \"{sampler}\" }}")
    }

    fn camera(&mut self, c: &CameraDesc) -> Result<(), WriteError> {
        use glint_core::desc::FovAxis;
        let axis = match c.fov_axis {
            FovAxis::Y => String::new(),
            FovAxis::X => "  fov_axis \"x\"".into(),
            FovAxis::Diagonal => "  fov_axis \"diagonal\"".into(),
            FovAxis::Smaller => "  fov_axis \"smaller\"".into(),
            FovAxis::Larger => "  fov_axis \"larger\"".into(),
        };
        let lines = [
            format!("eye {}", vec3(c.eye, "camera eye")?),
            format!("look {}", vec3(c.look, "camera look")?),
            format!("up {}", vec3(c.up, "camera up")?),
            format!("fov {}{axis}", num(c.fov_y_degrees, "camera fov")?),
            format!("aperture {}", num(c.aperture_radius, "camera aperture")?),
            format!("focal_distance {}", num(c.focal_distance, "camera focal_distance")?),
        ];
        self.out.push('\n');
        self.line(0, "camera {");
        for l in &lines {
            self.line(1, l);
        }
        self.line(0, "}");
        self.out.push('\n');
        let defaults = CameraDesc::default();
        #[allow(clippy::needless_update)] // fields the description may gain
        let rest = CameraDesc {
            eye: defaults.eye,
            look: defaults.look,
            up: defaults.up,
            fov_y_degrees: defaults.fov_y_degrees,
            fov_axis: defaults.fov_axis,
            aperture_radius: defaults.aperture_radius,
            focal_distance: defaults.focal_distance,
            ..c.clone()
        };
        if rest != defaults {
            self.warnings
                .push(format!("the .glint format cannot hold these camera settings yet; they are left out: {rest:?}"));
        }
        Ok(())
    }

    fn texture(
        &mut self,
        t: &TextureDesc,
        name: &str,
        base_dir: Option<&Path>,
        linear: bool,
    ) -> Result<(), WriteError> {
        let line = match t {
            TextureDesc::Checker { even, odd, cells, filtered, .. } => format!(
                "texture {} checker {{ even {} odd {} cells {}{} }}",
                quote(name),
                vec3(*even, "checker even")?,
                vec3(*odd, "checker odd")?,
                vec2(*cells, "checker cells")?,
                if *filtered { " filtered true" } else { "" }
            ),
            TextureDesc::Image { path, sampling, .. } => {
                if path.is_empty() {
                    return fail(format!(
                        "image texture '{name}' has no source file, so a .glint file cannot refer to it; \
                         save its pixels as a PNG and load that"
                    ));
                }
                let file = texture_file(Path::new(path), base_dir);
                let encoding = if linear { " encoding \"linear\"" } else { "" };
                let sampling = sampling_properties(sampling);
                format!("texture {} image {{ file {}{sampling}{encoding} }}", quote(name), quote(&file))
            }
        };
        self.line(0, &line);
        Ok(())
    }

    fn material(&mut self, m: &MaterialDesc, name: &str, textures: &[String]) -> Result<(), WriteError> {
        let what = |field: &str| format!("material '{name}' {field}");
        let mut lines = vec![
            format!(
                "ka {}  kd {}  ks {}  kt {}",
                num(m.ka, &what("ka"))?,
                num(m.kd, &what("kd"))?,
                num(m.ks, &what("ks"))?,
                num(m.kt, &what("kt"))?
            ),
            format!("diffuse {}", vec3(m.diffuse, &what("diffuse"))?),
            format!(
                "specular {}  shininess {}",
                vec3(m.specular, &what("specular"))?,
                num(m.shininess, &what("shininess"))?
            ),
            format!("transmissive {}  ior {}", vec3(m.transmissive, &what("transmissive"))?, num(m.ior, &what("ior"))?),
        ];
        if let Some(ambient) = m.ambient {
            lines.push(format!("ambient {}", vec3(ambient, &what("ambient"))?));
        }
        if let Some(reflective) = m.reflective {
            lines.push(format!("reflective {}", vec3(reflective, &what("reflective"))?));
        }
        if let Some(texture) = m.texture {
            let Some(texture_name) = textures.get(texture) else {
                return fail(format!(
                    "material '{name}' uses texture {texture}, but the scene has {} textures",
                    textures.len()
                ));
            };
            lines.push(format!("texture {}", quote(texture_name)));
        }
        lines.push(format!(
            "blend {}  repeat {}",
            num(m.blend, &what("blend"))?,
            vec2(m.texture_repeat, &what("repeat"))?
        ));
        if let Some(b) = &m.bsdf {
            lines.push(bsdf(b, name, textures)?);
        }
        lines.push(format!("emission {}  two_sided {}", vec3(m.emission, &what("emission"))?, m.two_sided));
        if m.microfacet == glint_core::desc::MicrofacetKind::Beckmann {
            lines.push("microfacet \"beckmann\"".to_owned());
        }
        if !m.casts_shadows {
            lines.push("casts_shadows false".to_owned());
        }
        if m.highlight == glint_core::desc::Highlight::Blinn {
            lines.push("highlight \"blinn\"".to_owned());
        }
        if m.textured_ambient {
            lines.push("textured_ambient true".to_owned());
        }
        if let Some(map) = m.normal_map {
            let Some(texture_name) = textures.get(map.texture) else {
                return fail(format!(
                    "material '{name}' has normal map texture {}, which the scene lacks",
                    map.texture
                ));
            };
            lines.push(format!(
                "normal_map {}  normal_scale {}",
                quote(texture_name),
                num(map.scale, &what("normal_scale"))?
            ));
        }
        if let Some(texture) = m.emission_texture {
            let Some(texture_name) = textures.get(texture) else {
                return fail(format!("material '{name}' has emission texture {texture}, which the scene lacks"));
            };
            lines.push(format!("emission_texture {}", quote(texture_name)));
        }
        self.line(0, &format!("material {} {{", quote(name)));
        for l in &lines {
            self.line(1, l);
        }
        self.line(0, "}");
        let defaults = MaterialDesc::default();
        #[allow(clippy::needless_update)] // fields the description may gain
        let rest = MaterialDesc {
            name: defaults.name.clone(),
            ka: defaults.ka,
            kd: defaults.kd,
            ks: defaults.ks,
            kt: defaults.kt,
            ambient: defaults.ambient,
            diffuse: defaults.diffuse,
            specular: defaults.specular,
            reflective: defaults.reflective,
            transmissive: defaults.transmissive,
            shininess: defaults.shininess,
            ior: defaults.ior,
            texture: defaults.texture,
            blend: defaults.blend,
            texture_repeat: defaults.texture_repeat,
            bsdf: defaults.bsdf,
            emission: defaults.emission,
            two_sided: defaults.two_sided,
            microfacet: defaults.microfacet,
            casts_shadows: defaults.casts_shadows,
            normal_map: defaults.normal_map,
            emission_texture: defaults.emission_texture,
            highlight: defaults.highlight,
            textured_ambient: defaults.textured_ambient,
            ..m.clone()
        };
        if rest != defaults {
            self.warnings
                .push(format!("the .glint format cannot hold all of material '{name}' yet; left out: {rest:?}"));
        }
        Ok(())
    }

    fn light(&mut self, light: &LightDesc, textures: &[String]) -> Result<(), WriteError> {
        let line = match light {
            LightDesc::Environment(env) => {
                let what = "environment light";
                let mut parts = vec![format!("radiance {}", vec3(env.radiance, what)?)];
                if let Some(texture) = env.texture {
                    parts.push(format!("texture {}", quote(texture_ref(texture, textures, what)?)));
                }
                for op in &env.transform {
                    parts.push(transform(op, "the environment light")?);
                }
                format!("light environment {{ {} }}", parts.join("  "))
            }
            &LightDesc::Point { position, color, attenuation } => format!(
                "light point {{ position {} color {} attenuation {} }}",
                vec3(position, "light position")?,
                vec3(color, "light color")?,
                vec3(attenuation, "light attenuation")?
            ),
            &LightDesc::Directional { direction, color } => format!(
                "light directional {{ direction {} color {} }}",
                vec3(direction, "light direction")?,
                vec3(color, "light color")?
            ),
            &LightDesc::Spot { position, direction, color, attenuation, angle_degrees, penumbra_degrees, falloff } => {
                format!(
                    "light spot {{ position {} direction {} color {} attenuation {} angle {} penumbra {}{} }}",
                    vec3(position, "light position")?,
                    vec3(direction, "light direction")?,
                    vec3(color, "light color")?,
                    vec3(attenuation, "light attenuation")?,
                    num(angle_degrees, "light angle")?,
                    num(penumbra_degrees, "light penumbra")?,
                    if falloff == glint_core::desc::SpotFalloff::Linear { " falloff \"linear\"" } else { "" }
                )
            }
            &LightDesc::Area { shape, color, attenuation, samples } => {
                let what = "area light";
                let (kind, place) = match shape {
                    AreaShape::Rectangle { corner, edge_u, edge_v } => (
                        "rectangle",
                        format!(
                            "corner {} edge_u {} edge_v {}",
                            vec3(corner, what)?,
                            vec3(edge_u, what)?,
                            vec3(edge_v, what)?
                        ),
                    ),
                    AreaShape::Disk { center, normal, radius } => (
                        "disk",
                        format!(
                            "position {} normal {} radius {}",
                            vec3(center, what)?,
                            vec3(normal, what)?,
                            num(radius, what)?
                        ),
                    ),
                    AreaShape::Sphere { center, radius } => {
                        ("sphere", format!("position {} radius {}", vec3(center, what)?, num(radius, what)?))
                    }
                };
                format!(
                    "light {kind} {{ {place} color {} attenuation {} samples {samples} }}",
                    vec3(color, what)?,
                    vec3(attenuation, what)?
                )
            }
        };
        self.line(0, &line);
        Ok(())
    }

    /// `mesh "name" { file "…" }`: a .glint file refers to mesh files, so a mesh must
    /// be the whole content of a file (as `mesh` definitions and course meshes are).
    fn mesh(
        &mut self,
        mesh: &MeshDesc,
        index: usize,
        all: &[MeshDesc],
        base_dir: Option<&Path>,
    ) -> Result<(), WriteError> {
        let name = &self.mesh_names[index];
        if mesh.path.is_empty() {
            return fail(format!(
                "mesh '{name}' was built in code, not read from a file; a .glint file can only name mesh files"
            ));
        }
        if all.iter().filter(|m| m.path == mesh.path).count() > 1 {
            return fail(format!(
                "the file {} holds several meshes (one per material); a .glint `mesh` reads a file as one mesh",
                mesh.path
            ));
        }
        let file = texture_file(Path::new(&mesh.path), base_dir);
        self.line(0, &format!("mesh {} {{ file {} }}", quote(name), quote(&file)));
        Ok(())
    }

    /// CSG, blobs, implicit surfaces, quadrics and superellipsoids, in the syntax of
    /// docs/scene-format.md.
    fn solid(
        &mut self,
        solid: &SolidDesc,
        statements: Vec<String>,
        depth: usize,
        materials: &[String],
        origin: &str,
    ) -> Result<(), WriteError> {
        let material = |index: usize| -> Result<String, WriteError> {
            match materials.get(index) {
                Some(name) => Ok(format!("material {}", quote(name))),
                None => fail(format!("the object at {origin} uses material {index}, which the scene lacks")),
            }
        };
        let what = format!("solid at {origin}");
        let mut parts = Vec::new();
        let keyword = match solid {
            SolidDesc::Csg { op, children } => {
                let keyword = match op {
                    SetOp::Union => "union",
                    SetOp::Intersection => "intersection",
                    SetOp::Difference => "difference",
                };
                self.line(depth, &format!("{keyword} {{"));
                for s in &statements {
                    self.line(depth + 1, s);
                }
                for child in children {
                    self.node(child, depth + 1, materials)?;
                }
                self.line(depth, "}");
                return Ok(());
            }
            SolidDesc::Blob { blob, material: m } => {
                parts.push(material(*m)?);
                parts.push(format!("threshold {}", num(blob.threshold, &what)?));
                for c in &blob.components {
                    let mut fields = match c.shape {
                        BlobComponentShape::Sphere { center, radius } => {
                            vec![
                                format!("component sphere {{ center {}", vec3(center, &what)?),
                                format!("radius {}", num(radius, &what)?),
                            ]
                        }
                        BlobComponentShape::Cylinder { from, to, radius } => vec![
                            format!("component cylinder {{ from {}", vec3(from, &what)?),
                            format!("to {}", vec3(to, &what)?),
                            format!("radius {}", num(radius, &what)?),
                        ],
                    };
                    fields.push(format!("strength {}", num(c.strength, &what)?));
                    for op in &c.transform {
                        fields.push(transform(op, origin)?);
                    }
                    parts.push(format!("{} }}", fields.join("  ")));
                }
                "blob"
            }
            SolidDesc::Implicit { implicit, material: m } => {
                parts.push(material(*m)?);
                parts.push(format!("function {}", quote(&implicit.function)));
                let [lo, hi] = implicit.bounds;
                parts.push(format!("bounds {} {}", vec3(lo, &what)?, vec3(hi, &what)?));
                if let Some(l) = implicit.lipschitz {
                    parts.push(format!("lipschitz {}", num(l, &what)?));
                }
                "implicit"
            }
            SolidDesc::Quadric { coefficients, bounds, material: m } => {
                parts.push(material(*m)?);
                let c = coefficients.iter().map(|&x| num(x, &what)).collect::<Result<Vec<_>, _>>()?;
                parts.push(format!("coefficients [{}]", c.join(" ")));
                if let Some([lo, hi]) = bounds {
                    parts.push(format!("bounds {} {}", vec3(*lo, &what)?, vec3(*hi, &what)?));
                }
                "quadric"
            }
            SolidDesc::Superellipsoid { e1, e2, material: m } => {
                parts.push(material(*m)?);
                parts.push(format!("exponents [{} {}]", num(*e1, &what)?, num(*e2, &what)?));
                "superellipsoid"
            }
        };
        parts.extend(statements);
        self.line(depth, &format!("{keyword} {{ {} }}", parts.join("  ")));
        Ok(())
    }

    fn node(&mut self, node: &NodeDesc, depth: usize, materials: &[String]) -> Result<(), WriteError> {
        if depth >= MAX_NESTING {
            return fail(format!(
                "the object at {} is nested {} groups deep; a .glint file allows at most {}",
                node.origin,
                depth,
                MAX_NESTING - 1
            ));
        }
        let mut statements = Vec::new();
        for op in &node.transform {
            statements.push(transform(op, &node.origin)?);
        }
        match &node.kind {
            NodeKind::Shape { shape, material } => {
                let Some(material_name) = materials.get(*material) else {
                    return fail(format!(
                        "the object at {} uses material {material}, but the scene has {} materials",
                        node.origin,
                        materials.len()
                    ));
                };
                let (keyword, extra): (String, Option<String>) = match *shape {
                    ShapeDesc::Sphere => ("sphere".into(), None),
                    ShapeDesc::Cube => ("cube".into(), None),
                    ShapeDesc::Cylinder => ("cylinder".into(), None),
                    ShapeDesc::Cone => ("cone".into(), None),
                    ShapeDesc::Plane => ("plane".into(), None),
                    ShapeDesc::Disk => ("disk".into(), None),
                    ShapeDesc::Rectangle => ("rectangle".into(), None),
                    ShapeDesc::Torus { minor_radius } => {
                        ("torus".into(), Some(format!("minor_radius {}", num(minor_radius, "torus minor_radius")?)))
                    }
                    ShapeDesc::Mesh { index } => {
                        let Some(name) = self.mesh_names.get(index) else {
                            return fail(format!(
                                "the object at {} uses mesh {index}, which the scene lacks",
                                node.origin
                            ));
                        };
                        (format!("mesh_instance {}", quote(name)), None)
                    }
                };
                let mut parts = vec![format!("material {}", quote(material_name))];
                parts.extend(extra);
                parts.extend(statements);
                self.line(depth, &format!("{keyword} {{ {} }}", parts.join("  ")));
            }
            NodeKind::Solid(solid) => self.solid(solid, statements, depth, materials, &node.origin)?,
            NodeKind::Group(children) => {
                self.line(depth, "group {");
                for s in &statements {
                    self.line(depth + 1, s);
                }
                for child in children {
                    self.node(child, depth + 1, materials)?;
                }
                self.line(depth, "}");
            }
            NodeKind::Moving { close, children } => {
                self.line(depth, "moving {");
                for s in &statements {
                    self.line(depth + 1, s);
                }
                let close = close.iter().map(|op| transform(op, &node.origin)).collect::<Result<Vec<_>, _>>()?;
                self.line(depth + 1, &format!("close {{ {} }}", close.join("  ")));
                for child in children {
                    self.node(child, depth + 1, materials)?;
                }
                self.line(depth, "}");
            }
        }
        Ok(())
    }
}

/// `bsdf kind { … }` with every parameter written out.
fn bsdf(b: &BsdfDesc, material: &str, textures: &[String]) -> Result<String, WriteError> {
    let what = format!("material '{material}' bsdf");
    let what = what.as_str();
    // A parameter and, when it has one, its texture: `name value  texture_name "t"`.
    let color = |name: &str, texture_name: &str, p: &ColorParam| -> Result<String, WriteError> {
        let mut text = format!("{name} {}", vec3(p.value, what)?);
        if let Some(t) = p.texture {
            text.push_str(&format!("  {texture_name} {}", quote(texture_ref(t, textures, what)?)));
        }
        Ok(text)
    };
    let roughness = |p: &ScalarParam| -> Result<String, WriteError> {
        let mut text = format!("roughness {}", num(p.value, what)?);
        if let Some(t) = p.texture {
            text.push_str(&format!("  roughness_texture {}", quote(texture_ref(t, textures, what)?)));
        }
        Ok(text)
    };
    let iors = |int_ior: f32, ext_ior: f32| -> Result<String, WriteError> {
        Ok(format!("ior {}  ext_ior {}", num(int_ior, what)?, num(ext_ior, what)?))
    };
    let (kind, parts) = match b {
        BsdfDesc::Diffuse { reflectance } => ("diffuse", vec![color("reflectance", "texture", reflectance)?]),
        BsdfDesc::Conductor { eta, k, specular, alpha } => (
            "conductor",
            vec![
                format!("eta {}  k {}", vec3(*eta, what)?, vec3(*k, what)?),
                color("specular", "specular_texture", specular)?,
                roughness(alpha)?,
            ],
        ),
        BsdfDesc::Dielectric { int_ior, ext_ior, reflectance, transmittance, alpha } => (
            "dielectric",
            vec![
                iors(*int_ior, *ext_ior)?,
                format!("reflectance {}  transmittance {}", vec3(*reflectance, what)?, vec3(*transmittance, what)?),
                roughness(alpha)?,
            ],
        ),
        BsdfDesc::ThinDielectric { int_ior, ext_ior, reflectance, transmittance } => (
            "thin_dielectric",
            vec![
                iors(*int_ior, *ext_ior)?,
                format!("reflectance {}  transmittance {}", vec3(*reflectance, what)?, vec3(*transmittance, what)?),
            ],
        ),
        BsdfDesc::Plastic { diffuse, int_ior, ext_ior, specular, alpha, nonlinear } => (
            "plastic",
            vec![
                color("diffuse", "texture", diffuse)?,
                iors(*int_ior, *ext_ior)?,
                format!("specular {}", vec3(*specular, what)?),
                roughness(alpha)?,
                format!("nonlinear {nonlinear}"),
            ],
        ),
        BsdfDesc::MetallicRoughness { base, metallic, alpha, ior } => {
            let mut share = format!("metallic {}", num(metallic.value, what)?);
            if let Some(t) = metallic.texture {
                share.push_str(&format!("  metallic_texture {}", quote(texture_ref(t, textures, what)?)));
            }
            (
                "metallic_roughness",
                vec![color("base", "texture", base)?, share, roughness(alpha)?, format!("ior {}", num(*ior, what)?)],
            )
        }
    };
    Ok(format!("bsdf {kind} {{ {} }}", parts.join("  ")))
}

/// The name a texture index is written under.
fn texture_ref<'t>(index: usize, textures: &'t [String], what: &str) -> Result<&'t str, WriteError> {
    match textures.get(index) {
        Some(name) => Ok(name),
        None => fail(format!("{what} uses texture {index}, but the scene has {} textures", textures.len())),
    }
}

/// One transform statement.
fn transform(op: &TransformOp, origin: &str) -> Result<String, WriteError> {
    let what = format!("transform of the object at {origin}");
    Ok(match *op {
        TransformOp::Translate(t) => format!("translate {}", vec3(t, &what)?),
        TransformOp::Scale(s) => format!("scale {}", vec3(s, &what)?),
        TransformOp::Rotate { axis, degrees } => format!("rotate {} {}", vec3(axis, &what)?, num(degrees, &what)?),
        TransformOp::Matrix(rows) => {
            let numbers: Vec<String> = rows.iter().flatten().map(|x| num(*x, &what)).collect::<Result<_, _>>()?;
            format!("matrix [{}]", numbers.join(" "))
        }
    })
}

/// The shortest decimal that reads back (through the lexer's f64 → f32) to exactly `x`.
pub fn num(x: f32, what: &str) -> Result<String, WriteError> {
    if !x.is_finite() {
        return fail(format!("{what} is {x}; a .glint file holds only finite numbers"));
    }
    let reads_back = |s: &str| s.parse::<f64>().is_ok_and(|y| y as f32 == x);
    let plain = format!("{x}");
    let short = if plain.len() > 12 { format!("{x:e}") } else { plain };
    if reads_back(&short) {
        return Ok(short);
    }
    // The shortest f32 decimal can round twice on the way back (to f64, then to f32);
    // the exact value of the f32 as an f64 never does.
    Ok(format!("{}", f64::from(x)))
}

fn vec3(v: Vec3, what: &str) -> Result<String, WriteError> {
    Ok(format!("[{} {} {}]", num(v.x, what)?, num(v.y, what)?, num(v.z, what)?))
}

fn vec2(v: Vec2, what: &str) -> Result<String, WriteError> {
    Ok(format!("[{} {}]", num(v.x, what)?, num(v.y, what)?))
}

/// A `.glint` string literal: only `\"` and `\\` are escapes, and a string stays on one
/// line, so line breaks become spaces.
fn quote(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' | '\r' => out.push(' '),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

fn texture_name(t: &TextureDesc) -> &str {
    match t {
        TextureDesc::Image { name, .. } | TextureDesc::Checker { name, .. } => name,
    }
}

/// The names as written: line breaks removed, empty ones named `{kind}-{index}`, and
/// repeats made unique with `-2`, `-3`, … (the format refuses a name defined twice).
pub fn unique_names<'a>(names: impl Iterator<Item = &'a str>, kind: &str) -> Vec<String> {
    let mut taken = std::collections::HashSet::new();
    let mut out = Vec::new();
    for (i, name) in names.enumerate() {
        let clean: String = name.chars().map(|c| if c == '\n' || c == '\r' { ' ' } else { c }).collect();
        let base = if clean.is_empty() { format!("{kind}-{}", i + 1) } else { clean };
        let mut candidate = base.clone();
        let mut n = 2;
        while taken.contains(&candidate) {
            candidate = format!("{base}-{n}");
            n += 1;
        }
        taken.insert(candidate.clone());
        out.push(candidate);
    }
    out
}

/// How the output file should name the image at `path`: relative to `base_dir` when
/// both resolve and share more than the root, else the absolute (or stored) path.
fn texture_file(path: &Path, base_dir: Option<&Path>) -> String {
    let slashed = |p: &Path| p.to_string_lossy().replace('\\', "/");
    let Some(base_dir) = base_dir else { return path.display().to_string() };
    let dir = if base_dir.as_os_str().is_empty() { Path::new(".") } else { base_dir };
    let (Ok(file), Ok(dir)) = (std::fs::canonicalize(path), std::fs::canonicalize(dir)) else {
        return path.display().to_string();
    };
    match relative_path(&file, &dir) {
        Some(relative) => slashed(&relative),
        None => file.display().to_string(),
    }
}

/// `file` relative to the folder `dir` (both absolute), or `None` when they share
/// nothing but the root.
pub fn relative_path(file: &Path, dir: &Path) -> Option<PathBuf> {
    let f: Vec<Component> = file.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = f.iter().zip(&d).take_while(|(a, b)| a == b).count();
    let shares_more_than_root = f[..common].iter().any(|c| matches!(c, Component::Normal(_)));
    if !shares_more_than_root {
        return None;
    }
    let mut relative = PathBuf::new();
    for _ in common..d.len() {
        relative.push("..");
    }
    for c in &f[common..] {
        relative.push(c.as_os_str());
    }
    Some(relative)
}

/// The first difference between two descriptions that changes the picture, ignoring
/// node origins, material and texture names and image texture paths (which a written
/// file legitimately changes); `None` when they render the same.
pub fn difference(a: &SceneDesc, b: &SceneDesc) -> Option<String> {
    if a.settings != b.settings {
        return Some(format!("settings differ: {:?} vs {:?}", a.settings, b.settings));
    }
    if a.camera != b.camera {
        return Some(format!("cameras differ: {:?} vs {:?}", a.camera, b.camera));
    }
    if a.lights != b.lights {
        return Some(format!("lights differ: {:?} vs {:?}", a.lights, b.lights));
    }
    if a.materials.len() != b.materials.len() {
        return Some(format!("{} materials vs {}", a.materials.len(), b.materials.len()));
    }
    for (x, y) in a.materials.iter().zip(&b.materials) {
        let named = |m: &MaterialDesc| MaterialDesc { name: String::new(), ..m.clone() };
        if named(x) != named(y) {
            return Some(format!("material '{}' differs: {x:?} vs {y:?}", x.name));
        }
    }
    if a.textures.len() != b.textures.len() {
        return Some(format!("{} textures vs {}", a.textures.len(), b.textures.len()));
    }
    for (x, y) in a.textures.iter().zip(&b.textures) {
        let same = match (x, y) {
            (
                TextureDesc::Checker { even, odd, cells, filtered, .. },
                TextureDesc::Checker { even: e2, odd: o2, cells: c2, filtered: f2, .. },
            ) => (even, odd, cells, filtered) == (e2, o2, c2, f2),
            (
                TextureDesc::Image { width, height, texels, .. },
                TextureDesc::Image { width: w2, height: h2, texels: t2, .. },
            ) => (width, height, texels) == (w2, h2, t2),
            _ => false,
        };
        if !same {
            return Some(format!("texture '{}' differs", texture_name(x)));
        }
    }
    nodes_difference(&a.objects, &b.objects)
}

fn nodes_difference(a: &[NodeDesc], b: &[NodeDesc]) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{} objects vs {} in the same group", a.len(), b.len()));
    }
    for (x, y) in a.iter().zip(b) {
        if x.transform != y.transform {
            return Some(format!(
                "the transform of the object at {} differs: {:?} vs {:?}",
                x.origin, x.transform, y.transform
            ));
        }
        match (&x.kind, &y.kind) {
            (NodeKind::Group(xs), NodeKind::Group(ys))
            | (
                NodeKind::Solid(SolidDesc::Csg { children: xs, .. }),
                NodeKind::Solid(SolidDesc::Csg { children: ys, .. }),
            )
            | (NodeKind::Moving { children: xs, .. }, NodeKind::Moving { children: ys, .. }) => {
                let same_kind = match (&x.kind, &y.kind) {
                    (NodeKind::Solid(SolidDesc::Csg { op: a, .. }), NodeKind::Solid(SolidDesc::Csg { op: b, .. })) => {
                        a == b
                    }
                    (NodeKind::Moving { close: a, .. }, NodeKind::Moving { close: b, .. }) => a == b,
                    _ => true,
                };
                if !same_kind {
                    return Some(format!("the object at {} differs in its operation or motion", x.origin));
                }
                if let Some(d) = nodes_difference(xs, ys) {
                    return Some(d);
                }
            }
            (s, t) if s == t => {}
            (s, t) => return Some(format!("the object at {} differs: {s:?} vs {t:?}", x.origin)),
        }
    }
    None
}

/// Writes `text` to `path` through a temporary sibling renamed into place, so a failed
/// write never leaves a half-written scene behind.
///
/// # Errors
///
/// The I/O error, after removing the temporary file.
pub fn save_atomically(path: &Path, text: &str) -> std::io::Result<()> {
    crate::atomic_file::write_atomically(path, |tmp| std::fs::write(tmp, text), |e| e)
}

/// Frames per second when a scene does not say.
fn defaults_fps() -> f32 {
    RenderSettings::default().fps
}

/// The `wrap`/`filter` properties of an image texture that differ from the defaults,
/// each with a leading space.
fn sampling_properties(sampling: &glint_core::desc::ImageSampling) -> String {
    use glint_core::desc::TextureWrap;
    let word = |w: TextureWrap| match w {
        TextureWrap::Repeat => "\"repeat\"",
        TextureWrap::Clamp => "\"clamp\"",
        TextureWrap::Mirror => "\"mirror\"",
    };
    let mut out = String::new();
    let [u, v] = sampling.wrap;
    if u == v && u != TextureWrap::Repeat {
        out += &format!(" wrap {}", word(u));
    } else if u != v {
        out += &format!(" wrap_u {} wrap_v {}", word(u), word(v));
    }
    if sampling.nearest {
        out += " filter \"nearest\"";
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_back_exactly() {
        for x in [0.0f32, -0.0, 1.0, 0.1, 1.0 / 3.0, 1e-7, 3.4e38, -2.5e-20, 16777217.0, 0.001953125, 1.0e10] {
            let s = num(x, "x").unwrap();
            assert_eq!(s.parse::<f64>().unwrap() as f32, x, "{s}");
        }
        assert_eq!(num(0.5, "x").unwrap(), "0.5");
        assert_eq!(num(45.0, "x").unwrap(), "45");
        assert!(num(f32::NAN, "x").is_err());
    }

    #[test]
    fn names_are_made_unique_and_single_line() {
        let names = unique_names(["a", "", "a", "b\nc", "a-2"].into_iter(), "material");
        assert_eq!(names, vec!["a", "material-2", "a-2", "b c", "a-2-2"]);
        assert_eq!(quote(r#"say "hi" \ "#), r#""say \"hi\" \\ ""#);
    }

    #[test]
    fn relative_paths_climb_to_the_common_folder() {
        let rel = relative_path(Path::new("/work/scenes/tex/a.png"), Path::new("/work/out")).unwrap();
        assert_eq!(rel, Path::new("../scenes/tex/a.png"));
        assert_eq!(relative_path(Path::new("/a/b.png"), Path::new("/c")), None);
    }
}
