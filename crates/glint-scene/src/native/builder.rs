//! Node tree → [`SceneDesc`]: the top level of a file, names, includes.
//!
//! The builder walks the generic tree once, in written order, so "defined before use" is
//! simply "already in the registry". The meaning of each kind of node lives in its own
//! module (settings, lights, materials, objects); this one holds the shared state.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glint_core::desc::{LightDesc, MaterialDesc, NodeDesc, SceneDesc};

use super::animation::{Clock, at_clock};
use super::args::{self, Result};
use super::lexer::{Pos, tokenize};
use super::tree::{Node, parse};
use super::{lights, materials, settings};
use crate::error::SceneErrorKind;

/// Includes nested deeper than this are refused; a real scene needs a handful, and the
/// limit keeps a long chain of distinct files from exhausting the stack.
const MAX_INCLUDE_DEPTH: usize = 32;

/// The most scene nodes one scene may expand to (after copying definitions for `use`),
/// so that nested `use` of `define`s cannot blow up memory exponentially.
pub const MAX_NODES: usize = 1_000_000;

/// Node names allowed at the top level of a file, for the "expected one of" message.
const TOP_LEVEL: [&str; 27] = [
    "settings",
    "camera",
    "texture",
    "material",
    "light",
    "define",
    "use",
    "include",
    "group",
    "moving",
    "sphere",
    "cube",
    "cylinder",
    "cone",
    "plane",
    "disk",
    "rectangle",
    "torus",
    "mesh",
    "mesh_instance",
    "union",
    "intersection",
    "difference",
    "blob",
    "implicit",
    "quadric",
    "superellipsoid",
];

pub use crate::source::Source;

/// Names of one kind (materials, textures, definitions) mapped to their index and origin.
#[derive(Default)]
pub struct Registry {
    entries: HashMap<String, (usize, String)>,
}

impl Registry {
    /// Registers `name` (defined at `origin`) as `index`; names must be unique so that a
    /// reference can never silently mean something else.
    pub fn insert(&mut self, src: &Source, pos: Pos, what: &str, name: &str, index: usize) -> Result<()> {
        if let Some((_, first)) = self.entries.get(name) {
            return Err(
                src.invalid(pos, format!("{what} '{name}' is already defined at {first}; names must be unique"))
            );
        }
        self.entries.insert(name.to_owned(), (index, src.origin(pos)));
        Ok(())
    }

    /// The index of `name`, or an error naming the unknown name and the known ones.
    pub fn lookup(&self, src: &Source, pos: Pos, what: &str, name: &str) -> Result<usize> {
        if let Some((index, _)) = self.entries.get(name) {
            return Ok(*index);
        }
        let mut known: Vec<&str> = self.entries.keys().map(String::as_str).collect();
        known.sort_unstable();
        let hint = if known.is_empty() {
            format!("no {what}s are defined before this line")
        } else {
            format!("known {what}s: {}", known.join(", "))
        };
        Err(src.invalid(pos, format!("unknown {what} '{name}'; {hint} ({what}s must be defined before they are used)")))
    }

    /// The index of `name`, if it is defined.
    pub fn get(&self, name: &str) -> Option<usize> {
        self.entries.get(name).map(|(index, _)| *index)
    }

    /// Where `name` was defined, if it was.
    pub fn origin_of(&self, name: &str) -> Option<&str> {
        self.entries.get(name).map(|(_, origin)| origin.as_str())
    }
}

/// A `define`: its already-built nodes, copied by each `use`.
pub struct Definition {
    /// The defined objects, materials already resolved.
    pub nodes: Vec<NodeDesc>,
    /// How many scene nodes one copy adds (for [`MAX_NODES`]).
    pub node_count: usize,
}

/// Everything the builder accumulates while it walks the files of one scene.
#[derive(Default)]
pub struct Builder {
    /// The scene being built.
    pub desc: SceneDesc,
    /// Material names → index into `desc.materials`.
    pub materials: Registry,
    /// Texture names → index into `desc.textures`.
    pub textures: Registry,
    /// `define` names → index into `definitions`.
    pub define_names: Registry,
    /// The bodies of `define`s.
    pub definitions: Vec<Definition>,
    /// `mesh` names → index into `desc.meshes`.
    pub mesh_names: Registry,
    /// Index of the built-in default material once an object has needed it.
    pub default_material: Option<usize>,
    /// The `material` of the CSG node being built, which its children without one use.
    pub inherited_material: Option<usize>,
    /// Scene nodes created so far (for [`MAX_NODES`]).
    pub node_count: usize,
    /// Where `settings` and `camera` were given, so a second one is refused.
    settings_at: Option<String>,
    camera_at: Option<String>,
    /// Where the environment light was given, so a second one is refused.
    environment_at: Option<String>,
    /// The files being read, outermost first: canonical path (if any) and display name.
    include_stack: Vec<(Option<PathBuf>, String)>,
    /// The moment of the animation keyed properties are read at.
    pub clock: Clock,
}

