//! CS123/CS1230 XML scenefiles (`<scenefile>`), as the course's 2022 reader defines
//! them: defaults, attribute names and element meanings follow that reader; where it
//! gave up on input it could have read (an unknown element, `position` on a
//! directional light) glint reads on and warns.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use glint_core::desc::TransformOp;
use roxmltree::{Document, Node};

use super::model::{
    self, Camera, Child, CourseScene, Global, Group, Light, LightKind, Material, Primitive, Shape, Template, TextureMap,
};
use super::{Pos, Result, Source, Warnings};
use crate::error::SceneErrorKind;

/// Name of the top-level object that is rendered.
const ROOT: &str = "root";

const SCENEFILE_CHILDREN: [&str; 4] = ["globaldata", "cameradata", "lightdata", "object"];
const GLOBAL_CHILDREN: [&str; 4] = ["ambientcoeff", "diffusecoeff", "specularcoeff", "transparentcoeff"];
const CAMERA_CHILDREN: [&str; 7] = ["pos", "look", "focus", "up", "heightangle", "aperture", "focallength"];
const LIGHT_CHILDREN: [&str; 10] =
    ["id", "type", "color", "function", "position", "direction", "angle", "penumbra", "width", "height"];
const LIGHT_TYPES: [&str; 4] = ["point", "directional", "spot", "area"];
const TRANSBLOCK_CHILDREN: [&str; 5] = ["translate", "rotate", "scale", "matrix", "object"];
const PRIMITIVES: [&str; 6] = ["cube", "cone", "cylinder", "sphere", "torus", "mesh"];
const MATERIAL_CHILDREN: [&str; 11] = [
    "diffuse",
    "ambient",
    "specular",
    "reflective",
    "transparent",
    "emissive",
    "shininess",
    "ior",
    "blend",
    "texture",
    "bumpmap",
];

/// Reads the text into the course model.
pub fn read(src: &Source, text: &str, warnings: &mut Warnings) -> Result<CourseScene> {
    let doc = Document::parse(text).map_err(|e| {
        let p = e.pos();
        // The message ends with the position, which the error already carries.
        let message = e.to_string();
        let message = message.strip_suffix(&format!(" at {}:{}", p.row, p.col)).unwrap_or(&message);
        src.error(SceneErrorKind::Syntax, Pos { line: p.row, column: p.col }, format!("malformed XML: {message}"))
    })?;
    let mut reader = Reader { src, doc: &doc, warnings, objects: HashMap::new(), templates: Vec::new() };
    reader.scenefile()
}

struct Reader<'a, 'input> {
    src: &'a Source,
    doc: &'a Document<'input>,
    warnings: &'a mut Warnings,
    /// Top-level object names → index in `templates` (filled as they are read, so a
    /// `master` may refer to any top-level object, before or after it).
    objects: HashMap<String, usize>,
    templates: Vec<Template>,
}

type El<'a, 'input> = Node<'a, 'input>;

impl<'a, 'input> Reader<'a, 'input> {
    fn pos(&self, node: El) -> Pos {
        let p = self.doc.text_pos_at(node.range().start);
        Pos { line: p.row, column: p.col }
    }

    fn attr_pos(&self, node: El, name: &str) -> Pos {
        match node.attribute_node(name) {
            Some(a) => {
                let p = self.doc.text_pos_at(a.range_value().start);
                Pos { line: p.row, column: p.col }
            }
            None => self.pos(node),
        }
    }

    fn unknown(&mut self, node: El, place: &str, allowed: &[&str]) {
        let pos = self.pos(node);
        self.warnings.at(
            self.src,
            pos,
            format!(
                "unknown element <{}> in {place} is ignored; expected one of: {}",
                node.tag_name().name(),
                allowed.join(", ")
            ),
        );
    }

