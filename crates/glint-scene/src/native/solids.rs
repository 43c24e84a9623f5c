//! Solids beyond the canonical shapes: CSG (`union`, `intersection`, `difference`),
//! `blob`, `implicit`, `quadric` and `superellipsoid`.

use glam::Vec3;
use glint_core::desc::{
    BlobComponentDesc, BlobComponentShape, BlobDesc, ImplicitDesc, NodeDesc, NodeKind, SetOp, SolidDesc, TransformOp,
};
use glint_core::shape::implicit::compile_expression;
use glint_core::shape::superellipsoid::EXPONENT_RANGE;

use super::args::{self, Result, Seen};
use super::builder::{Builder, Source};
use super::lexer::Pos;
use super::objects::{TRANSFORMS, is_object, transform_op};
use super::tree::{Node, ValueKind};

/// The solid node names, in the order the documentation lists them.
pub const SOLIDS: [&str; 7] = ["union", "intersection", "difference", "blob", "implicit", "quadric", "superellipsoid"];

/// Kinds after `component` in a blob.
const COMPONENT_KINDS: [&str; 2] = ["sphere", "cylinder"];

/// Default blob threshold (POV-Ray's tutorials use values around it).
const BLOB_THRESHOLD: f32 = 0.5;

/// Default box of an implicit surface.
const IMPLICIT_BOUNDS: [Vec3; 2] = [Vec3::splat(-1.0), Vec3::ONE];

/// Whether `name` starts a solid node.
pub fn is_solid(name: &str) -> bool {
    SOLIDS.contains(&name)
}

/// Properties and objects shared by the solids' blocks.
struct Common {
    transform: Vec<TransformOp>,
    material: Option<usize>,
    seen: Seen,
}

impl Builder {
    /// Builds one solid node (which [`is_solid`] accepted).
    pub fn solid(&mut self, src: &Source, node: &Node) -> Result<NodeDesc> {
        args::no_values(src, node)?;
        let kind = match node.name.as_str() {
            "union" => return self.csg(src, node, SetOp::Union),
            "intersection" => return self.csg(src, node, SetOp::Intersection),
            "difference" => return self.csg(src, node, SetOp::Difference),
            "blob" => self.blob(src, node)?,
            "implicit" => self.implicit(src, node)?,
            "quadric" => self.quadric(src, node)?,
            _ => self.superellipsoid(src, node)?,
        };
        self.count_nodes(src, node.pos(), 1)?;
        let (solid, transform) = kind;
        Ok(NodeDesc { transform, kind: NodeKind::Solid(solid), origin: src.origin(node.pos()) })
    }

    /// The material of an object that names none: the enclosing CSG node's, if it gave
    /// one, else the default material.
    pub fn material_or_inherited(&mut self, src: &Source, pos: Pos) -> Result<usize> {
        match self.inherited_material {
            Some(index) => Ok(index),
            None => self.default_material(src, pos),
        }
    }

    /// Reads a transform or `material` into `common`; false when `prop` is neither.
    fn common(&mut self, src: &Source, node: &Node, prop: &Node, common: &mut Common) -> Result<bool> {
        if let Some(op) = transform_op(src, prop)? {
            common.transform.push(op);
            return Ok(true);
        }
        if prop.name != "material" {
            return Ok(false);
        }
        common.seen.once(src, prop, &node.name)?;
        args::no_block(src, prop)?;
        let (name, pos) = args::string(src, prop, "a material name")?;
        common.material = Some(self.materials.lookup(src, pos, "material", &name)?);
        Ok(true)
    }

