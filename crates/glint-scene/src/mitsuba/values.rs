//! Typed properties (`float`, `integer`, `boolean`, `string`, `rgb`, `spectrum`,
//! `point`, `vector`, `transform`) and the [`Plugin`] view of an element: its
//! properties and nested objects, each marked when read so that anything left unread
//! can be refused by name instead of silently changing the image.

use std::cell::Cell;

use glam::Vec3;

use super::transform::{self, Transform};
use super::tree::Elem;
use crate::error::SceneError;

/// Element names that are typed properties.
const VALUE_TAGS: [&str; 9] =
    ["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// Element names that are nested plugin objects (or references to one).
const OBJECT_TAGS: [&str; 13] = [
    "bsdf",
    "texture",
    "emitter",
    "shape",
    "sensor",
    "film",
    "rfilter",
    "sampler",
    "integrator",
    "medium",
    "phase",
    "volume",
    "ref",
];

/// A typed property value.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Value {
    Float(f32),
    Integer(i64),
    Boolean(bool),
    Str(String),
    Rgb(Vec3),
    /// A uniform spectrum (the only kind glint's RGB pipeline can take exactly).
    Spectrum(f32),
    Point(Vec3),
    Vector(Vec3),
    Transform(Transform),
}

impl Value {
    /// The element name Mitsuba uses for this kind, for messages.
    fn kind(&self) -> &'static str {
        match self {
            Value::Float(_) => "float",
            Value::Integer(_) => "integer",
            Value::Boolean(_) => "boolean",
            Value::Str(_) => "string",
            Value::Rgb(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Transform(_) => "transform",
        }
    }
}

/// Numbers separated by spaces and/or commas.
pub(super) fn numbers(text: &str) -> Result<Vec<f32>, String> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|w| !w.is_empty())
        .map(|w| w.parse::<f32>().map_err(|_| format!("'{w}' is not a number")))
        .collect()
}

/// `x=`, `y=`, `z=` attributes, `missing` for absent ones.
pub(super) fn vec3_attr(e: &Elem, missing: f32) -> Result<Vec3, SceneError> {
    let mut v = [missing; 3];
    for (slot, name) in v.iter_mut().zip(["x", "y", "z"]) {
        if let Some(text) = e.attr(name) {
            *slot = text.trim().parse().map_err(|_| e.attr_error(name, format!("'{text}' is not a number")))?;
        }
    }
    Ok(Vec3::from_array(v))
}

/// Reads one typed property element.
fn value(e: &Elem) -> Result<Value, SceneError> {
    let text = || e.required("value");
    let nums = |t: &str| numbers(t).map_err(|m| e.attr_error("value", m));
    let triple = |t: &str| -> Result<Vec3, SceneError> {
        match nums(t)?.as_slice() {
            [v] => Ok(Vec3::splat(*v)),
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            other => Err(e.attr_error("value", format!("<{}> takes 1 or 3 numbers, not {}", e.tag, other.len()))),
        }
    };
    Ok(match e.tag.as_str() {
        "float" => Value::Float(one_number(e, text()?)?),
        "integer" => {
            let t = text()?;
            Value::Integer(t.trim().parse().map_err(|_| e.attr_error("value", format!("'{t}' is not an integer")))?)
        }
        "boolean" => Value::Boolean(boolean(e, text()?)?),
        "string" => Value::Str(text()?.to_owned()),
        "rgb" => Value::Rgb(triple(text()?)?),
        "spectrum" => Value::Spectrum(spectrum(e)?),
        "point" | "vector" => {
            let v = match e.attr("value") {
                Some(t) => triple(t)?,
                None => vec3_attr(e, 0.0)?,
            };
            if e.tag == "point" { Value::Point(v) } else { Value::Vector(v) }
        }
        _ => Value::Transform(transform::parse(e)?),
    })
}

fn one_number(e: &Elem, text: &str) -> Result<f32, SceneError> {
    let t = text.trim();
    t.parse().map_err(|_| e.attr_error("value", format!("'{t}' is not a number")))
}

