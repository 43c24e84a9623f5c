//! "The Ray Tracer Challenge" (Jamis Buck, 2019) YAML scenes → [`SceneDesc`].
//!
//! A scene is a list of items: `- add: camera|light|sphere|plane|cube|cylinder|cone|group|…`
//! and `- define: NAME` with `value:` (and `extend:`) for reusable materials and transform
//! lists. The book's conventions are kept where glint differs (see `docs/formats.md`):
//!
//! - **Handedness.** The book's world is left-handed: with its view transform, +x is on
//!   the right when looking along +z. glint's camera is right-handed, so every object
//!   goes under one root group mirrored in z (`scale [1 1 -1]`), and the camera and
//!   lights are mirrored with it; the picture comes out as the book draws it.
//! - **Field of view** is the full angle, in radians, of the *larger* image side;
//!   glint's is the vertical angle in degrees.
//! - **Lighting.** The book's Phong model (`ambient = colour·intensity·ambient` per
//!   light, a white highlight `intensity·specular`, scalar `reflective` and
//!   `transparency`) maps onto the Whitted material exactly; values are written to the
//!   image as they are (`Transfer::Identity`), as the book writes its PPM files.
//!
//! What glint cannot draw (the `triangle` items, solid 3-D patterns on curved surfaces,
//! open or infinite cylinders and cones) is skipped or approximated with a warning that
//! names the line.

mod material;
mod shapes;
mod transform;
mod values;
pub mod yaml;

use std::collections::HashMap;
use std::path::Path;

use glam::Vec3;
use glint_core::desc::{AreaShape, CameraDesc, LightDesc, NodeDesc, NodeKind, SceneDesc, Transfer, TransformOp};

use crate::error::{SceneError, SceneErrorKind};
use crate::native::lexer::Pos;
use crate::native::{MAX_IMAGE_SIDE, MAX_NODES};
use material::MaterialCache;
use values::{Result, Src};
use yaml::Yaml;

/// The book's world is left-handed; mirroring z makes it glint's right-handed world.
pub const MIRROR: Vec3 = Vec3::new(1.0, 1.0, -1.0);

/// Reads a Ray Tracer Challenge YAML file.
///
/// # Errors
///
/// A [`SceneError`] naming the file, line and column of the first problem: malformed
/// YAML, an unknown item or transform, a value of the wrong type or out of range.
pub fn load_challenge(path: &Path) -> std::result::Result<(SceneDesc, Vec<String>), SceneError> {
    let text = crate::input::read_text(path, crate::input::InputKind::Scene)?;
    parse_challenge(&text, &path.display().to_string())
}

/// Reads Ray Tracer Challenge YAML text; `file_name` is used in errors, warnings and node
/// origins. Returns the scene and the warnings about what was skipped or approximated.
///
/// # Errors
///
/// As [`load_challenge`].
pub fn parse_challenge(text: &str, file_name: &str) -> std::result::Result<(SceneDesc, Vec<String>), SceneError> {
    let dir = Path::new(file_name).parent().map(Path::to_path_buf).unwrap_or_default();
    let src = Src { name: file_name.to_owned(), dir };
    let root = yaml::parse(text)
        .map_err(|e| SceneError::new(SceneErrorKind::Syntax, file_name, e.pos.line, e.pos.column, e.message))?;
    let Some(root) = root else {
        return Err(SceneError::new(
            SceneErrorKind::Invalid,
            file_name,
            0,
            0,
            "the file holds no scene; a Ray Tracer Challenge scene is a list of '- add: …' and '- define: …' items",
        ));
    };
    let mut reader = Reader {
        src,
        desc: SceneDesc::default(),
        warnings: Vec::new(),
        defines: HashMap::new(),
        camera_at: None,
        materials: MaterialCache::default(),
        shadowless: HashMap::new(),
        node_count: 0,
    };
    reader.desc.settings.ambient_light = Vec3::ZERO;
    reader.desc.settings.background = Vec3::ZERO;
    reader.desc.settings.output_transfer = Transfer::Identity;
    reader.scene(&root)?;
    Ok((reader.desc, reader.warnings))
}