    /// `union { … }`, `intersection { … }`, `difference { first subtracted… }`.
    fn csg(&mut self, src: &Source, node: &Node, op: SetOp) -> Result<NodeDesc> {
        let mut common = Common { transform: Vec::new(), material: None, seen: Seen::default() };
        // Properties first, wherever they are written, so `material` reaches every child.
        for prop in node.children() {
            if !is_object(&prop.name) && !self.common(src, node, prop, &mut common)? {
                let mut allowed = vec!["material"];
                allowed.extend(TRANSFORMS);
                allowed.extend(["objects (shapes, solids, group, use)"]);
                return Err(args::unknown(src, prop, "node", &format!("in '{}'", node.name), &allowed));
            }
        }
        let outer = self.inherited_material;
        if common.material.is_some() {
            self.inherited_material = common.material;
        }
        let children = self.csg_children(src, node);
        self.inherited_material = outer;
        let children = children?;
        if children.is_empty() {
            return Err(src.invalid(
                node.pos(),
                format!(
                    "'{}' needs at least one object inside, like {} {{ sphere {{ }} cube {{ }} }}",
                    node.name, node.name
                ),
            ));
        }
        self.count_nodes(src, node.pos(), 1)?;
        Ok(NodeDesc {
            transform: common.transform,
            kind: NodeKind::Solid(SolidDesc::Csg { op, children }),
            origin: src.origin(node.pos()),
        })
    }

    fn csg_children(&mut self, src: &Source, node: &Node) -> Result<Vec<NodeDesc>> {
        let mut children = Vec::new();
        for child in node.children().iter().filter(|c| is_object(&c.name)) {
            match child.name.as_str() {
                "disk" | "rectangle" => {
                    return Err(src.invalid(
                        child.pos(),
                        format!(
                            "a {} has no inside, so it cannot be part of '{}'; use a thin {} \
                             (a plane works: inside CSG it is the half-space below it)",
                            child.name,
                            node.name,
                            if child.name == "disk" { "cylinder" } else { "cube" }
                        ),
                    ));
                }
                "mesh_instance" => {
                    return Err(src.invalid(
                        child.pos(),
                        format!("a mesh cannot be part of '{}'; use the analytic shapes and solids", node.name),
                    ));
                }
                _ => children.push(self.object(src, child)?),
            }
        }
        Ok(children)
    }

    /// The material of a leaf solid: its own, else inherited or default.
    fn solid_material(&mut self, src: &Source, node: &Node, common: &Common) -> Result<usize> {
        match common.material {
            Some(index) => Ok(index),
            None => self.material_or_inherited(src, node.pos()),
        }
    }

    /// `blob { threshold t  component sphere { … }  component cylinder { … } … }`.
    fn blob(&mut self, src: &Source, node: &Node) -> Result<(SolidDesc, Vec<TransformOp>)> {
        let mut common = Common { transform: Vec::new(), material: None, seen: Seen::default() };
        let mut threshold = BLOB_THRESHOLD;
        let mut components = Vec::new();
        let mut rest = node.children().iter();
        while let Some(prop) = rest.next() {
            if self.common(src, node, prop, &mut common)? {
                continue;
            }
            match prop.name.as_str() {
                "component" => {
                    args::no_values(src, prop)?;
                    let kind = Builder::kind_node(src, prop, rest.next(), &COMPONENT_KINDS)?;
                    components.push(component(src, kind)?);
                }
                "threshold" => {
                    common.seen.once(src, prop, "blob")?;
                    threshold = args::number_where(src, prop, "greater than 0", |x| x > 0.0)?;
                }
                _ => {
                    let mut allowed = vec!["component", "threshold", "material"];
                    allowed.extend(TRANSFORMS);
                    return Err(args::unknown(src, prop, "property", "in 'blob'", &allowed));
                }
            }
        }
        if !components.iter().any(|c: &BlobComponentDesc| c.strength > 0.0) {
            return Err(src.invalid(
                node.pos(),
                "a blob needs at least one component with positive strength, like \
                 `component sphere { radius 1 strength 1 }`",
            ));
        }
        let material = self.solid_material(src, node, &common)?;
        Ok((SolidDesc::Blob { blob: BlobDesc { threshold, components }, material }, common.transform))
    }

