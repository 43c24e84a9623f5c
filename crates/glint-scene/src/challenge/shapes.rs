//! `- add: sphere|plane|cube|cylinder|cone|group|…` and defined object templates.
//!
//! The book's sphere, cube and plane are glint's. Its cylinder and cone are infinite
//! unless bounded by `min`/`max`, open unless `closed`, and its cone is double-napped
//! (radius |y|); glint has the closed unit cylinder and a single closed cone, so those
//! are placed with transforms where that is exact and approximated with a warning where
//! it is not.

use std::borrow::Cow;

use glam::Vec3;
use glint_core::desc::{MaterialDesc, NodeDesc, NodeKind, SetOp, ShapeDesc, SolidDesc, TransformOp};

use super::Reader;
use super::values::{self, Result, Src};
use super::yaml::{Value, Yaml};
use crate::error::{SceneError, SceneErrorKind};
use crate::native::lexer::Pos;

/// Where an unbounded cylinder or cone is cut, in object units from the origin.
pub const UNBOUNDED_EXTENT: f32 = 1000.0;

/// Defined templates may use other templates; deeper nesting than this is a cycle.
const MAX_NESTING: usize = 64;

/// Kinds glint cannot draw yet, skipped with a warning.
const SKIPPED: [&str; 2] = ["triangle", "smooth-triangle"];

impl Reader {
    /// One object item; `None` when it is skipped. `inherited` is the material of the
    /// enclosing group, used by children that name none.
    pub(super) fn object(&mut self, item: &Yaml, inherited: Option<&Yaml>, depth: usize) -> Result<Option<NodeDesc>> {
        let src = &self.src;
        if depth >= MAX_NESTING {
            return Err(src.invalid(item.pos, format!("objects nest more than {MAX_NESTING} deep")));
        }
        let entries = values::mapping(src, item, "an object")?;
        let kind_node = values::required(src, entries, item.pos, "add", "an object")?;
        let kind = values::word(src, kind_node, "add")?;
        let shadowless = casts_no_shadow(src, entries)?;
        let node = match kind {
            "sphere" | "plane" | "cube" | "cylinder" | "cone" => self.shape(item, entries, kind, inherited).map(Some),
            "group" => self.group(item, entries, inherited, depth).map(Some),
            "csg" => self.csg(item, entries, inherited, depth),
            "obj" => self.obj(item, entries, inherited),
            _ => return self.other_object(item, kind_node, kind, inherited, depth),
        }?;
        Ok(node.map(|mut node| {
            if shadowless {
                self.without_shadows(&mut node);
            }
            node
        }))
    }

    /// Every material in `node` replaced by a copy that casts no shadow (`shadow:
    /// false` on the item or a group around it).
    fn without_shadows(&mut self, node: &mut NodeDesc) {
        let mut each = |material: &mut usize| *material = self.shadowless_material(*material);
        visit_materials(node, &mut each);
    }

    /// The index of a copy of material `index` that casts no shadow, made once.
    fn shadowless_material(&mut self, index: usize) -> usize {
        if !self.desc.materials[index].casts_shadows {
            return index;
        }
        if let Some(&copy) = self.shadowless.get(&index) {
            return copy;
        }
        let original = &self.desc.materials[index];
        let copy =
            MaterialDesc { name: format!("{} (no shadow)", original.name), casts_shadows: false, ..original.clone() };
        self.desc.materials.push(copy);
        self.shadowless.insert(index, self.desc.materials.len() - 1);
        self.desc.materials.len() - 1
    }

