//! Mitsuba 3 XML scenes (`<scene version="3.0.0">`): the subset glint renders the same
//! way, read into a [`SceneDesc`]; everything else is refused with the file, line and
//! the plugin or parameter named (see `docs/formats.md`).
//!
//! Reading goes in two steps: [`tree`] applies Mitsuba's textual rules (includes,
//! `$name` defaults, old names), then a [`Reader`] walks the top-level objects, with
//! one module per kind of plugin ([`shapes`], [`bsdfs`], [`textures`], [`emitters`],
//! [`sensor`]) and [`values`]/[`transform`] for the typed properties they share.
//!
//! Texture coordinates: glint's uv on every shape equals Mitsuba's uv, and image
//! textures are stored flipped vertically, because Mitsuba looks up row `v·height`
//! from the top while glint puts v = 1 at the top. Mesh uvs go through Mitsuba's
//! `flip_tex_coords` (on by default), so an OBJ or PLY textured for either renderer
//! shows the same image in both.

mod bsdfs;
mod emitters;
mod sensor;
mod shapes;
pub(crate) mod tables;
mod textures;
mod transform;
mod tree;
mod values;

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use glint_core::desc::{MaterialDesc, SceneDesc, TextureDesc};

use crate::detect::{Loaded, SceneFormat};
use crate::error::SceneError;
use crate::source::Source;
use tree::Elem;

/// Reads a Mitsuba 3 XML scene file.
///
/// # Errors
///
/// A [`SceneError`] at the file, line and column of the first problem: malformed XML,
/// an unsupported plugin or parameter, a file that cannot be read.
pub fn load_mitsuba(path: &Path) -> Result<Loaded, SceneError> {
    let text = crate::input::read_text(path, crate::input::InputKind::Scene)?;
    load_text(path, &text)
}

/// Reads Mitsuba scene text that came from `path` (for [`crate::load_any`], which has
/// read the file already to tell its format).
pub(crate) fn load_text(path: &Path, text: &str) -> Result<Loaded, SceneError> {
    read(text, tree::source_for(path))
}

/// Reads Mitsuba scene text that did not necessarily come from a file: `file_name`
/// names it in messages and `scene_dir` is where relative paths (meshes, textures,
/// includes) start.
///
/// # Errors
///
/// As [`load_mitsuba`].
pub fn parse_mitsuba(text: &str, file_name: &str, scene_dir: &Path) -> Result<Loaded, SceneError> {
    read(text, Source { name: file_name.to_owned(), dir: scene_dir.to_path_buf() })
}

/// Whether `text` is a Mitsuba scene: its document element is `<scene>` (the course
/// XML format's is `<scenefile>`).
pub fn is_mitsuba(text: &str) -> bool {
    root_tag(text) == Some("scene")
}

/// The name of the first element of an XML text, skipping the declaration, comments,
/// processing instructions and the doctype.
fn root_tag(text: &str) -> Option<&str> {
    let mut rest = text.trim_start_matches('\u{feff}');
    loop {
        rest = &rest[rest.find('<')?..];
        if let Some(after) = rest.strip_prefix("<!--") {
            rest = &after[after.find("-->")? + 3..];
        } else if rest.starts_with("<?") || rest.starts_with("<!") {
            rest = &rest[rest.find('>')? + 1..];
        } else {
            let name = &rest[1..];
            let end = name.find(|c: char| c.is_whitespace() || c == '>' || c == '/').unwrap_or(name.len());
            return Some(&name[..end]);
        }
    }
}

fn read(text: &str, src: Source) -> Result<Loaded, SceneError> {
    let root = tree::parse(text, Rc::new(src))?;
    let mut reader = Reader::new(&root);
    reader.scene_children(&root)?;
    let scene = reader.finish(&root)?;
    Ok(Loaded { scene, format: SceneFormat::Mitsuba, warnings: reader.warnings })
}

/// The state of one scene being read: the objects found by `id`, what was built so far,
/// and caches so that an object referenced many times is built once.
struct Reader<'a> {
    ids: HashMap<&'a str, &'a Elem>,
    scene: SceneDesc,
    /// Material index of each BSDF element already built (keyed by its address).
    materials: HashMap<*const Elem, usize>,
    /// Texture index of each texture element already loaded.
    textures: HashMap<*const Elem, usize>,
    /// The squared copy of each texture that needed one (a principled roughness).
    squared: HashMap<usize, usize>,
    sensor_seen: bool,
    integrator_seen: bool,
    warnings: Vec<String>,
}

impl<'a> Reader<'a> {
    fn new(root: &'a Elem) -> Self {
        let mut ids = HashMap::new();
        collect_ids(root, &mut ids);
        let mut scene = SceneDesc::default();
        sensor::mitsuba_defaults(&mut scene.settings);
        Self {
            ids,
            scene,
            materials: HashMap::new(),
            textures: HashMap::new(),
            squared: HashMap::new(),
            sensor_seen: false,
            integrator_seen: false,
            warnings: Vec::new(),
        }
    }