/// A `- define:` item: its value (with `extend` already merged in) and where it is.
struct Define {
    value: Yaml,
    origin: String,
}

/// Everything the reader accumulates while it walks the items of one file.
struct Reader {
    src: Src,
    desc: SceneDesc,
    warnings: Vec<String>,
    defines: HashMap<String, Define>,
    camera_at: Option<Pos>,
    materials: MaterialCache,
    /// Material → its copy that casts no shadow (for `shadow: false`).
    shadowless: HashMap<usize, usize>,
    /// Scene nodes created so far, against [`MAX_NODES`].
    node_count: usize,
}

impl Reader {
    /// The top-level list of items, in written order.
    fn scene(&mut self, root: &Yaml) -> Result<()> {
        let items = root.seq().ok_or_else(|| {
            self.src.invalid(
                root.pos,
                format!(
                    "a Ray Tracer Challenge scene is a list of '- add: …' and '- define: …' items, found {}",
                    root.describe()
                ),
            )
        })?;
        let mut objects = Vec::new();
        for item in items {
            let entries = values::mapping(&self.src, item, "a scene item")?;
            match (values::get(entries, "add"), values::get(entries, "define")) {
                (Some(_), Some(define)) => {
                    return Err(self.src.invalid(define.pos, "an item has either 'add' or 'define', not both"));
                }
                (None, Some(_)) => self.define_item(item, entries)?,
                (Some(kind), None) => match values::word(&self.src, kind, "add")? {
                    "camera" => self.camera(item, entries)?,
                    "light" => self.light(entries, item.pos)?,
                    _ => {
                        if let Some(node) = self.object(item, None, 0)? {
                            objects.push(node);
                        }
                    }
                },
                (None, None) => {
                    return Err(self.src.invalid(
                        item.pos,
                        "a scene item starts with 'add: KIND' (camera, light, sphere, …) or 'define: NAME'",
                    ));
                }
            }
        }
        if self.camera_at.is_none() {
            return Err(self.src.invalid(
                root.pos,
                "the scene has no camera; add one, like `- add: camera` with width, height, field-of-view, from, to and up",
            ));
        }
        if !objects.is_empty() {
            self.desc.objects.push(NodeDesc {
                transform: vec![TransformOp::Scale(MIRROR)],
                kind: NodeKind::Group(objects),
                origin: self.src.origin(root.pos),
            });
        }
        Ok(())
    }

    /// `- define: NAME` with `value:` and optionally `extend: OTHER`.
    fn define_item(&mut self, item: &Yaml, entries: &[(Yaml, Yaml)]) -> Result<()> {
        let src = &self.src;
        values::unknown_keys(src, entries, &["define", "value", "extend"], "in a 'define'", &mut self.warnings);
        let name_node = values::required(src, entries, item.pos, "define", "a definition")?;
        let name = values::word(src, name_node, "define")?.to_owned();
        let mut value = values::required(src, entries, item.pos, "value", &format!("definition '{name}'"))?.clone();
        if let Some(base) = values::get(entries, "extend") {
            let base_name = values::word(src, base, "extend")?;
            let base = self.define(base, base_name, "definition")?;
            value = extend(src, &base.value, &value, &name, base_name)?;
        }
        if let Some(first) = self.defines.get(&name) {
            return Err(self.src.invalid(
                name_node.pos,
                format!("'{name}' is already defined at {}; names must be unique", first.origin),
            ));
        }
        let origin = self.src.origin(name_node.pos);
        self.defines.insert(name, Define { value, origin });
        Ok(())
    }

    /// The definition `name` refers to, or an error listing the known ones.
    fn define(&self, node: &Yaml, name: &str, what: &str) -> Result<&Define> {
        if let Some(define) = self.defines.get(name) {
            return Ok(define);
        }
        let mut known: Vec<&str> = self.defines.keys().map(String::as_str).collect();
        known.sort_unstable();
        let hint = if known.is_empty() {
            "nothing is defined before this line".to_owned()
        } else {
            format!("defined names: {}", known.join(", "))
        };
        Err(self.src.invalid(node.pos, format!("unknown {what} '{name}'; {hint} (define it before it is used)")))
    }

