//! CS1230 JSON scenefiles (2023 on), as the course's reader defines them: required and
//! optional fields, defaults, and the transform order translate·rotate·scale·matrix.
//! Unknown fields, which the course's reader refuses, are warnings here.

use std::collections::HashMap;

use glam::{Vec2, Vec3};
use glint_core::desc::TransformOp;

use super::json_value::{self, Kind, Member, Value};
use super::model::{
    self, Camera, Child, CourseScene, Global, Group, Light, LightKind, Material, Primitive, Shape, Template, TextureMap,
};
use super::{Pos, Result, Source, Warnings};
use crate::error::SceneErrorKind;

const ROOT_FIELDS: [&str; 5] = ["name", "globalData", "cameraData", "groups", "templateGroups"];
const GLOBAL_FIELDS: [&str; 4] = ["ambientCoeff", "diffuseCoeff", "specularCoeff", "transparentCoeff"];
const CAMERA_FIELDS: [&str; 7] = ["position", "up", "heightAngle", "look", "focus", "aperture", "focalLength"];
const GROUP_FIELDS: [&str; 8] = ["name", "translate", "rotate", "scale", "matrix", "lights", "primitives", "groups"];
const LIGHT_FIELDS: [&str; 9] =
    ["name", "type", "color", "attenuationCoeff", "direction", "penumbra", "angle", "width", "height"];
const LIGHT_TYPES: [&str; 4] = ["point", "directional", "spot", "area"];
const PRIMITIVE_TYPES: [&str; 5] = ["cube", "sphere", "cylinder", "cone", "mesh"];
const PRIMITIVE_FIELDS: [&str; 16] = [
    "type",
    "meshFile",
    "ambient",
    "diffuse",
    "specular",
    "reflective",
    "transparent",
    "shininess",
    "ior",
    "blend",
    "textureFile",
    "textureU",
    "textureV",
    "bumpMapFile",
    "bumpMapU",
    "bumpMapV",
];

/// Reads the text into the course model.
pub fn read(src: &Source, text: &str, warnings: &mut Warnings) -> Result<CourseScene> {
    let doc = json_value::parse(text).map_err(|e| src.error(SceneErrorKind::Syntax, e.pos, e.message))?;
    let mut reader = Reader { src, warnings, templates: Vec::new(), template_names: HashMap::new() };
    reader.scene(&doc)
}

struct Reader<'a> {
    src: &'a Source,
    warnings: &'a mut Warnings,
    templates: Vec<Template>,
    template_names: HashMap<String, usize>,
}

/// An object's members, looked up by key, with the object's position for messages
/// about missing keys.
struct Obj<'v> {
    members: &'v [Member],
    pos: Pos,
    what: &'static str,
}

impl<'v> Obj<'v> {
    fn get(&self, key: &str) -> Option<&'v Value> {
        // The course's reader keeps the last of duplicate keys.
        self.members.iter().rev().find(|m| m.key == key).map(|m| &m.value)
    }
}