fn boolean(e: &Elem, text: &str) -> Result<bool, SceneError> {
    match text.trim().to_ascii_lowercase().as_str() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        other => Err(e.attr_error("value", format!("'{other}' is not a boolean; expected true or false"))),
    }
}

/// A uniform spectrum: one number. Wavelength lists and spectrum files would need
/// spectral rendering (or an upsampling glint does not do), so they are refused.
fn spectrum(e: &Elem) -> Result<f32, SceneError> {
    if e.attr("filename").is_some() {
        return Err(e.attr_error("filename", "spectrum files are not supported; give one uniform value or an <rgb>"));
    }
    let text = e.required("value")?;
    if text.contains(':') {
        return Err(e.attr_error(
            "value",
            "wavelength:value spectra are not supported (glint renders in RGB); give one uniform value or an <rgb>",
        ));
    }
    match numbers(text).map_err(|m| e.attr_error("value", m))?.as_slice() {
        [v] => Ok(*v),
        _ => Err(e.attr_error("value", "a <spectrum> must be a single uniform value")),
    }
}

/// One property: its name, value and element, and whether a reader used it.
struct Prop<'a> {
    name: String,
    value: Value,
    elem: &'a Elem,
    used: Cell<bool>,
}

/// A plugin element (`<bsdf type="diffuse">`, …) opened for reading.
pub(super) struct Plugin<'a> {
    pub elem: &'a Elem,
    /// The `type` attribute.
    pub ty: &'a str,
    props: Vec<Prop<'a>>,
    children: Vec<(&'a Elem, Cell<bool>)>,
}

impl<'a> Plugin<'a> {
    /// Sorts `elem`'s children into properties and nested objects.
    pub fn open(elem: &'a Elem) -> Result<Self, SceneError> {
        let ty = elem.required("type")?;
        let mut props: Vec<Prop<'a>> = Vec::new();
        let mut children = Vec::new();
        for c in &elem.children {
            if VALUE_TAGS.contains(&c.tag.as_str()) {
                let name = c.required("name")?;
                if props.iter().any(|p| p.name == name) {
                    return Err(c.attr_error("name", format!("parameter '{name}' is given twice")));
                }
                props.push(Prop { name: name.to_owned(), value: value(c)?, elem: c, used: Cell::new(false) });
            } else if OBJECT_TAGS.contains(&c.tag.as_str()) {
                children.push((c, Cell::new(false)));
            } else {
                return Err(c.error(format!("unknown element <{}> inside <{} type=\"{ty}\">", c.tag, elem.tag)));
            }
        }
        Ok(Self { elem, ty, props, children })
    }

    /// `bsdf 'diffuse'`: how messages name this plugin.
    pub fn label(&self) -> String {
        format!("{} '{}'", self.elem.tag, self.ty)
    }

    /// An error about the plugin as a whole.
    pub fn error(&self, message: impl std::fmt::Display) -> SceneError {
        self.elem.error(format!("{}: {message}", self.label()))
    }

    /// An error about parameter `name` (at its element when given).
    pub fn param_error(&self, name: &str, message: impl std::fmt::Display) -> SceneError {
        let e = self.props.iter().find(|p| p.name == name).map_or(self.elem, |p| p.elem);
        e.error(format!("{}: parameter '{name}': {message}", self.label()))
    }

    fn take(&self, name: &str) -> Option<&Prop<'a>> {
        let p = self.props.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Whether parameter `name` is given (as a value or a named nested object).
    pub fn has(&self, name: &str) -> bool {
        self.props.iter().any(|p| p.name == name) || self.children.iter().any(|(c, _)| c.attr("name") == Some(name))
    }

    fn wrong_kind(&self, p: &Prop, expected: &str) -> SceneError {
        p.elem.error(format!("{}: parameter '{}' must be {expected}, not a <{}>", self.label(), p.name, p.value.kind()))
    }

    /// The raw value of parameter `name`, for parameters of more than one kind.
    pub fn value(&self, name: &str) -> Option<&Value> {
        self.take(name).map(|p| &p.value)
    }