    fn scenefile(&mut self) -> Result<CourseScene> {
        let root = self.doc.root_element();
        if root.tag_name().name() != "scenefile" {
            return Err(self.src.invalid(
                self.pos(root),
                format!("the document element is <{}>; a course scene starts with <scenefile>", root.tag_name().name()),
            ));
        }
        // The course reader's defaults.
        let mut global = Global { ka: 0.5, kd: 0.5, ks: 0.5, kt: 0.0 };
        let mut camera = Camera {
            position: Vec3::splat(5.0),
            look: Vec3::splat(-1.0),
            up: Vec3::Y,
            height_angle: 45.0,
            depth_of_field: None,
            pos: self.pos(root),
        };
        let mut lights = Vec::new();
        let mut objects = Vec::new();
        for e in root.children().filter(Node::is_element) {
            match e.tag_name().name() {
                "globaldata" => self.global(e, &mut global)?,
                "cameradata" => camera = self.camera(e, camera)?,
                "lightdata" => lights.push(self.light(e)?),
                "object" => objects.push(e),
                _ => self.unknown(e, "<scenefile>", &SCENEFILE_CHILDREN),
            }
        }
        // Register every top-level name first, then read the trees.
        for &e in &objects {
            self.register_object(e)?;
        }
        for &e in &objects {
            let index = self.objects[e.attribute("name").unwrap_or_default()];
            self.templates[index].group = self.object_tree(e)?;
        }
        let Some(&root_index) = self.objects.get(ROOT) else {
            let known: Vec<&str> = self.templates.iter().map(|t| t.name.as_str()).collect();
            return Err(self.src.invalid(
                self.pos(root),
                format!(
                    "no <object type=\"tree\" name=\"{ROOT}\">: the course renders the object named '{ROOT}'{}",
                    if known.is_empty() { String::new() } else { format!(" (found: {})", known.join(", ")) }
                ),
            ));
        };
        let root_pos = self.templates[root_index].group.pos;
        Ok(CourseScene {
            global,
            camera,
            lights,
            root: Group { children: vec![Child::Template { index: root_index, pos: root_pos }], ..Group::default() },
            templates: std::mem::take(&mut self.templates),
        })
    }

    fn global(&mut self, e: El, global: &mut Global) -> Result<()> {
        for c in e.children().filter(Node::is_element) {
            let target = match c.tag_name().name() {
                "ambientcoeff" => &mut global.ka,
                "diffusecoeff" => &mut global.kd,
                "specularcoeff" => &mut global.ks,
                "transparentcoeff" => &mut global.kt,
                _ => {
                    self.unknown(c, "<globaldata>", &GLOBAL_CHILDREN);
                    continue;
                }
            };
            *target = self.single(c)?;
        }
        Ok(())
    }