    /// Kinds beyond the primitives, groups, CSG and OBJ: skipped ones, misplaced cameras
    /// and lights, defined templates, or an unknown name.
    fn other_object(
        &mut self,
        item: &Yaml,
        kind_node: &Yaml,
        kind: &str,
        inherited: Option<&Yaml>,
        depth: usize,
    ) -> Result<Option<NodeDesc>> {
        let src = &self.src;
        match kind {
            _ if SKIPPED.contains(&kind) => {
                self.warn(kind_node.pos, format!("glint has no '{kind}' primitive yet; the object is skipped"));
                Ok(None)
            }
            "camera" | "light" => {
                Err(src
                    .invalid(kind_node.pos, format!("a {kind} belongs at the top level of the scene, not in a group")))
            }
            _ => match self.defines.get(kind).filter(|d| d.value.get("add").is_some()) {
                Some(define) => {
                    let merged = template(&define.value, item);
                    self.object(&merged, inherited, depth + 1)
                }
                None => {
                    let mut known: Vec<&str> = ADD_KINDS.to_vec();
                    let mut templates: Vec<&str> = self
                        .defines
                        .iter()
                        .filter(|(_, d)| d.value.get("add").is_some())
                        .map(|(name, _)| name.as_str())
                        .collect();
                    templates.sort_unstable();
                    known.extend(templates);
                    let hint = values::did_you_mean(kind, &known);
                    Err(self.src.invalid(
                        kind_node.pos,
                        format!("unknown object '{kind}'{hint}; expected one of: {}", known.join(", ")),
                    ))
                }
            },
        }
    }

    /// A primitive with its material and transform.
    fn shape(
        &mut self,
        item: &Yaml,
        entries: &[(Yaml, Yaml)],
        kind: &str,
        inherited: Option<&Yaml>,
    ) -> Result<NodeDesc> {
        let src = &self.src;
        let mut known = vec!["add", "material", "transform", "shadow"];
        if matches!(kind, "cylinder" | "cone") {
            known.extend(["min", "max", "closed"]);
        }
        let mut warnings = Vec::new();
        values::unknown_keys(src, entries, &known, &format!("in '{kind}'"), &mut warnings);
        let transform = match values::get(entries, "transform") {
            Some(t) => self.transform(t, "transform")?,
            None => Vec::new(),
        };
        let bounds = if matches!(kind, "cylinder" | "cone") { Some(self.bounds(entries, item.pos)?) } else { None };
        for warning in warnings {
            if !self.warnings.contains(&warning) {
                self.warnings.push(warning);
            }
        }
        let shape = match kind {
            "sphere" => ShapeDesc::Sphere,
            "plane" => ShapeDesc::Plane,
            "cube" => ShapeDesc::Cube,
            "cylinder" => ShapeDesc::Cylinder,
            _ => ShapeDesc::Cone,
        };
        let material_node = values::get(entries, "material").or(inherited);
        let material = self.material(material_node, shape, kind, item.pos)?;
        let origin = self.src.origin(item.pos);
        let leaf = |pre: Vec<TransformOp>| NodeDesc {
            transform: pre,
            kind: NodeKind::Shape { shape, material },
            origin: origin.clone(),
        };
        let node = match (shape, bounds) {
            (ShapeDesc::Cylinder, Some(b)) => {
                let mut ops = self.cylinder_placement(item.pos, b);
                ops.extend(transform);
                NodeDesc { transform: ops, ..leaf(Vec::new()) }
            }
            (ShapeDesc::Cone, Some(b)) => {
                let nappes = self.cone_placement(item.pos, b);
                match <[Vec<TransformOp>; 1]>::try_from(nappes) {
                    Ok([mut ops]) => {
                        ops.extend(transform);
                        leaf(ops)
                    }
                    Err(nappes) => {
                        self.count_nodes(item.pos, nappes.len())?;
                        NodeDesc {
                            transform,
                            kind: NodeKind::Group(nappes.into_iter().map(leaf).collect()),
                            origin: origin.clone(),
                        }
                    }
                }
            }
            _ => leaf(transform),
        };
        self.count_nodes(item.pos, 1)?;
        Ok(node)
    }