    /// Reads every top-level object in document order.
    fn scene_children(&mut self, root: &'a Elem) -> Result<(), SceneError> {
        for e in &root.children {
            match e.tag.as_str() {
                "shape" => shapes::shape(self, e)?,
                "emitter" => emitters::emitter(self, e)?,
                "sensor" => self.sensor(e)?,
                "integrator" => self.integrator(e)?,
                // Defined here, built where they are used (a `ref` may come first).
                "bsdf" | "texture" if e.attr("id").is_some() => {}
                "bsdf" | "texture" => return Err(e.error(format!("a top-level <{}> needs an 'id' to be used", e.tag))),
                other => {
                    let what = e.attr("type").map_or(format!("<{other}>"), |t| format!("<{other} type=\"{t}\">"));
                    return Err(e.error(format!(
                        "{what} is not supported; a scene may hold shape, emitter, sensor, integrator, bsdf, \
                         texture, default and include"
                    )));
                }
            }
        }
        Ok(())
    }

    fn sensor(&mut self, e: &'a Elem) -> Result<(), SceneError> {
        if self.sensor_seen {
            self.warnings.push(format!("{}: only the first <sensor> is rendered", e.file.origin(e.pos)));
            return Ok(());
        }
        self.sensor_seen = true;
        sensor::sensor(e, &mut self.scene)
    }

    fn integrator(&mut self, e: &'a Elem) -> Result<(), SceneError> {
        if self.integrator_seen {
            return Err(e.error("the scene has more than one <integrator>"));
        }
        self.integrator_seen = true;
        sensor::integrator(e, &mut self.scene.settings)
    }

    /// The scene, once the whole file is read.
    fn finish(&mut self, root: &Elem) -> Result<SceneDesc, SceneError> {
        if !self.sensor_seen {
            return Err(
                root.error("the scene has no <sensor>: glint needs a camera (e.g. <sensor type=\"perspective\">)")
            );
        }
        Ok(std::mem::take(&mut self.scene))
    }

    /// The element a `<ref id=…>` points at (or `e` itself), which must be a `<tag>`.
    fn resolve(&self, e: &'a Elem, tag: &str) -> Result<&'a Elem, SceneError> {
        let target = if e.tag == "ref" {
            let id = e.required("id")?;
            *self.ids.get(id).ok_or_else(|| e.attr_error("id", format!("no object has id '{id}'")))?
        } else {
            e
        };
        if target.tag != tag {
            return Err(e.error(format!("expected a <{tag}> here, found a <{}>", target.tag)));
        }
        Ok(target)
    }

    /// Adds a material and returns its index.
    /// A warning at element `e`.
    fn warn_at(&mut self, e: &Elem, message: String) {
        self.warnings.push(format!("{}: {message}", e.file.origin(e.pos)));
    }

    /// The index of a copy of texture `index` with every value squared (a perceptual
    /// roughness map read as the GGX alpha), made once.
    fn squared_texture(&mut self, index: usize) -> usize {
        if let Some(&i) = self.squared.get(&index) {
            return i;
        }
        let mut copy = self.scene.textures[index].clone();
        match &mut copy {
            TextureDesc::Image { name, texels, .. } => {
                name.push_str(" squared");
                texels.iter_mut().for_each(|t| *t *= *t);
            }
            TextureDesc::Checker { name, even, odd, .. } => {
                name.push_str(" squared");
                (*even, *odd) = (*even * *even, *odd * *odd);
            }
        }
        self.scene.textures.push(copy);
        let i = self.scene.textures.len() - 1;
        self.squared.insert(index, i);
        i
    }

    fn add_material(&mut self, m: MaterialDesc) -> usize {
        self.scene.materials.push(m);
        self.scene.materials.len() - 1
    }
}

/// Every element with an `id`, anywhere in the tree (Mitsuba lets a reference name an
/// object defined at the top level or nested inside another).
fn collect_ids<'a>(e: &'a Elem, ids: &mut HashMap<&'a str, &'a Elem>) {
    for c in &e.children {
        if let (Some(id), false) = (c.attr("id"), c.tag == "ref") {
            ids.entry(id).or_insert(c);
        }
        collect_ids(c, ids);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn root_tag_skips_prolog_and_comments() {
        assert_eq!(root_tag("<?xml version=\"1.0\"?>\n<!-- hi -->\n<scene version=\"3.0.0\">"), Some("scene"));
        assert_eq!(root_tag("<scenefile>"), Some("scenefile"));
        assert_eq!(root_tag("plain text"), None);
    }
}