    /// `implicit { function "…" bounds [min] [max] lipschitz L }`.
    fn implicit(&mut self, src: &Source, node: &Node) -> Result<(SolidDesc, Vec<TransformOp>)> {
        let mut common = Common { transform: Vec::new(), material: None, seen: Seen::default() };
        let mut function = None;
        let mut bounds = IMPLICIT_BOUNDS;
        let mut lipschitz = None;
        for prop in node.children() {
            if self.common(src, node, prop, &mut common)? {
                continue;
            }
            match prop.name.as_str() {
                "function" => {
                    common.seen.once(src, prop, "implicit")?;
                    args::no_block(src, prop)?;
                    let (text, pos) = args::string(src, prop, "an expression")?;
                    if let Err(e) = compile_expression(&text) {
                        // The column inside the string: after the opening quote.
                        let at = Pos { line: pos.line, column: pos.column + 1 + e.offset as u32 };
                        return Err(src.invalid(at, format!("in the implicit function: {}", e.message)));
                    }
                    function = Some(text);
                }
                "bounds" => {
                    common.seen.once(src, prop, "implicit")?;
                    bounds = box_property(src, prop)?;
                }
                "lipschitz" => {
                    common.seen.once(src, prop, "implicit")?;
                    lipschitz = Some(args::number_where(src, prop, "greater than 0", |x| x > 0.0)?);
                }
                _ => {
                    let mut allowed = vec!["function", "bounds", "lipschitz", "material"];
                    allowed.extend(TRANSFORMS);
                    return Err(args::unknown(src, prop, "property", "in 'implicit'", &allowed));
                }
            }
        }
        let Some(function) = function else {
            return Err(src.invalid(node.pos(), "'implicit' needs a function, like `function \"x^2 + y^2 + z^2 - 1\"`"));
        };
        let material = self.solid_material(src, node, &common)?;
        Ok((SolidDesc::Implicit { implicit: ImplicitDesc { function, bounds, lipschitz }, material }, common.transform))
    }

    /// `quadric { coefficients [A B C D E F G H I J] bounds [min] [max] }`.
    fn quadric(&mut self, src: &Source, node: &Node) -> Result<(SolidDesc, Vec<TransformOp>)> {
        let mut common = Common { transform: Vec::new(), material: None, seen: Seen::default() };
        let mut coefficients = None;
        let mut bounds = None;
        for prop in node.children() {
            if self.common(src, node, prop, &mut common)? {
                continue;
            }
            match prop.name.as_str() {
                "coefficients" => {
                    common.seen.once(src, prop, "quadric")?;
                    let c = args::numbers(src, prop, &[10])?;
                    if c[..9].iter().all(|&x| x == 0.0) {
                        return Err(src.invalid(
                            args::value_pos(prop),
                            "a quadric needs a non-zero coefficient among the first nine; J alone is no surface",
                        ));
                    }
                    let mut array = [0.0; 10];
                    array.copy_from_slice(&c);
                    coefficients = Some(array);
                }
                "bounds" => {
                    common.seen.once(src, prop, "quadric")?;
                    bounds = Some(box_property(src, prop)?);
                }
                _ => {
                    let mut allowed = vec!["coefficients", "bounds", "material"];
                    allowed.extend(TRANSFORMS);
                    return Err(args::unknown(src, prop, "property", "in 'quadric'", &allowed));
                }
            }
        }
        let Some(coefficients) = coefficients else {
            return Err(src.invalid(
                node.pos(),
                "'quadric' needs its coefficients, like `coefficients [1 1 1 0 0 0 0 0 0 -1]` (a unit sphere)",
            ));
        };
        let material = self.solid_material(src, node, &common)?;
        Ok((SolidDesc::Quadric { coefficients, bounds, material }, common.transform))
    }