    /// A number (`float` or `integer`).
    pub fn float(&self, name: &str) -> Result<Option<f32>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match p.value {
            Value::Float(v) => Ok(Some(v)),
            Value::Integer(v) => Ok(Some(v as f32)),
            _ => Err(self.wrong_kind(p, "a <float>")),
        }
    }

    /// A number with a default.
    pub fn float_or(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    /// An `integer`.
    pub fn int(&self, name: &str) -> Result<Option<i64>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match p.value {
            Value::Integer(v) => Ok(Some(v)),
            _ => Err(self.wrong_kind(p, "an <integer>")),
        }
    }

    /// A `boolean` with a default.
    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = self.take(name) else { return Ok(default) };
        match p.value {
            Value::Boolean(v) => Ok(v),
            _ => Err(self.wrong_kind(p, "a <boolean>")),
        }
    }

    /// A `string`.
    pub fn string(&self, name: &str) -> Result<Option<&str>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match &p.value {
            Value::Str(s) => Ok(Some(s.as_str())),
            _ => Err(self.wrong_kind(p, "a <string>")),
        }
    }

    /// A colour: `rgb`, a uniform `spectrum` or a `float` (grey).
    pub fn color(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match p.value {
            Value::Rgb(v) => Ok(Some(v)),
            Value::Spectrum(v) | Value::Float(v) => Ok(Some(Vec3::splat(v))),
            Value::Integer(v) => Ok(Some(Vec3::splat(v as f32))),
            _ => Err(self.wrong_kind(p, "an <rgb>, <spectrum> or <float>")),
        }
    }

    /// A `point` (a `vector` is accepted too).
    pub fn point(&self, name: &str) -> Result<Option<Vec3>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match p.value {
            Value::Point(v) | Value::Vector(v) => Ok(Some(v)),
            _ => Err(self.wrong_kind(p, "a <point>")),
        }
    }

    /// A `transform`.
    pub fn transform(&self, name: &str) -> Result<Option<Transform>, SceneError> {
        let Some(p) = self.take(name) else { return Ok(None) };
        match &p.value {
            Value::Transform(t) => Ok(Some(t.clone())),
            _ => Err(self.wrong_kind(p, "a <transform>")),
        }
    }

    /// The nested object (or `<ref>`) whose `name` attribute is `name`.
    pub fn named_object(&self, name: &str) -> Option<&'a Elem> {
        let (c, used) = self.children.iter().find(|(c, _)| c.attr("name") == Some(name))?;
        used.set(true);
        Some(c)
    }

    /// Every nested `<tag>` object and every `<ref>` without a `name` (or named `tag`,
    /// as exporters write `<ref name="bsdf" id=…/>`), in document order; the caller
    /// resolves references and checks their kind.
    pub fn objects(&self, tag: &str) -> Vec<&'a Elem> {
        self.children
            .iter()
            .filter(|(c, used)| {
                let unnamed_or_tag = c.attr("name").is_none_or(|n| n == tag);
                let hit = !used.get() && (c.tag == tag || c.tag == "ref" && unnamed_or_tag);
                if hit {
                    used.set(true);
                }
                hit
            })
            .map(|(c, _)| *c)
            .collect()
    }

    /// Refuses every property or nested object no reader took, except the `harmless`
    /// parameters (ones that do not change the image, such as output file formats).
    pub fn finish(&self, harmless: &[&str]) -> Result<(), SceneError> {
        if let Some(p) = self.props.iter().find(|p| !p.used.get() && !harmless.contains(&p.name.as_str())) {
            return Err(p.elem.error(format!(
                "{}: parameter '{}' is not supported by glint (it would change the image)",
                self.label(),
                p.name
            )));
        }
        if let Some((c, _)) =
            self.children.iter().find(|(c, used)| !used.get() && !c.attr("name").is_some_and(|n| harmless.contains(&n)))
        {
            let what = match (c.attr("type"), c.attr("id")) {
                (Some(t), _) => format!("<{} type=\"{t}\">", c.tag),
                (None, Some(id)) => format!("<{} id=\"{id}\">", c.tag),
                _ => format!("<{}>", c.tag),
            };
            return Err(c.error(format!("{}: nested {what} is not supported here", self.label())));
        }
        Ok(())
    }
}