impl Reader<'_> {
    /// `value` as an object; its unknown and repeated keys are warnings.
    fn object<'v>(&mut self, value: &'v Value, what: &'static str, allowed: &[&str]) -> Result<Obj<'v>> {
        let Kind::Object(members) = &value.kind else {
            return Err(self
                .src
                .invalid(value.pos, format!("{what} must be an object {{ … }}, found {}", value.describe())));
        };
        for (i, m) in members.iter().enumerate() {
            if !allowed.contains(&m.key.as_str()) {
                self.warnings.at(
                    self.src,
                    m.key_pos,
                    format!(
                        "unknown field \"{}\" in {what} is ignored; expected one of: {}",
                        m.key,
                        allowed.join(", ")
                    ),
                );
            } else if members[..i].iter().any(|earlier| earlier.key == m.key) {
                self.warnings.at(
                    self.src,
                    m.key_pos,
                    format!("\"{}\" is given twice in {what}; the last one is used", m.key),
                );
            }
        }
        Ok(Obj { members, pos: value.pos, what })
    }

    fn required<'v>(&self, obj: &Obj<'v>, key: &str) -> Result<&'v Value> {
        obj.get(key).ok_or_else(|| self.src.invalid(obj.pos, format!("{} needs the field \"{key}\"", obj.what)))
    }

    fn number(&self, v: &Value, key: &str) -> Result<f32> {
        match v.kind {
            Kind::Number(x) if (x as f32).is_finite() => Ok(x as f32),
            Kind::Number(_) => Err(self.src.invalid(v.pos, format!("\"{key}\" is too large for a 32-bit float"))),
            _ => Err(self.src.invalid(v.pos, format!("\"{key}\" must be a number, found {}", v.describe()))),
        }
    }

    fn string<'v>(&self, v: &'v Value, key: &str) -> Result<&'v str> {
        match &v.kind {
            Kind::String(s) => Ok(s),
            _ => Err(self.src.invalid(v.pos, format!("\"{key}\" must be a string, found {}", v.describe()))),
        }
    }

    fn array<'v>(&self, v: &'v Value, key: &str) -> Result<&'v [Value]> {
        match &v.kind {
            Kind::Array(items) => Ok(items),
            _ => Err(self.src.invalid(v.pos, format!("\"{key}\" must be an array [ … ], found {}", v.describe()))),
        }
    }

    /// An array of exactly `n` numbers (`hint` shows the expected form).
    fn numbers(&self, v: &Value, key: &str, n: usize, hint: &str) -> Result<Vec<f32>> {
        let items = self.array(v, key)?;
        if items.len() != n {
            return Err(self
                .src
                .invalid(v.pos, format!("\"{key}\" needs {n} numbers, like {hint}, found {} values", items.len())));
        }
        items.iter().map(|x| self.number(x, key)).collect()
    }

    fn vec3(&self, v: &Value, key: &str) -> Result<Vec3> {
        let n = self.numbers(v, key, 3, "[1, 0.5, 0]")?;
        Ok(Vec3::new(n[0], n[1], n[2]))
    }

    fn scene(&mut self, doc: &Value) -> Result<CourseScene> {
        let root = self.object(doc, "the scene", &ROOT_FIELDS)?;
        let global = self.global(self.required(&root, "globalData")?)?;
        let camera = self.camera(self.required(&root, "cameraData")?)?;
        if let Some(v) = root.get("name") {
            self.string(v, "name")?;
        }
        if let Some(templates) = root.get("templateGroups") {
            for t in self.array(templates, "templateGroups")? {
                self.template(t)?;
            }
        }
        let mut group = Group { pos: doc.pos, ..Group::default() };
        if let Some(groups) = root.get("groups") {
            self.groups(groups, &mut group)?;
        }
        Ok(CourseScene {
            global,
            camera,
            lights: Vec::new(),
            root: group,
            templates: std::mem::take(&mut self.templates),
        })
    }

    fn global(&mut self, v: &Value) -> Result<Global> {
        let o = self.object(v, "\"globalData\"", &GLOBAL_FIELDS)?;
        let coefficient = |key| self.number(self.required(&o, key)?, key);
        let (ka, kd, ks) = (coefficient("ambientCoeff")?, coefficient("diffuseCoeff")?, coefficient("specularCoeff")?);
        let kt = match o.get("transparentCoeff") {
            Some(v) => self.number(v, "transparentCoeff")?,
            None => 0.0,
        };
        Ok(Global { ka, kd, ks, kt })
    }

    fn camera(&mut self, v: &Value) -> Result<Camera> {
        let o = self.object(v, "\"cameraData\"", &CAMERA_FIELDS)?;
        let position = self.vec3(self.required(&o, "position")?, "position")?;
        let up = self.vec3(self.required(&o, "up")?, "up")?;
        let height_angle = self.number(self.required(&o, "heightAngle")?, "heightAngle")?;
        let look = match (o.get("look"), o.get("focus")) {
            (Some(_), Some(focus)) => {
                return Err(self
                    .src
                    .invalid(focus.pos, "\"cameraData\" has both \"look\" and \"focus\"; give one of them"));
            }
            (Some(look), None) => self.vec3(look, "look")?,
            (None, Some(focus)) => self.vec3(focus, "focus")? - position,
            (None, None) => {
                return Err(self
                    .src
                    .invalid(o.pos, "\"cameraData\" needs \"look\" (a direction) or \"focus\" (a point to look at)"));
            }
        };
        let aperture = o.get("aperture").map(|v| self.number(v, "aperture").map(|x| (x, v.pos))).transpose()?;
        let focal = o.get("focalLength").map(|v| self.number(v, "focalLength").map(|x| (x, v.pos))).transpose()?;
        let depth_of_field = (aperture.is_some() || focal.is_some()).then(|| {
            let pos = aperture.or(focal).map_or(o.pos, |(_, p)| p);
            (aperture.map_or(0.0, |a| a.0), focal.map_or(0.0, |f| f.0), pos)
        });
        Ok(Camera { position, look, up, height_angle, depth_of_field, pos: o.pos })
    }

    /// A `templateGroups` entry: a named group, usable by later groups (and templates).
    fn template(&mut self, v: &Value) -> Result<()> {
        let o = self.object(v, "a template group", &GROUP_FIELDS)?;
        let name_value = self.required(&o, "name")?;
        let name = self.string(name_value, "name")?.to_owned();
        if let Some(&first) = self.template_names.get(&name) {
            let first = self.src.origin(self.templates[first].group.pos);
            return Err(self
                .src
                .invalid(name_value.pos, format!("two template groups are named '{name}'; the first is at {first}")));
        }
        // Registered before its body is read, as the course does, so that a template
        // that names itself is caught as a cycle rather than read as a plain group.
        let index = self.templates.len();
        self.template_names.insert(name.clone(), index);
        self.templates.push(Template { name, group: Group { pos: v.pos, ..Group::default() } });
        let group = self.group_body(&o)?;
        self.templates[index].group = group;
        Ok(())
    }

    /// `"groups": [ … ]`: each entry is a group, or a use of a template when its name is
    /// a template's (the entry's other fields are then ignored, as the course does).
    fn groups(&mut self, v: &Value, parent: &mut Group) -> Result<()> {
        for item in self.array(v, "groups")? {
            let o = self.object(item, "a group", &GROUP_FIELDS)?;
            if let Some(name) = o.get("name") {
                let name_text = self.string(name, "name")?;
                if let Some(&index) = self.template_names.get(name_text) {
                    if let Some(extra) = o.members.iter().find(|m| m.key != "name") {
                        self.warnings.at(
                            self.src,
                            extra.key_pos,
                            format!(
                                "this group names the template '{name_text}', so it is that template; its \"{}\" is ignored",
                                extra.key
                            ),
                        );
                    }
                    parent.children.push(Child::Template { index, pos: item.pos });
                    continue;
                }
            }
            let group = self.group_body(&o)?;
            parent.children.push(Child::Group(group));
        }
        Ok(())
    }

    /// The fields of a group: transforms (`M = T·R·S·M_matrix`), lights, primitives and
    /// child groups.
    fn group_body(&mut self, o: &Obj) -> Result<Group> {
        let mut group = Group { pos: o.pos, ..Group::default() };
        // glint order: the first op acts on the objects first.
        if let Some(v) = o.get("matrix") {
            group.transform.push(self.matrix(v)?);
        }
        if let Some(v) = o.get("scale") {
            group.transform.push(model::scale(self.src, v.pos, self.vec3(v, "scale")?)?);
        }
        if let Some(v) = o.get("rotate") {
            let r = self.numbers(v, "rotate", 4, "[0, 1, 0, 45] (an axis and an angle in degrees)")?;
            group.transform.push(model::rotate(self.src, v.pos, Vec3::new(r[0], r[1], r[2]), r[3])?);
        }
        if let Some(v) = o.get("translate") {
            group.transform.push(model::translate(self.src, v.pos, self.vec3(v, "translate")?)?);
        }
        if let Some(v) = o.get("lights") {
            for light in self.array(v, "lights")? {
                group.lights.push(self.light(light)?);
            }
        }
        if let Some(v) = o.get("primitives") {
            for p in self.array(v, "primitives")? {
                group.primitives.push(self.primitive(p)?);
            }
        }
        if let Some(v) = o.get("groups") {
            self.groups(v, &mut group)?;
        }
        Ok(group)
    }

    /// `"matrix": [[row], [row], [row], [row]]`, rows as written.
    fn matrix(&self, v: &Value) -> Result<TransformOp> {
        let rows = self.array(v, "matrix")?;
        let hint = "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]";
        if rows.len() != 4 {
            return Err(self.src.invalid(
                v.pos,
                format!("\"matrix\" needs 4 rows of 4 numbers, like {hint}, found {} rows", rows.len()),
            ));
        }
        let mut m = [[0.0f32; 4]; 4];
        for (i, row) in rows.iter().enumerate() {
            let r = self.numbers(row, "matrix", 4, "[1, 0, 0, 0]")?;
            m[i].copy_from_slice(&r);
        }
        model::matrix(self.src, v.pos, m)
    }

    fn light(&mut self, v: &Value) -> Result<Light> {
        let o = self.object(v, "a light", &LIGHT_FIELDS)?;
        let type_value = self.required(&o, "type")?;
        let kind_name = self.string(type_value, "type")?;
        if !LIGHT_TYPES.contains(&kind_name) {
            return Err(self.src.invalid(
                type_value.pos,
                format!("unknown light type \"{kind_name}\"; expected one of: {}", LIGHT_TYPES.join(", ")),
            ));
        }
        let color = self.vec3(self.required(&o, "color")?, "color")?;
        // What each type needs, as the course's reader asks for it.
        let needed = |key: &str| -> Result<&Value> {
            o.get(key).ok_or_else(|| self.src.invalid(o.pos, format!("a {kind_name} light needs \"{key}\"")))
        };
        let attenuation = if kind_name == "directional" {
            Vec3::X
        } else {
            self.vec3(needed("attenuationCoeff")?, "attenuationCoeff")?
        };
        let direction = if matches!(kind_name, "directional" | "spot") {
            self.vec3(needed("direction")?, "direction")?
        } else {
            Vec3::ZERO
        };
        let number = |key: &str| self.number(needed(key)?, key);
        let kind = match kind_name {
            "point" => LightKind::Point,
            "directional" => LightKind::Directional,
            "spot" => LightKind::Spot { angle: number("angle")?, penumbra: number("penumbra")? },
            _ => LightKind::Area { width: number("width")?, height: number("height")? },
        };
        if let Some(name) = o.get("name") {
            self.string(name, "name")?;
        }
        Ok(Light { kind, color, attenuation, position: Vec3::ZERO, direction, pos: v.pos })
    }

    fn primitive(&mut self, v: &Value) -> Result<Primitive> {
        let o = self.object(v, "a primitive", &PRIMITIVE_FIELDS)?;
        let type_value = self.required(&o, "type")?;
        let shape = match self.string(type_value, "type")? {
            "cube" => Shape::Cube,
            "sphere" => Shape::Sphere,
            "cylinder" => Shape::Cylinder,
            "cone" => Shape::Cone,
            "mesh" => {
                let file = o.get("meshFile").ok_or_else(|| {
                    self.src.invalid(o.pos, "a mesh primitive needs \"meshFile\", the path of its .obj file")
                })?;
                Shape::Mesh(self.string(file, "meshFile")?.to_owned())
            }
            other => {
                return Err(self.src.invalid(
                    type_value.pos,
                    format!("unknown primitive type \"{other}\"; expected one of: {}", PRIMITIVE_TYPES.join(", ")),
                ));
            }
        };
        let mut m = Material::default();
        for (key, target) in [
            ("ambient", &mut m.ambient),
            ("diffuse", &mut m.diffuse),
            ("specular", &mut m.specular),
            ("reflective", &mut m.reflective),
            ("transparent", &mut m.transparent),
        ] {
            if let Some(v) = o.get(key) {
                *target = self.vec3(v, key)?;
            }
        }
        for (key, target) in [("shininess", &mut m.shininess), ("ior", &mut m.ior), ("blend", &mut m.blend)] {
            if let Some(v) = o.get(key) {
                *target = self.number(v, key)?;
            }
        }
        if let Some(file) = o.get("textureFile") {
            let name = self.string(file, "textureFile")?.to_owned();
            // The course takes a repeat that is not a number as 1.
            let repeat =
                |key| o.get(key).and_then(|v| if let Kind::Number(x) = v.kind { Some(x as f32) } else { None });
            let (u, v) = (repeat("textureU").unwrap_or(1.0), repeat("textureV").unwrap_or(1.0));
            m.texture = Some(TextureMap { file: name, repeat: Vec2::new(u, v), pos: file.pos });
        }
        if let Some(bump) = o.get("bumpMapFile") {
            self.warnings.at(self.src, bump.pos, "bump maps are not supported; \"bumpMapFile\" is ignored");
        }
        Ok(Primitive { shape, material: m, pos: v.pos })
    }
}