    fn camera(&mut self, e: El, mut camera: Camera) -> Result<Camera> {
        camera.pos = self.pos(e);
        let mut look = None;
        let mut focus = None;
        let mut aperture = None;
        let mut focal_length = None;
        for c in e.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "pos" => camera.position = self.triple(c, ["x", "y", "z"])?,
                "look" => look = Some(self.triple(c, ["x", "y", "z"])?),
                "focus" => focus = Some((self.triple(c, ["x", "y", "z"])?, self.pos(c))),
                "up" => camera.up = self.triple(c, ["x", "y", "z"])?,
                "heightangle" => camera.height_angle = self.single(c)?,
                "aperture" => aperture = Some((self.single(c)?, self.pos(c))),
                "focallength" => focal_length = Some((self.single(c)?, self.pos(c))),
                _ => self.unknown(c, "<cameradata>", &CAMERA_CHILDREN),
            }
        }
        match (look, focus) {
            (Some(_), Some((_, pos))) => {
                return Err(self.src.invalid(pos, "the camera has both <look> and <focus>; give one of them"));
            }
            (Some(look), None) => camera.look = look,
            (None, Some((point, _))) => camera.look = point - camera.position,
            (None, None) => {}
        }
        if aperture.is_some() || focal_length.is_some() {
            let pos = aperture.or(focal_length).map_or(camera.pos, |(_, p)| p);
            camera.depth_of_field = Some((aperture.map_or(0.0, |a| a.0), focal_length.map_or(0.0, |f| f.0), pos));
        }
        Ok(camera)
    }

    fn light(&mut self, e: El) -> Result<Light> {
        // The course reader's defaults; a light without <type> is a point light.
        let mut light = Light {
            kind: LightKind::Point,
            color: Vec3::ONE,
            attenuation: Vec3::X,
            position: Vec3::splat(3.0),
            direction: Vec3::ZERO,
            pos: self.pos(e),
        };
        let (mut angle, mut penumbra, mut width, mut height) = (0.0, 0.0, 0.0, 0.0);
        let mut kind = "point";
        for c in e.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "id" => {
                    self.single(c)?;
                }
                "type" => {
                    let v = self.attr(c, "v")?;
                    let Some(&known) = LIGHT_TYPES.iter().find(|t| **t == v) else {
                        return Err(self.src.invalid(
                            self.attr_pos(c, "v"),
                            format!("unknown light type '{v}'; expected one of: {}", LIGHT_TYPES.join(", ")),
                        ));
                    };
                    kind = known;
                }
                "color" => light.color = self.color(c)?,
                "function" => light.attenuation = self.function(c)?,
                "position" => light.position = self.triple(c, ["x", "y", "z"])?,
                "direction" => light.direction = self.triple(c, ["x", "y", "z"])?,
                "angle" => angle = self.single(c)?,
                "penumbra" => penumbra = self.single(c)?,
                "width" => width = self.single(c)?,
                "height" => height = self.single(c)?,
                _ => self.unknown(c, "<lightdata>", &LIGHT_CHILDREN),
            }
        }
        light.kind = match kind {
            "directional" => LightKind::Directional,
            "spot" => LightKind::Spot { angle, penumbra },
            "area" => LightKind::Area { width, height },
            _ => LightKind::Point,
        };
        Ok(light)
    }

    /// `<function>`: attenuation coefficients under any of the names the course reads.
    fn function(&mut self, c: El) -> Result<Vec3> {
        for names in [["a", "b", "c"], ["x", "y", "z"], ["v1", "v2", "v3"]] {
            if names.iter().all(|n| c.has_attribute(*n)) {
                return self.triple(c, names);
            }
        }
        Err(self.src.invalid(
            self.pos(c),
            "<function> needs the attenuation coefficients as attributes a, b, c (or x, y, z or v1, v2, v3)",
        ))
    }

    fn register_object(&mut self, e: El) -> Result<()> {
        let Some(name) = e.attribute("name") else {
            return Err(self.src.invalid(self.pos(e), "a top-level <object> needs a name attribute"));
        };
        if e.attribute("type") != Some("tree") {
            return Err(self.src.invalid(
                self.attr_pos(e, "type"),
                format!(
                    "top-level <object> elements must be of type \"tree\", found {}",
                    e.attribute("type").map_or_else(|| "no type".to_owned(), |t| format!("\"{t}\""))
                ),
            ));
        }
        if let Some(&first) = self.objects.get(name) {
            let first = self.src.origin(self.templates[first].group.pos);
            return Err(self.src.invalid(
                self.attr_pos(e, "name"),
                format!("two objects are named '{name}'; the first is at {first}"),
            ));
        }
        self.objects.insert(name.to_owned(), self.templates.len());
        self.templates.push(Template { name: name.to_owned(), group: Group { pos: self.pos(e), ..Group::default() } });
        Ok(())
    }

    /// An `<object type="tree">`: a group of its transblocks.
    fn object_tree(&mut self, e: El) -> Result<Group> {
        let mut group = Group { pos: self.pos(e), ..Group::default() };
        for c in e.children().filter(Node::is_element) {
            if c.tag_name().name() == "transblock" {
                group.children.push(Child::Group(self.transblock(c)?));
            } else {
                self.unknown(c, "<object type=\"tree\">", &["transblock"]);
            }
        }
        Ok(group)
    }

    /// A `<transblock>`: transforms (applied to everything in the block, the first
    /// written outermost) and objects.
    fn transblock(&mut self, e: El) -> Result<Group> {
        let mut group = Group { pos: self.pos(e), ..Group::default() };
        let mut written_ops = Vec::new();
        for c in e.children().filter(Node::is_element) {
            let pos = self.pos(c);
            match c.tag_name().name() {
                "translate" => written_ops.push(model::translate(self.src, pos, self.triple(c, ["x", "y", "z"])?)?),
                "scale" => written_ops.push(model::scale(self.src, pos, self.triple(c, ["x", "y", "z"])?)?),
                "rotate" => {
                    let axis = self.triple(c, ["x", "y", "z"])?;
                    let angle = if c.has_attribute("angle") || !c.has_attribute("a") { "angle" } else { "a" };
                    let degrees = self.number(c, angle)?;
                    written_ops.push(model::rotate(self.src, pos, axis, degrees)?);
                }
                "matrix" => written_ops.push(self.matrix(c)?),
                "object" => self.transblock_object(c, &mut group)?,
                _ => self.unknown(c, "<transblock>", &TRANSBLOCK_CHILDREN),
            }
        }
        // CTM = T₁·T₂·…: the last written acts on the objects first.
        written_ops.reverse();
        group.transform = written_ops;
        Ok(group)
    }

    fn transblock_object(&mut self, c: El, group: &mut Group) -> Result<()> {
        let pos = self.pos(c);
        match c.attribute("type") {
            Some("primitive") => group.primitives.push(self.primitive(c)?),
            Some("master") => {
                let name = self.attr(c, "name")?;
                let Some(&index) = self.objects.get(name) else {
                    let mut known: Vec<&str> = self.objects.keys().map(String::as_str).collect();
                    known.sort_unstable();
                    return Err(self.src.invalid(
                        self.attr_pos(c, "name"),
                        format!("unknown master object '{name}'; top-level objects: {}", known.join(", ")),
                    ));
                };
                group.children.push(Child::Template { index, pos });
            }
            Some("tree") => {
                // An inline tree: its transblocks are children of this block.
                let tree = self.object_tree(c)?;
                group.children.extend(tree.children);
            }
            other => {
                return Err(self.src.invalid(
                    self.attr_pos(c, "type"),
                    format!(
                        "{} for <object>; expected type=\"primitive\", \"master\" or \"tree\"",
                        other.map_or_else(|| "no type".to_owned(), |t| format!("unknown type \"{t}\""))
                    ),
                ));
            }
        }
        Ok(())
    }

    fn matrix(&mut self, e: El) -> Result<TransformOp> {
        let mut rows = [[0.0f32; 4]; 4];
        let mut count = 0;
        for row in e.children().filter(Node::is_element) {
            if count == 4 {
                self.warnings.at(self.src, self.pos(row), "a <matrix> has 4 rows; this extra row is ignored");
                continue;
            }
            let names = if row.has_attribute("a") { ["a", "b", "c", "d"] } else { ["v1", "v2", "v3", "v4"] };
            for (i, name) in names.iter().enumerate() {
                rows[count][i] = self.number(row, name)?;
            }
            count += 1;
        }
        if count < 4 {
            return Err(self.src.invalid(
                self.pos(e),
                format!("a <matrix> needs 4 rows like <row a=\"1\" b=\"0\" c=\"0\" d=\"0\"/>, found {count}"),
            ));
        }
        model::matrix(self.src, self.pos(e), rows)
    }

    fn primitive(&mut self, e: El) -> Result<Primitive> {
        let name = self.attr(e, "name")?;
        let shape = match name {
            "cube" => Shape::Cube,
            "cone" => Shape::Cone,
            "cylinder" => Shape::Cylinder,
            "sphere" => Shape::Sphere,
            "torus" => Shape::Torus,
            "mesh" => match e.attribute("meshfile").or_else(|| e.attribute("filename")) {
                Some(file) => Shape::Mesh(file.to_owned()),
                None => {
                    return Err(self.src.invalid(self.pos(e), "a mesh object needs its file: meshfile=\"path.obj\""));
                }
            },
            _ => {
                return Err(self.src.invalid(
                    self.attr_pos(e, "name"),
                    format!("unknown primitive '{name}'; expected one of: {}", PRIMITIVES.join(", ")),
                ));
            }
        };
        let mut m = Material::default();
        for c in e.children().filter(Node::is_element) {
            match c.tag_name().name() {
                "diffuse" => m.diffuse = self.color(c)?,
                "ambient" => m.ambient = self.color(c)?,
                "specular" => m.specular = self.color(c)?,
                "reflective" => m.reflective = self.color(c)?,
                "transparent" => m.transparent = self.color(c)?,
                "emissive" => m.emissive = self.color(c)?,
                "shininess" => m.shininess = self.single(c)?,
                "ior" => m.ior = self.single(c)?,
                "blend" => m.blend = self.single(c)?,
                "texture" => {
                    let file = self.attr(c, "file")?.to_owned();
                    let u = if c.has_attribute("u") { self.number(c, "u")? } else { 1.0 };
                    let v = if c.has_attribute("v") { self.number(c, "v")? } else { 1.0 };
                    m.texture = Some(TextureMap { file, repeat: Vec2::new(u, v), pos: self.pos(c) });
                }
                "bumpmap" => {
                    let pos = self.pos(c);
                    self.warnings.at(self.src, pos, "bump maps are not supported; <bumpmap> is ignored");
                }
                _ => self.unknown(c, "a primitive", &MATERIAL_CHILDREN),
            }
        }
        Ok(Primitive { shape, material: m, pos: self.pos(e) })
    }

    fn attr(&self, e: El<'a, 'input>, name: &str) -> Result<&'a str> {
        e.attribute(name).ok_or_else(|| {
            self.src.invalid(self.pos(e), format!("<{}> needs the attribute {name}=\"…\"", e.tag_name().name()))
        })
    }

    /// A number attribute, which must be present and finite.
    fn number(&self, e: El, name: &str) -> Result<f32> {
        let text = self.attr(e, name)?;
        match text.trim().parse::<f32>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.src.invalid(
                self.attr_pos(e, name),
                format!("{name}=\"{text}\" of <{}> is not a number", e.tag_name().name()),
            )),
        }
    }

    /// `<x v="…"/>`.
    fn single(&self, e: El) -> Result<f32> {
        self.number(e, "v")
    }

    fn triple(&self, e: El, names: [&str; 3]) -> Result<Vec3> {
        Ok(Vec3::new(self.number(e, names[0])?, self.number(e, names[1])?, self.number(e, names[2])?))
    }

    /// `r g b` (or `x y z`); an alpha `a`/`w` is allowed and ignored.
    fn color(&self, e: El) -> Result<Vec3> {
        if !e.has_attribute("r") && e.has_attribute("x") {
            return self.triple(e, ["x", "y", "z"]);
        }
        self.triple(e, ["r", "g", "b"])
    }
}