    /// `- add: camera`: the book's camera with its field of view on the larger side.
    fn camera(&mut self, item: &Yaml, entries: &[(Yaml, Yaml)]) -> Result<()> {
        let src = &self.src;
        if let Some(first) = self.camera_at {
            return Err(src.invalid(
                item.pos,
                format!("a second camera; the first is at line {}; a scene has one camera", first.line),
            ));
        }
        self.camera_at = Some(item.pos);
        let known = ["add", "width", "height", "field-of-view", "from", "to", "up"];
        values::unknown_keys(src, entries, &known, "in 'camera'", &mut self.warnings);
        let need = |key| values::required(src, entries, item.pos, key, "the camera");
        let width = values::whole(src, need("width")?, "width", 1, MAX_IMAGE_SIDE)?;
        let height = values::whole(src, need("height")?, "height", 1, MAX_IMAGE_SIDE)?;
        let fov = values::number_where(
            src,
            need("field-of-view")?,
            "field-of-view",
            "an angle in radians between 0 and π (both excluded)",
            |x| x > 0.0 && x < std::f32::consts::PI,
        )?;
        let from = values::vec3(src, need("from")?, "from")?;
        let to_node = need("to")?;
        let to = values::vec3(src, to_node, "to")?;
        let up = match values::get(entries, "up") {
            Some(node) => values::vec3(src, node, "up")?,
            None => Vec3::Y,
        };
        let forward = to - from;
        if !(forward.length_squared() > 0.0 && forward.length_squared().is_finite()) {
            return Err(src.invalid(to_node.pos, format!("'to' {to} must differ from 'from' {from}")));
        }
        let sine = forward.normalize().cross(up.normalize_or_zero()).length();
        if sine.is_nan() || sine < 1e-4 {
            let at = values::get(entries, "up").map_or(item.pos, |n| n.pos);
            return Err(
                src.invalid(at, format!("'up' {up} must not be zero or parallel to the viewing direction {forward}"))
            );
        }
        self.desc.settings.width = width;
        self.desc.settings.height = height;
        self.desc.camera = CameraDesc {
            eye: mirrored(from),
            look: mirrored(forward),
            up: mirrored(up),
            fov_y_degrees: vertical_fov_degrees(book_field_of_view(fov, sine), width, height),
            ..CameraDesc::default()
        };
        Ok(())
    }

    /// `- add: light`: a point light (`at`, `intensity`) or the book's area light
    /// (`corner`, `uvec`, `vvec`, `usteps`, `vsteps`), glint's rectangle light.
    fn light(&mut self, entries: &[(Yaml, Yaml)], pos: Pos) -> Result<()> {
        let src = &self.src;
        let known = ["add", "at", "intensity", "corner", "uvec", "vvec", "usteps", "vsteps", "jitter"];
        values::unknown_keys(src, entries, &known, "in 'light'", &mut self.warnings);
        let intensity = values::color(src, values::required(src, entries, pos, "intensity", "a light")?, "intensity")?;
        let light = match (values::get(entries, "at"), values::get(entries, "corner")) {
            (Some(at), _) => {
                let position = values::vec3(src, at, "at")?;
                LightDesc::Point { position: mirrored(position), color: intensity, attenuation: Vec3::X }
            }
            (None, Some(corner)) => {
                let corner = values::vec3(src, corner, "corner")?;
                let edge = |key| -> Result<Vec3> {
                    let node = values::required(src, entries, pos, key, "an area light")?;
                    let v = values::vec3(src, node, key)?;
                    if v.length_squared() > 0.0 {
                        Ok(v)
                    } else {
                        Err(src.invalid(node.pos, format!("'{key}' must not be zero")))
                    }
                };
                let (edge_u, edge_v) = (edge("uvec")?, edge("vvec")?);
                let steps = |key| match values::get(entries, key) {
                    Some(node) => values::whole(src, node, key, 1, 4096),
                    None => Ok(1),
                };
                // glint samples n×n cells; the book usteps×vsteps: keep the count.
                let cells = steps("usteps")? * steps("vsteps")?;
                let samples = (f64::from(cells).sqrt().round() as u32).clamp(1, 64);
                if let Some(jitter) = values::get(entries, "jitter") {
                    values::boolean(src, jitter, "jitter")?;
                }
                let shape = AreaShape::Rectangle {
                    corner: mirrored(corner),
                    edge_u: mirrored(edge_u),
                    edge_v: mirrored(edge_v),
                };
                LightDesc::Area { shape, color: intensity, attenuation: Vec3::X, samples }
            }
            (None, None) => {
                return Err(src.invalid(
                    pos,
                    "a light needs 'at' (a point light) or 'corner', 'uvec' and 'vvec' (an area light)",
                ));
            }
        };
        // The book adds `colour·intensity·ambient` once per light: glint's L_a is the sum.
        self.desc.settings.ambient_light += intensity;
        self.desc.lights.push(light);
        Ok(())
    }