    /// `min`, `max` and `closed` of a cylinder or cone, with the book's defaults
    /// (unbounded and open).
    fn bounds(&self, entries: &[(Yaml, Yaml)], pos: Pos) -> Result<Bounds> {
        let src = &self.src;
        let min = values::get(entries, "min").map(|n| values::bound(src, n, "min")).transpose()?;
        let max = values::get(entries, "max").map(|n| values::bound(src, n, "max")).transpose()?;
        let closed = values::get(entries, "closed").map(|n| values::boolean(src, n, "closed")).transpose()?;
        let (min, max) = (min.unwrap_or(f32::NEG_INFINITY), max.unwrap_or(f32::INFINITY));
        if min >= max {
            let at = values::get(entries, "max").or_else(|| values::get(entries, "min")).map_or(pos, |n| n.pos);
            return Err(src.invalid(at, format!("'min' {min} must be below 'max' {max}, or the object is empty")));
        }
        Ok(Bounds { min, max, closed: closed.unwrap_or(false) })
    }

    /// glint's cylinder (−1 ≤ y ≤ 1, closed) scaled and moved onto `min ≤ y ≤ max`.
    fn cylinder_placement(&mut self, pos: Pos, b: Bounds) -> Vec<TransformOp> {
        let (lo, hi) = self.cut_unbounded(pos, b, "cylinder");
        if !b.closed {
            self.warn(pos, "glint's cylinders have caps; this open cylinder is drawn closed");
        }
        vec![
            TransformOp::Scale(Vec3::new(1.0, 0.5 * (hi - lo), 1.0)),
            TransformOp::Translate(Vec3::new(0.0, 0.5 * (hi + lo), 0.0)),
        ]
    }

    /// The book's cone (radius |y|) from glint's cones (apex y = 1, base radius 1 at
    /// y = −1): one nappe, or two apex to apex for `min < 0 < max`. Each is a transform
    /// list placing one glint cone.
    fn cone_placement(&mut self, pos: Pos, b: Bounds) -> Vec<Vec<TransformOp>> {
        let (mut lo, mut hi) = self.cut_unbounded(pos, b, "cone");
        if !b.closed {
            self.warn(pos, "glint's cones have a base cap; this open cone is drawn closed");
        }
        if lo > 0.0 || hi < 0.0 {
            self.warn(pos, "glint's cones reach their apex; this truncated cone is drawn up to its apex at y = 0");
            lo = lo.min(0.0);
            hi = hi.max(0.0);
        }
        [hi, lo].into_iter().filter(|&end| end != 0.0).map(nappe).collect()
    }

    /// Replaces infinite bounds by ±[`UNBOUNDED_EXTENT`], with a warning.
    fn cut_unbounded(&mut self, pos: Pos, b: Bounds, what: &str) -> (f32, f32) {
        if b.min.is_finite() && b.max.is_finite() {
            return (b.min, b.max);
        }
        let lo = if b.min.is_finite() { b.min } else { b.max.min(0.0) - UNBOUNDED_EXTENT };
        let hi = if b.max.is_finite() { b.max } else { b.min.max(0.0) + UNBOUNDED_EXTENT };
        self.warn(pos, format!("glint has no infinite {what}; this one is cut at y = {lo} and y = {hi}"));
        (lo, hi)
    }

    /// `- add: group` with `children`, `transform` and a `material` for children that
    /// name none.
    fn group(
        &mut self,
        item: &Yaml,
        entries: &[(Yaml, Yaml)],
        inherited: Option<&Yaml>,
        depth: usize,
    ) -> Result<NodeDesc> {
        let mut warnings = Vec::new();
        values::unknown_keys(
            &self.src,
            entries,
            &["add", "children", "transform", "material", "shadow"],
            "in 'group'",
            &mut warnings,
        );
        for warning in warnings {
            if !self.warnings.contains(&warning) {
                self.warnings.push(warning);
            }
        }
        let transform = match values::get(entries, "transform") {
            Some(t) => self.transform(t, "transform")?,
            None => Vec::new(),
        };
        let material = values::get(entries, "material").or(inherited);
        let mut children = Vec::new();
        if let Some(list) = values::get(entries, "children") {
            for child in values::list(&self.src, list, "children")? {
                if let Some(node) = self.object(child, material, depth + 1)? {
                    children.push(node);
                }
            }
        }
        self.count_nodes(item.pos, 1)?;
        Ok(NodeDesc { transform, kind: NodeKind::Group(children), origin: self.src.origin(item.pos) })
    }
}