impl Builder {
    /// A builder that reads keyed properties at `clock`.
    pub fn at(clock: Clock) -> Self {
        Self { clock, ..Self::default() }
    }

    /// Lexes, parses and builds one file's text into the scene; `canonical` identifies the
    /// file for include-cycle detection (None for text that is not a file).
    pub fn file(&mut self, src: &Source, text: &str, canonical: Option<PathBuf>) -> Result<()> {
        let syntax = |e: super::lexer::SyntaxError| src.error(SceneErrorKind::Syntax, e.pos, e.message);
        let tokens = tokenize(text).map_err(syntax)?;
        let nodes = at_clock(src, &parse(&tokens).map_err(syntax)?, self.clock)?;
        self.include_stack.push((canonical, src.name.clone()));
        let result = self.top_level(src, &nodes);
        self.include_stack.pop();
        result
    }

    /// The scene built so far, once every file has been read.
    pub fn finish(self) -> SceneDesc {
        self.desc
    }

    /// Builds the nodes of a file's top level in written order.
    fn top_level(&mut self, src: &Source, nodes: &[Node]) -> Result<()> {
        let mut rest = nodes.iter();
        while let Some(node) = rest.next() {
            match node.name.as_str() {
                "settings" => {
                    Self::only_once(src, node, &mut self.settings_at)?;
                    settings::settings(src, node, &mut self.desc.settings, self.clock.fps)?;
                }
                "camera" => {
                    Self::only_once(src, node, &mut self.camera_at)?;
                    self.desc.camera = settings::camera(src, node)?;
                }
                "light" => {
                    args::no_values(src, node)?;
                    let kind = Self::kind_node(src, node, rest.next(), &lights::KINDS)?;
                    let light = lights::light(src, kind, &self.textures, &self.desc.textures)?;
                    if matches!(light, LightDesc::Environment(_)) {
                        Self::only_one_environment(src, node, &mut self.environment_at)?;
                    }
                    self.desc.lights.push(light);
                }
                "texture" => {
                    let (name, pos) = args::string(src, node, "a texture name")?;
                    let kind = Self::kind_node(src, node, rest.next(), &materials::TEXTURE_KINDS)?;
                    // Check the name before decoding a possibly large image.
                    self.textures.insert(src, pos, "texture", &name, self.desc.textures.len())?;
                    let texture = materials::texture(src, &name, kind)?;
                    self.desc.textures.push(texture);
                }
                "material" => {
                    let (name, pos) = args::string(src, node, "a material name")?;
                    if name == "default" && self.default_material.is_some() {
                        let first = self.materials.origin_of("default").unwrap_or("?");
                        return Err(src.invalid(
                            pos,
                            format!(
                                "material 'default' must be defined before any object without a \
                                 material; the object at {first} already uses the built-in default"
                            ),
                        ));
                    }
                    let material = materials::material(src, node, &name, &self.textures)?;
                    self.materials.insert(src, pos, "material", &name, self.desc.materials.len())?;
                    self.desc.materials.push(material);
                }
                "define" => self.define(src, node)?,
                "mesh" => self.mesh_definition(src, node)?,
                "include" => self.include(src, node)?,
                name if super::objects::is_object(name) => {
                    let object = self.object(src, node)?;
                    self.desc.objects.push(object);
                }
                _ => {
                    return Err(args::unknown(src, node, "node", "at the top level", &TOP_LEVEL));
                }
            }
        }
        Ok(())
    }

    /// Refuses a second `settings`/`camera`, which would silently override the first.
    fn only_once(src: &Source, node: &Node, first: &mut Option<String>) -> Result<()> {
        if let Some(first) = first {
            return Err(src.invalid(
                node.pos(),
                format!("'{}' is given twice; the first is at {first}; put all of it in one block", node.name),
            ));
        }
        *first = Some(src.origin(node.pos()));
        Ok(())
    }