    /// Counts `added` new scene nodes against [`MAX_NODES`].
    fn count_nodes(&mut self, pos: Pos, added: usize) -> Result<()> {
        self.node_count = self.node_count.saturating_add(added);
        if self.node_count > MAX_NODES {
            return Err(self.src.invalid(pos, format!("the scene expands to more than {MAX_NODES} objects")));
        }
        Ok(())
    }
}

/// The field of view the book's camera really shows. Its `view_transform` does not
/// normalise `left = forward × up`, so when `up` is not perpendicular to the viewing
/// direction (at angle θ) its camera axes have length sin θ and the picture spans
/// `tan(fov/2)/sin θ` instead of `tan(fov/2)`: slightly wider than written.
pub fn book_field_of_view(fov: f32, sine: f32) -> f32 {
    2.0 * ((0.5 * fov).tan() / sine).atan()
}

/// A point or direction of the book's world in glint's (z mirrored; `+ 0` keeps −0
/// out of the numbers).
fn mirrored(v: Vec3) -> Vec3 {
    v * MIRROR + Vec3::ZERO
}

/// glint's full vertical angle in degrees for the book's `field-of-view`, which is the
/// full angle of the larger image side in radians (`half_view = tan(fov/2)` spans half
/// the width of a landscape image and half the height of a portrait one).
pub fn vertical_fov_degrees(fov: f32, width: u32, height: u32) -> f32 {
    if width >= height {
        let aspect = width as f32 / height as f32;
        (2.0 * ((0.5 * fov).tan() / aspect).atan()).to_degrees()
    } else {
        fov.to_degrees()
    }
}

/// `extend:` — the base's value overridden by `value`: mapping keys are replaced, lists
/// are appended to.
fn extend(src: &Src, base: &Yaml, value: &Yaml, name: &str, base_name: &str) -> Result<Yaml> {
    match (base.map(), value.map(), base.seq(), value.seq()) {
        (Some(base_entries), Some(entries), _, _) => {
            let mut merged: Vec<(Yaml, Yaml)> = base_entries
                .iter()
                .filter(|(k, _)| values::get(entries, k.scalar().unwrap_or("")).is_none())
                .cloned()
                .collect();
            merged.extend(entries.iter().cloned());
            Ok(Yaml { value: yaml::Value::Map(merged), pos: value.pos })
        }
        (_, _, Some(base_items), Some(items)) => {
            let mut merged = base_items.to_vec();
            merged.extend(items.iter().cloned());
            Ok(Yaml { value: yaml::Value::Seq(merged), pos: value.pos })
        }
        _ => Err(src.invalid(
            value.pos,
            format!(
                "'{name}' extends '{base_name}', so both must be mappings or both lists; '{base_name}' is {} and this value is {}",
                base.describe(),
                value.describe()
            ),
        )),
    }
}