impl Reader {
    /// `add: csg` with `operation: union|intersection|difference`, `left` and `right`
    /// objects: a glint CSG solid (the book's `difference` is left minus right).
    fn csg(
        &mut self,
        item: &Yaml,
        entries: &[(Yaml, Yaml)],
        inherited: Option<&Yaml>,
        depth: usize,
    ) -> Result<Option<NodeDesc>> {
        let mut warnings = Vec::new();
        let known = ["add", "operation", "left", "right", "transform", "material", "shadow"];
        values::unknown_keys(&self.src, entries, &known, "in 'csg'", &mut warnings);
        for warning in warnings {
            if !self.warnings.contains(&warning) {
                self.warnings.push(warning);
            }
        }
        let op_node = values::required(&self.src, entries, item.pos, "operation", "a csg")?;
        let op = match values::word(&self.src, op_node, "operation")? {
            "union" => SetOp::Union,
            "intersection" => SetOp::Intersection,
            "difference" => SetOp::Difference,
            other => {
                return Err(self.src.invalid(
                    op_node.pos,
                    format!("unknown csg operation '{other}'; expected union, intersection or difference"),
                ));
            }
        };
        let material = values::get(entries, "material").or(inherited);
        let mut children = Vec::new();
        for side in ["left", "right"] {
            let child = operand(values::required(&self.src, entries, item.pos, side, "a csg")?);
            match self.object(&child, material, depth + 1)? {
                Some(node) => children.push(node),
                None => {
                    self.warn(child.pos, format!("the csg's {side} side draws nothing, so the csg is skipped"));
                    return Ok(None);
                }
            }
        }
        let transform = match values::get(entries, "transform") {
            Some(t) => self.transform(t, "transform")?,
            None => Vec::new(),
        };
        self.count_nodes(item.pos, 1)?;
        let kind = NodeKind::Solid(SolidDesc::Csg { op, children });
        Ok(Some(NodeDesc { transform, kind, origin: self.src.origin(item.pos) }))
    }

    /// `add: obj` with `file:` (relative to the scene): the OBJ's triangles as one glint
    /// mesh, placed by the item's transform, in the item's (or inherited) material.
    fn obj(&mut self, item: &Yaml, entries: &[(Yaml, Yaml)], inherited: Option<&Yaml>) -> Result<Option<NodeDesc>> {
        let mut warnings = Vec::new();
        values::unknown_keys(
            &self.src,
            entries,
            &["add", "file", "transform", "material", "shadow"],
            "in 'obj'",
            &mut warnings,
        );
        for warning in warnings {
            if !self.warnings.contains(&warning) {
                self.warnings.push(warning);
            }
        }
        let file_node = values::required(&self.src, entries, item.pos, "file", "an obj")?;
        let Some(file) = file_node.scalar() else {
            return Err(self.src.invalid(file_node.pos, "'file' must be the path of an .obj file"));
        };
        let path = self.src.dir.join(file);
        let import = crate::mesh::load_mesh(&path).map_err(|e| {
            SceneError::new(
                SceneErrorKind::Io,
                self.src.name.clone(),
                file_node.pos.line,
                file_node.pos.column,
                format!("cannot load '{file}': {e}"),
            )
        })?;
        self.desc.meshes.push(crate::mesh::merged(&import, file, &path.display().to_string()));
        let index = self.desc.meshes.len() - 1;
        let shape = ShapeDesc::Mesh { index };
        let material = self.material(values::get(entries, "material").or(inherited), shape, "obj", item.pos)?;
        let transform = match values::get(entries, "transform") {
            Some(t) => self.transform(t, "transform")?,
            None => Vec::new(),
        };
        self.count_nodes(item.pos, 1)?;
        Ok(Some(NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: self.src.origin(item.pos) }))
    }
}

/// What `add:` names directly, for the "expected one of" message.
const ADD_KINDS: [&str; 11] =
    ["camera", "light", "sphere", "plane", "cube", "cylinder", "cone", "group", "obj", "csg", "triangle"];

