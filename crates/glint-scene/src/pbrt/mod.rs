//! pbrt-v4 scenes (`.pbrt`): the directives, shapes, materials, lights and textures
//! glint can render the same way, read into a [`SceneDesc`]. What glint cannot
//! render exactly is approximated or skipped with a warning naming the file and line;
//! malformed input is an error at its file, line and column (see `docs/formats.md`).
//!
//! pbrt reads a scene as a stream of directives that change a graphics state (the
//! current transform, material, area light) and emit shapes and lights with it;
//! [`directives`] runs that state machine, with one module per kind of object
//! ([`camera`], [`shapes`], [`materials`], [`lights`], [`textures`]) and
//! [`params`]/[`spectra`] for the typed parameter lists they share.
//!
//! Handedness: pbrt's camera space has +x to the right of the image, +y up and +z
//! forward, a left-handed frame; glint's camera has the image's right along
//! `look × up`. Where the two disagree (a camera transform that is a proper rotation,
//! as `LookAt` gives), the whole world is mirrored in x ([`Reader::mirror`]), which
//! renders pbrt's image, not its mirror image.

mod camera;
mod directives;
mod lexer;
mod lights;
mod materials;
mod meshes;
mod params;
mod shapes;
mod spectra;
mod subdivision;
mod textures;

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use glam::{Mat4, Vec3};
use glint_core::desc::{MaterialDesc, NodeDesc, NodeKind, SceneDesc, TransformOp};

use crate::detect::{Loaded, SceneFormat};
use crate::error::SceneError;
use crate::source::{Pos, Source};
use spectra::ColorSpace;

/// Reads a pbrt-v4 scene file.
///
/// # Errors
///
/// A [`SceneError`] at the file, line and column of the first problem: a malformed
/// token or parameter list, an unknown directive, a file that cannot be read.
pub fn load_pbrt(path: &Path) -> Result<Loaded, SceneError> {
    let text = crate::input::read_text(path, crate::input::InputKind::Scene)?;
    load_text(path, &text)
}

/// Reads pbrt scene text that came from `path` (for [`crate::load_any`], which has
/// read the file already to tell its format).
pub(crate) fn load_text(path: &Path, text: &str) -> Result<Loaded, SceneError> {
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    read(text, Source { name: path.display().to_string(), dir })
}

/// Reads pbrt scene text that did not necessarily come from a file: `file_name` names
/// it in messages and `scene_dir` is where relative paths (includes, meshes, images)
/// start.
///
/// # Errors
///
/// As [`load_pbrt`].
pub fn parse_pbrt(text: &str, file_name: &str, scene_dir: &Path) -> Result<Loaded, SceneError> {
    read(text, Source { name: file_name.to_owned(), dir: scene_dir.to_path_buf() })
}

/// The directives a pbrt file may start with, for telling the format by content.
const OPENING_DIRECTIVES: [&str; 14] = [
    "LookAt",
    "Camera",
    "Film",
    "Sampler",
    "Integrator",
    "WorldBegin",
    "Transform",
    "ConcatTransform",
    "Scale",
    "Rotate",
    "Translate",
    "PixelFilter",
    "ColorSpace",
    "Option",
];

/// Whether `text` looks like a pbrt scene: its first word (after `#` comments) is one
/// of the directives a pbrt scene starts with.
pub fn is_pbrt(text: &str) -> bool {
    let first = text
        .trim_start_matches('\u{feff}')
        .lines()
        .map(|l| l.split('#').next().unwrap_or("").trim())
        .find(|l| !l.is_empty())
        .unwrap_or("");
    let word = first.split(|c: char| !c.is_ascii_alphanumeric()).next().unwrap_or("");
    OPENING_DIRECTIVES.contains(&word) && first.len() > word.len() || word == "WorldBegin"
}

fn read(text: &str, src: Source) -> Result<Loaded, SceneError> {
    let src = Rc::new(src);
    let mut reader = Reader::new();
    reader.run(text, &src, 0)?;
    let scene = reader.finish(&src)?;
    Ok(Loaded { scene, format: SceneFormat::Pbrt, warnings: reader.warnings })
}