    /// Refuses a second environment light: light from infinitely far away in every
    /// direction is one map, as in Mitsuba, which allows one environment emitter.
    fn only_one_environment(src: &Source, node: &Node, first: &mut Option<String>) -> Result<()> {
        if let Some(first) = first {
            return Err(src.invalid(
                node.pos(),
                format!(
                    "a scene has at most one environment light; the first is at {first}; \
                     combine them into one map, or scale it with 'radiance'"
                ),
            ));
        }
        *first = Some(src.origin(node.pos()));
        Ok(())
    }

    /// The node after `light`/`texture` that names its kind and holds its block:
    /// `light point { … }` is a `light` node followed by a `point` node.
    pub(super) fn kind_node<'n>(src: &Source, node: &Node, next: Option<&'n Node>, kinds: &[&str]) -> Result<&'n Node> {
        let expected = kinds.join(", ");
        if let Some(block) = &node.block {
            return Err(src.invalid(
                block.open,
                format!(
                    "'{}' needs its type before the block, as in `{} {} {{ … }}`; expected one of: {expected}",
                    node.name, node.name, kinds[0]
                ),
            ));
        }
        let Some(kind) = next else {
            return Err(src.invalid(
                node.pos(),
                format!(
                    "expected {} {} type after '{}'; one of: {expected}",
                    article(&node.name),
                    node.name,
                    node.name
                ),
            ));
        };
        if !kinds.contains(&kind.name.as_str()) {
            return Err(src.invalid(
                kind.pos(),
                format!("unknown {} type '{}'; expected one of: {expected}", node.name, kind.name),
            ));
        }
        args::no_values(src, kind)?;
        Ok(kind)
    }

    /// The material for an object without `material`: a user-defined "default" if there
    /// is one, else the built-in default, created the first time it is needed.
    pub fn default_material(&mut self, src: &Source, pos: Pos) -> Result<usize> {
        if let Some(index) = self.default_material {
            return Ok(index);
        }
        if let Some(index) = self.materials.get("default") {
            return Ok(index);
        }
        let index = self.desc.materials.len();
        self.desc.materials.push(MaterialDesc { name: "default".to_owned(), ..MaterialDesc::default() });
        self.materials.insert(src, pos, "material", "default", index)?;
        self.default_material = Some(index);
        Ok(index)
    }

    /// Counts `added` new scene nodes against [`MAX_NODES`].
    pub fn count_nodes(&mut self, src: &Source, pos: Pos, added: usize) -> Result<()> {
        self.node_count = self.node_count.saturating_add(added);
        if self.node_count > MAX_NODES {
            return Err(
                src.invalid(pos, format!("the scene expands to more than {MAX_NODES} objects; reduce nested 'use'"))
            );
        }
        Ok(())
    }

    /// `include "file.glint"`: builds that file's nodes here, as if written in place.
    fn include(&mut self, src: &Source, node: &Node) -> Result<()> {
        let (relative, pos) = args::string(src, node, "a file name")?;
        args::no_block(src, node)?;
        let path = src.dir.join(&relative);
        let name = path.display().to_string();
        let canonical = std::fs::canonicalize(&path).ok();
        if let Some(canonical) = &canonical {
            let start = self.include_stack.iter().position(|(c, _)| c.as_ref() == Some(canonical));
            if let Some(start) = start {
                let mut chain: Vec<&str> = self.include_stack[start..].iter().map(|(_, n)| n.as_str()).collect();
                chain.push(&name);
                return Err(src.invalid(pos, format!("include cycle: {}", chain.join(" -> "))));
            }
        }
        if self.include_stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(src.invalid(pos, format!("includes are nested more than {MAX_INCLUDE_DEPTH} deep")));
        }
        let text = crate::input::read_text(&path, crate::input::InputKind::Scene).map_err(|e| {
            src.error(SceneErrorKind::Io, pos, format!("cannot read included file '{name}': {}", e.problem))
        })?;
        let included = Source { name, dir: parent_dir(&path) };
        self.file(&included, &text, canonical)
    }
}

/// "an" before a word that starts with a vowel, else "a".
fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) { "an" } else { "a" }
}

/// The folder relative paths inside `file` start from ("" for a bare file name, meaning
/// the current directory).
pub fn parent_dir(file: &Path) -> PathBuf {
    file.parent().map(Path::to_path_buf).unwrap_or_default()
}