/// `min`/`max` (possibly infinite) and `closed` of a cylinder or cone.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    min: f32,
    max: f32,
    closed: bool,
}

/// The transform taking glint's cone (apex y = 1, base y = −1, radius 1) to the book's
/// nappe from the apex at y = 0 to its closed end at y = `end` (radius |end|):
/// `y = (end/2)·(1 − y_glint)`, radius scaled by |end|.
fn nappe(end: f32) -> Vec<TransformOp> {
    vec![
        TransformOp::Scale(Vec3::new(end.abs(), -0.5 * end, end.abs())),
        TransformOp::Translate(Vec3::new(0.0, 0.5 * end, 0.0)),
    ]
}

/// Whether the item says `shadow: false`: the object is drawn but casts no shadow.
fn casts_no_shadow(src: &Src, entries: &[(Yaml, Yaml)]) -> Result<bool> {
    match values::get(entries, "shadow") {
        Some(shadow) => Ok(!values::boolean(src, shadow, "shadow")?),
        None => Ok(false),
    }
}

/// A csg operand as the book's bonus scenes write it, with `type: cube` in place of
/// `add: cube`, turned into the usual form.
fn operand(child: &Yaml) -> Cow<'_, Yaml> {
    let Some(entries) = child.map().filter(|e| values::get(e, "add").is_none()) else {
        return Cow::Borrowed(child);
    };
    if values::get(entries, "type").is_none() {
        return Cow::Borrowed(child);
    }
    let renamed = entries
        .iter()
        .map(|(k, v)| {
            if k.scalar() == Some("type") {
                let key = Yaml { value: Value::Scalar { text: "add".into(), plain: true }, pos: k.pos };
                (key, v.clone())
            } else {
                (k.clone(), v.clone())
            }
        })
        .collect();
    Cow::Owned(Yaml { value: Value::Map(renamed), pos: child.pos })
}

/// A defined object template used as `add: NAME`: the definition's keys overridden by
/// the item's, except `transform`, where the item's list follows the definition's.
fn template(define: &Yaml, item: &Yaml) -> Yaml {
    let base = define.map().unwrap_or_default();
    let over = item.map().unwrap_or_default();
    let mut merged: Vec<(Yaml, Yaml)> = base
        .iter()
        .filter(|(k, _)| {
            let key = k.scalar().unwrap_or("");
            key == "add" || key == "transform" || values::get(over, key).is_none()
        })
        .cloned()
        .collect();
    for (k, v) in over {
        match k.scalar() {
            Some("add") => {}
            Some("transform") => {
                let as_items = |t: &Yaml| match t.seq() {
                    Some(items) => items.to_vec(),
                    None => vec![t.clone()],
                };
                match merged.iter_mut().find(|(key, _)| key.scalar() == Some("transform")) {
                    Some((_, existing)) => {
                        let mut items = as_items(existing);
                        items.extend(as_items(v));
                        *existing = Yaml { value: Value::Seq(items), pos: v.pos };
                    }
                    None => merged.push((k.clone(), v.clone())),
                }
            }
            _ => merged.push((k.clone(), v.clone())),
        }
    }
    Yaml { value: Value::Map(merged), pos: item.pos }
}

/// Calls `each` on every material index in `node` and below.
fn visit_materials(node: &mut NodeDesc, each: &mut impl FnMut(&mut usize)) {
    match &mut node.kind {
        NodeKind::Shape { material, .. } => each(material),
        NodeKind::Group(children) | NodeKind::Moving { children, .. } => {
            children.iter_mut().for_each(|c| visit_materials(c, each));
        }
        NodeKind::Solid(solid) => match solid {
            SolidDesc::Csg { children, .. } => children.iter_mut().for_each(|c| visit_materials(c, each)),
            SolidDesc::Blob { material, .. }
            | SolidDesc::Implicit { material, .. }
            | SolidDesc::Quadric { material, .. }
            | SolidDesc::Superellipsoid { material, .. } => each(material),
        },
    }
}