/// A diffuse area light in the graphics state: the shapes that follow emit `radiance`.
#[derive(Clone, Debug, PartialEq)]
struct AreaLight {
    radiance: Vec3,
    /// pbrt's `power` (radiant flux) when given: each shape's radiance is then chosen so
    /// that it emits this much, `L = power / (π · area · sides)`.
    power: Option<f32>,
    two_sided: bool,
    /// Numbers the `AreaLightSource` directives, to share emissive materials.
    id: usize,
}

/// pbrt's graphics state: what `AttributeBegin` saves and `AttributeEnd` restores.
#[derive(Clone, Debug)]
struct GraphicsState {
    /// The current transformation matrix: camera-from-world before `WorldBegin`,
    /// world-from-object after.
    ctm: Mat4,
    reverse_orientation: bool,
    /// Index of the current material; `None` is pbrt's default (diffuse, 0.5).
    material: Option<usize>,
    area_light: Option<AreaLight>,
    color_space: ColorSpace,
}

impl Default for GraphicsState {
    fn default() -> Self {
        Self {
            ctm: Mat4::IDENTITY,
            reverse_orientation: false,
            material: None,
            area_light: None,
            color_space: ColorSpace::Srgb,
        }
    }
}

/// A saved state and what saved it (`AttributeBegin` or the old `TransformBegin`,
/// which saves only the transform), with where, for unbalanced-block errors.
struct Saved {
    state: GraphicsState,
    transform_only: bool,
    pos: Pos,
    src: Rc<Source>,
}

/// A texture by name: an image or checkerboard in the scene's list times a factor
/// (pbrt's `scale` texture), or a constant.
#[derive(Clone, Copy, Debug, PartialEq)]
enum TextureRef {
    Scaled(usize, Vec3),
    Constant(Vec3),
}

/// The state of one scene being read.
struct Reader {
    scene: SceneDesc,
    warnings: Vec<String>,
    gs: GraphicsState,
    stack: Vec<Saved>,
    named_coordinate_systems: HashMap<String, Mat4>,
    /// pbrt's camera-from-world when `Camera` was given.
    camera_from_world: Option<Mat4>,
    in_world: bool,
    /// Whether the world is mirrored in x to keep pbrt's image unmirrored (decided at
    /// `WorldBegin`; see the module documentation).
    mirror: bool,
    named_materials: HashMap<String, usize>,
    /// Textures by name; pbrt keeps float and spectrum textures apart, as does this.
    textures: HashMap<(bool, String), TextureRef>,
    /// Finished `ObjectBegin` definitions: their nodes, in world-from-object terms.
    objects: HashMap<String, Vec<NodeDesc>>,
    /// The definition being read, between `ObjectBegin` and `ObjectEnd`.
    current_object: Option<(String, Vec<NodeDesc>)>,
    /// Shapes of the world (inside the mirroring root at the end).
    nodes: Vec<NodeDesc>,
    /// Emitting copies of materials, by (material, area light id).
    emissive: HashMap<(usize, usize), usize>,
    area_light_count: usize,
    default_material: Option<usize>,
    /// `Integrator` seen, so the default can be applied otherwise.
    integrator_seen: bool,
}

impl Reader {
    fn new() -> Self {
        let mut scene = SceneDesc::default();
        camera::pbrt_defaults(&mut scene);
        Self {
            scene,
            warnings: Vec::new(),
            gs: GraphicsState::default(),
            stack: Vec::new(),
            named_coordinate_systems: HashMap::new(),
            camera_from_world: None,
            in_world: false,
            mirror: false,
            named_materials: HashMap::new(),
            textures: HashMap::new(),
            objects: HashMap::new(),
            current_object: None,
            nodes: Vec::new(),
            emissive: HashMap::new(),
            area_light_count: 0,
            default_material: None,
            integrator_seen: false,
        }
    }