    /// `superellipsoid { exponents [e1 e2] }`.
    fn superellipsoid(&mut self, src: &Source, node: &Node) -> Result<(SolidDesc, Vec<TransformOp>)> {
        let mut common = Common { transform: Vec::new(), material: None, seen: Seen::default() };
        let (mut e1, mut e2) = (1.0, 1.0);
        for prop in node.children() {
            if self.common(src, node, prop, &mut common)? {
                continue;
            }
            if prop.name != "exponents" {
                let mut allowed = vec!["exponents", "material"];
                allowed.extend(TRANSFORMS);
                return Err(args::unknown(src, prop, "property", "in 'superellipsoid'", &allowed));
            }
            common.seen.once(src, prop, "superellipsoid")?;
            let e = args::numbers(src, prop, &[2])?;
            let (lo, hi) = EXPONENT_RANGE;
            if !e.iter().all(|x| (lo..=hi).contains(x)) {
                return Err(src.invalid(
                    args::value_pos(prop),
                    format!("'exponents' must each be from {lo} to {hi}, found [{} {}]", e[0], e[1]),
                ));
            }
            (e1, e2) = (e[0], e[1]);
        }
        let material = self.solid_material(src, node, &common)?;
        Ok((SolidDesc::Superellipsoid { e1, e2, material }, common.transform))
    }
}

/// `bounds [x y z] [x y z]`: two corners with min < max on every axis.
fn box_property(src: &Source, prop: &Node) -> Result<[Vec3; 2]> {
    args::no_block(src, prop)?;
    let corner = |i: usize| match prop.args.get(i).map(|v| &v.kind) {
        Some(ValueKind::Vector(v)) if v.len() == 3 => Some(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32)),
        _ => None,
    };
    match (corner(0), corner(1), prop.args.len()) {
        (Some(min), Some(max), 2) => {
            if min.cmplt(max).all() {
                Ok([min, max])
            } else {
                Err(src.invalid(
                    args::value_pos(prop),
                    format!("'{}' needs the smaller corner first, smaller on every axis: found {min} {max}", prop.name),
                ))
            }
        }
        _ => Err(src.invalid(
            args::value_pos(prop),
            format!("expected two corners for '{}', like `{} [-1 -1 -1] [1 1 1]`", prop.name, prop.name),
        )),
    }
}

/// `sphere { center radius strength transforms }` or `cylinder { from to radius … }`
/// after `component`.
fn component(src: &Source, kind: &Node) -> Result<BlobComponentDesc> {
    let cylinder = kind.name == "cylinder";
    let (mut center, mut from, mut to) = (Vec3::ZERO, None, None);
    let (mut radius, mut strength) = (1.0, 1.0);
    let mut transform = Vec::new();
    let mut seen = Seen::default();
    let place = format!("in 'component {}'", kind.name);
    for prop in kind.children() {
        if let Some(op) = transform_op(src, prop)? {
            transform.push(op);
            continue;
        }
        match (prop.name.as_str(), cylinder) {
            ("center", false) => center = args::vec3(src, prop)?,
            ("from", true) => from = Some(args::vec3(src, prop)?),
            ("to", true) => to = Some(args::vec3(src, prop)?),
            ("radius", _) => radius = args::number_where(src, prop, "greater than 0", |x| x > 0.0)?,
            ("strength", _) => strength = args::number_where(src, prop, "non-zero (negative carves)", |x| x != 0.0)?,
            _ => {
                let mut allowed = if cylinder { vec!["from", "to"] } else { vec!["center"] };
                allowed.extend(["radius", "strength"]);
                allowed.extend(TRANSFORMS);
                return Err(args::unknown(src, prop, "property", &place, &allowed));
            }
        }
        seen.once(src, prop, &format!("component {}", kind.name))?;
    }
    let shape = if cylinder {
        match (from, to) {
            (Some(from), Some(to)) => BlobComponentShape::Cylinder { from, to, radius },
            _ => {
                return Err(src.invalid(
                    kind.pos(),
                    "a cylinder component needs both ends, like `component cylinder { from [0 -1 0] to [0 1 0] }`",
                ));
            }
        }
    } else {
        BlobComponentShape::Sphere { center, radius }
    };
    Ok(BlobComponentDesc { shape, strength, transform })
}