    /// The scene, once every file is read: the world's shapes under one root that
    /// carries the mirror, if any.
    fn finish(&mut self, src: &Source) -> Result<SceneDesc, SceneError> {
        if let Some(open) = self.stack.last() {
            return Err(open.src.invalid(open.pos, "this AttributeBegin is never closed by AttributeEnd"));
        }
        if let Some((name, _)) = &self.current_object {
            return Err(src.invalid(Pos::default(), format!("ObjectBegin \"{name}\" is never closed by ObjectEnd")));
        }
        if !self.in_world {
            self.warnings.push(format!("{}: the file has no WorldBegin: the scene is empty", src.name));
            self.begin_world();
        }
        let transform = if self.mirror { vec![TransformOp::Scale(Vec3::new(-1.0, 1.0, 1.0))] } else { Vec::new() };
        let nodes = std::mem::take(&mut self.nodes);
        if !nodes.is_empty() {
            let origin = format!("{}:1:1", src.name);
            self.scene.objects.push(NodeDesc { transform, kind: NodeKind::Group(nodes), origin });
        }
        Ok(std::mem::take(&mut self.scene))
    }

    /// Enters the world block: the camera is fixed and the transform starts afresh.
    fn begin_world(&mut self) {
        let camera_from_world = self.camera_from_world.unwrap_or(Mat4::IDENTITY);
        let world_from_camera = camera_from_world.inverse();
        self.mirror = camera::needs_mirror(world_from_camera);
        camera::place(&mut self.scene.camera, world_from_camera, self.mirror);
        self.named_coordinate_systems.insert("camera".to_owned(), world_from_camera);
        self.named_coordinate_systems.insert("world".to_owned(), Mat4::IDENTITY);
        self.in_world = true;
        self.gs.ctm = Mat4::IDENTITY;
    }

    /// A point of pbrt's world in glint's world (mirrored when the world is).
    fn world_point(&self, p: Vec3) -> Vec3 {
        if self.mirror { Vec3::new(-p.x, p.y, p.z) } else { p }
    }

    /// Adds a material and returns its index.
    fn add_material(&mut self, m: MaterialDesc) -> usize {
        self.scene.materials.push(m);
        self.scene.materials.len() - 1
    }

    /// The current material for a shape, made emissive when an area light is on.
    fn shape_material(&mut self) -> usize {
        let base = match self.gs.material {
            Some(m) => m,
            None => *self.default_material.get_or_insert_with(|| {
                let m = materials::default_material();
                self.scene.materials.push(m);
                self.scene.materials.len() - 1
            }),
        };
        let Some(light) = self.gs.area_light.clone() else { return base };
        if let Some(&m) = self.emissive.get(&(base, light.id)) {
            return m;
        }
        let mut emitting = self.scene.materials[base].clone();
        emitting.name = format!("{} (emitting)", emitting.name);
        emitting.emission = light.radiance;
        // glint emits from both sides of a two-sided material, so a one-sided light
        // (pbrt's default) is one-sided in glint; its back is then black, not diffuse.
        emitting.two_sided = light.two_sided;
        let index = self.add_material(emitting);
        self.emissive.insert((base, light.id), index);
        index
    }

    /// Adds a node to the object being defined, or to the world.
    fn push_node(&mut self, node: NodeDesc) {
        match &mut self.current_object {
            Some((_, nodes)) => nodes.push(node),
            None => self.nodes.push(node),
        }
    }
}

/// A matrix as a node's transform op; pbrt allows projective matrices, glint only
/// affine ones (callers check).
fn matrix_op(m: Mat4) -> Vec<TransformOp> {
    if m == Mat4::IDENTITY {
        return Vec::new();
    }
    let rows = [0, 1, 2, 3].map(|i| m.row(i).to_array());
    vec![TransformOp::Matrix(rows)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn content_tells_pbrt() {
        assert!(is_pbrt("# comment\nLookAt 0 0 0  0 0 1  0 1 0\n"));
        assert!(is_pbrt("Camera \"perspective\""));
        assert!(is_pbrt("WorldBegin"));
        assert!(!is_pbrt("camera { eye [0 0 5] }"));
        assert!(!is_pbrt("Scale"));
    }
}
