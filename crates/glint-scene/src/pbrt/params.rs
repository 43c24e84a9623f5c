//! Parameter lists: `"float radius" [ 1 ]`, `"rgb L" [ 4 4 4 ]`, `"string filename" "a.ply"`.
//!
//! Each parameter is declared with a type and a name; the getters check the declared
//! type against what the directive expects and mark the parameter used, so that
//! [`Params::finish`] can warn about the ones glint did not read (pbrt refuses them;
//! glint renders on and says which were ignored).

use std::cell::Cell;
use std::rc::Rc;

use glam::{Vec2, Vec3};

use super::lexer::{Token, TokenKind};
use crate::error::SceneError;
use crate::source::{Pos, Source};

/// The values of one parameter, all of one kind.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

/// One declared parameter.
#[derive(Debug)]
pub(super) struct Param {
    /// The declared type, with pbrt-v3's aliases folded (`point` → `point3`, `color` → `rgb`).
    pub ty: String,
    pub name: String,
    pub values: Values,
    pub pos: Pos,
    used: Cell<bool>,
}

/// The canonical name of a declared type, or `None` when pbrt has no such type.
fn canonical_type(ty: &str) -> Option<&'static str> {
    Some(match ty {
        "integer" => "integer",
        "float" => "float",
        "point2" => "point2",
        "vector2" => "vector2",
        "point3" | "point" => "point3",
        "vector3" | "vector" => "vector3",
        "normal3" | "normal" => "normal3",
        "rgb" | "color" => "rgb",
        "spectrum" => "spectrum",
        "blackbody" => "blackbody",
        "bool" => "bool",
        "string" => "string",
        "texture" => "texture",
        _ => return None,
    })
}

/// A colour-like parameter as written: pbrt resolves spectra late, glint turns them
/// into RGB where they are used ([`super::spectra`]).
#[derive(Clone, Debug, PartialEq)]
pub(super) enum SpectrumValue {
    Rgb(Vec3),
    /// A named spectrum (`"metal-Cu-eta"`, `"stdillum-D65"`) or a spectrum file.
    Named(String),
    /// `(wavelength, value)` pairs.
    Samples(Vec<(f32, f32)>),
    /// A black body at this temperature in kelvin, times a scale (pbrt-v3's second value).
    Blackbody(f32, f32),
    /// A constant spectrum (a plain `float` where a spectrum is allowed).
    Constant(f32),
}

/// The parameters of one directive, with the file they were written in.
pub(super) struct Params {
    pub list: Vec<Param>,
    pub src: Rc<Source>,
    /// The directive's own position (for errors about a missing parameter).
    pub pos: Pos,
    /// What the directive is, for messages (`Shape "sphere"`).
    pub what: String,
}

impl Params {
    /// Reads `"type name" value(s)` pairs from `tokens[*at..]` up to the next directive.
    pub fn parse(
        tokens: &[Token],
        at: &mut usize,
        src: &Rc<Source>,
        pos: Pos,
        what: String,
    ) -> Result<Self, SceneError> {
        let mut list: Vec<Param> = Vec::new();
        while let Some(Token { kind: TokenKind::Str(decl), pos: decl_pos }) = tokens.get(*at) {
            *at += 1;
            let (ty, name) = declaration(decl, src, *decl_pos)?;
            let values = values(tokens, at, src, *decl_pos, &name)?;
            check_kind(ty, &name, &values, src, *decl_pos)?;
            let values = if ty == "bool" { as_bools(values) } else { values };
            if list.iter().any(|p| p.name == name) {
                return Err(src.invalid(*decl_pos, format!("{what}: parameter '{name}' is given twice")));
            }
            list.push(Param { ty: ty.to_owned(), name, values, pos: *decl_pos, used: Cell::new(false) });
        }
        Ok(Self { list, src: Rc::clone(src), pos, what })
    }

    /// An error at the directive.
    pub fn error(&self, message: impl AsRef<str>) -> SceneError {
        self.src.invalid(self.pos, format!("{}: {}", self.what, message.as_ref()))
    }

    /// An error at parameter `p`.
    pub fn param_error(&self, p: &Param, message: impl AsRef<str>) -> SceneError {
        self.src.invalid(p.pos, format!("{}: parameter '{}' {}", self.what, p.name, message.as_ref()))
    }

    /// `file:line:col` of the directive, the prefix of warnings about it.
    pub fn origin(&self) -> String {
        self.src.origin(self.pos)
    }

    /// A warning about the directive.
    pub fn warning(&self, message: impl AsRef<str>) -> String {
        format!("{}: {}: {}", self.origin(), self.what, message.as_ref())
    }

    /// The parameter called `name`, marked used, whatever its type.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let p = self.list.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Whether parameter `name` is present (without marking it used).
    pub fn has(&self, name: &str) -> bool {
        self.list.iter().any(|p| p.name == name)
    }

    /// Parameter `name`, which must be of one of the types `types`.
    fn typed(&self, name: &str, types: &[&str]) -> Result<Option<&Param>, SceneError> {
        let Some(p) = self.get(name) else { return Ok(None) };
        if !types.contains(&p.ty.as_str()) {
            return Err(self.param_error(p, format!("is declared '{}'; expected {}", p.ty, types.join(" or "))));
        }
        Ok(Some(p))
    }

    /// All the numbers of parameter `name` (of one of `types`).
    pub fn numbers(&self, name: &str, types: &[&str]) -> Result<Option<(&Param, &[f64])>, SceneError> {
        match self.typed(name, types)? {
            Some(p @ Param { values: Values::Numbers(v), .. }) => Ok(Some((p, v))),
            Some(p) => Err(self.param_error(p, "needs numbers")),
            None => Ok(None),
        }
    }

    /// A single float.
    pub fn float(&self, name: &str) -> Result<Option<f32>, SceneError> {
        self.one_number(name, &["float"]).map(|v| v.map(|x| x as f32))
    }

    /// A single float, or `default`.
    pub fn float_or(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        Ok(self.float(name)?.unwrap_or(default))
    }

    /// A single integer.
    pub fn int(&self, name: &str) -> Result<Option<i64>, SceneError> {
        let Some(v) = self.one_number(name, &["integer"])? else { return Ok(None) };
        if v.fract() != 0.0 || v.abs() > 2f64.powi(53) {
            let p = self.get(name).expect("just read");
            return Err(self.param_error(p, format!("{v} is not an integer")));
        }
        Ok(Some(v as i64))
    }

    fn one_number(&self, name: &str, types: &[&str]) -> Result<Option<f64>, SceneError> {
        match self.numbers(name, types)? {
            Some((_, [v])) => Ok(Some(*v)),
            Some((p, v)) => Err(self.param_error(p, format!("takes one value, not {}", v.len()))),
            None => Ok(None),
        }
    }

    /// A list of integers (mesh indices).
    pub fn ints(&self, name: &str) -> Result<Option<Vec<i64>>, SceneError> {
        let Some((p, v)) = self.numbers(name, &["integer"])? else { return Ok(None) };
        if let Some(bad) = v.iter().find(|x| x.fract() != 0.0) {
            return Err(self.param_error(p, format!("holds {bad}, which is not an integer")));
        }
        Ok(Some(v.iter().map(|&x| x as i64).collect()))
    }

    /// A list of 3-vectors (`point3`, `vector3` or `normal3`, as `types` allows).
    pub fn vec3s(&self, name: &str, types: &[&str]) -> Result<Option<Vec<Vec3>>, SceneError> {
        let Some((p, v)) = self.numbers(name, types)? else { return Ok(None) };
        if v.len() % 3 != 0 {
            return Err(self.param_error(p, format!("needs a multiple of 3 numbers, not {}", v.len())));
        }
        Ok(Some(v.chunks_exact(3).map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32)).collect()))
    }

    /// One 3-vector.
    pub fn vec3(&self, name: &str, types: &[&str]) -> Result<Option<Vec3>, SceneError> {
        match self.vec3s(name, types)?.as_deref() {
            None => Ok(None),
            Some([v]) => Ok(Some(*v)),
            Some(_) => Err(self.param_error(self.get(name).expect("read"), "takes one vector of 3 numbers")),
        }
    }

    /// A list of 2-vectors (`point2`; pbrt-v3's `float uv` is accepted too).
    pub fn vec2s(&self, name: &str) -> Result<Option<Vec<Vec2>>, SceneError> {
        let Some((p, v)) = self.numbers(name, &["point2", "vector2", "float"])? else { return Ok(None) };
        if v.len() % 2 != 0 {
            return Err(self.param_error(p, format!("needs a multiple of 2 numbers, not {}", v.len())));
        }
        Ok(Some(v.chunks_exact(2).map(|c| Vec2::new(c[0] as f32, c[1] as f32)).collect()))
    }

    /// A single string.
    pub fn string(&self, name: &str) -> Result<Option<&str>, SceneError> {
        self.string_of(name, &["string"])
    }

    /// A single string of a type in `types` (`texture`, `spectrum`).
    fn string_of(&self, name: &str, types: &[&str]) -> Result<Option<&str>, SceneError> {
        match self.typed(name, types)? {
            Some(Param { values: Values::Strings(v), .. }) if v.len() == 1 => Ok(Some(v[0].as_str())),
            Some(p) => Err(self.param_error(p, "takes one string")),
            None => Ok(None),
        }
    }

    /// A list of strings.
    pub fn strings(&self, name: &str) -> Result<Option<&[String]>, SceneError> {
        match self.typed(name, &["string"])? {
            Some(Param { values: Values::Strings(v), .. }) => Ok(Some(v)),
            Some(p) => Err(self.param_error(p, "takes strings")),
            None => Ok(None),
        }
    }

    /// A single bool (`true`, `"true"`, …).
    pub fn bool_or(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        match self.typed(name, &["bool"])? {
            Some(Param { values: Values::Bools(v), .. }) if v.len() == 1 => Ok(v[0]),
            Some(p) => Err(self.param_error(p, "takes one of true or false")),
            None => Ok(default),
        }
    }

    /// The name of the texture a `texture` parameter refers to.
    pub fn texture(&self, name: &str) -> Option<&str> {
        let p = self.list.iter().find(|p| p.name == name && p.ty == "texture")?;
        p.used.set(true);
        match &p.values {
            Values::Strings(v) if v.len() == 1 => Some(v[0].as_str()),
            _ => None,
        }
    }

    /// A colour-like parameter (`rgb`, `spectrum`, `blackbody` or a plain `float`).
    pub fn spectrum(&self, name: &str) -> Result<Option<SpectrumValue>, SceneError> {
        let Some(p) = self.list.iter().find(|p| p.name == name && p.ty != "texture") else { return Ok(None) };
        p.used.set(true);
        let nums = |n: usize| -> Result<&[f64], SceneError> {
            match &p.values {
                Values::Numbers(v) if v.len() == n || n == 0 => Ok(v),
                Values::Numbers(v) => Err(self.param_error(p, format!("takes {n} numbers, not {}", v.len()))),
                _ => Err(self.param_error(p, "needs numbers")),
            }
        };
        Ok(Some(match p.ty.as_str() {
            "rgb" => {
                let v = nums(3)?;
                SpectrumValue::Rgb(Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
            }
            "float" => SpectrumValue::Constant(nums(1)?[0] as f32),
            "blackbody" => match nums(0)? {
                [t] => SpectrumValue::Blackbody(*t as f32, 1.0),
                // pbrt-v3 wrote a scale after the temperature.
                [t, scale] => SpectrumValue::Blackbody(*t as f32, *scale as f32),
                v => return Err(self.param_error(p, format!("takes a temperature, not {} numbers", v.len()))),
            },
            "spectrum" => match &p.values {
                Values::Strings(v) if v.len() == 1 => SpectrumValue::Named(v[0].clone()),
                Values::Numbers(v) if v.len() >= 2 && v.len() % 2 == 0 => {
                    SpectrumValue::Samples(v.chunks_exact(2).map(|c| (c[0] as f32, c[1] as f32)).collect())
                }
                _ => return Err(self.param_error(p, "needs a spectrum name or (wavelength, value) pairs")),
            },
            other => {
                return Err(self.param_error(p, format!("is declared '{other}'; expected rgb, spectrum or blackbody")));
            }
        }))
    }

    /// Warnings for the parameters no getter read.
    pub fn finish(&self, warnings: &mut Vec<String>) {
        for p in self.list.iter().filter(|p| !p.used.get()) {
            warnings.push(format!(
                "{}: {}: parameter \"{} {}\" is not used by glint and was ignored",
                self.src.origin(p.pos),
                self.what,
                p.ty,
                p.name
            ));
        }
    }
}

/// Splits `"type name"` into its canonical type and the name.
fn declaration(decl: &str, src: &Source, pos: Pos) -> Result<(&'static str, String), SceneError> {
    let mut words = decl.split_whitespace();
    let (Some(ty), Some(name), None) = (words.next(), words.next(), words.next()) else {
        return Err(src.invalid(pos, format!("\"{decl}\" is not a parameter declaration like \"float radius\"")));
    };
    let canonical = canonical_type(ty).ok_or_else(|| {
        src.invalid(
            pos,
            format!(
                "unknown parameter type '{ty}'; pbrt's are integer, float, point2, vector2, point3, vector3, \
                 normal3, rgb, spectrum, blackbody, bool, string and texture"
            ),
        )
    })?;
    Ok((canonical, name.to_owned()))
}

/// The value(s) after a declaration: one bare value or a bracketed list.
fn values(tokens: &[Token], at: &mut usize, src: &Source, pos: Pos, name: &str) -> Result<Values, SceneError> {
    let single = |t: &Token| match &t.kind {
        TokenKind::Number(n) => Some(Values::Numbers(vec![*n])),
        TokenKind::Str(s) => Some(string_value(s)),
        TokenKind::Word(w) if w == "true" || w == "false" => Some(Values::Bools(vec![w == "true"])),
        _ => None,
    };
    let Some(first) = tokens.get(*at) else {
        return Err(src.invalid(pos, format!("parameter '{name}' has no value")));
    };
    if first.kind != TokenKind::Open {
        *at += 1;
        return single(first).ok_or_else(|| {
            src.invalid(first.pos, format!("parameter '{name}' needs a value, found {}", first.describe()))
        });
    }
    *at += 1;
    let mut items = Vec::new();
    loop {
        let Some(t) = tokens.get(*at) else {
            return Err(src.invalid(first.pos, format!("the '[' of parameter '{name}' is never closed")));
        };
        *at += 1;
        if t.kind == TokenKind::Close {
            break;
        }
        items.push((
            single(t)
                .ok_or_else(|| src.invalid(t.pos, format!("parameter '{name}': {} cannot be a value", t.describe())))?,
            t.pos,
        ));
    }
    merge(items, src, first.pos, name)
}

/// A quoted value: `"true"`/`"false"` may be bools (the declared type decides later).
fn string_value(s: &str) -> Values {
    Values::Strings(vec![s.to_owned()])
}

/// One list from single values, which must all be of one kind.
fn merge(items: Vec<(Values, Pos)>, src: &Source, pos: Pos, name: &str) -> Result<Values, SceneError> {
    let mut out: Option<Values> = None;
    for (v, at) in items {
        out = Some(match (out, v) {
            (None, v) => v,
            (Some(Values::Numbers(mut a)), Values::Numbers(b)) => {
                a.extend(b);
                Values::Numbers(a)
            }
            (Some(Values::Strings(mut a)), Values::Strings(b)) => {
                a.extend(b);
                Values::Strings(a)
            }
            (Some(Values::Bools(mut a)), Values::Bools(b)) => {
                a.extend(b);
                Values::Bools(a)
            }
            _ => return Err(src.invalid(at, format!("parameter '{name}' mixes numbers, strings and bools"))),
        });
    }
    out.ok_or_else(|| src.invalid(pos, format!("parameter '{name}' has an empty list of values")))
}

/// Checks that the values suit the declared type (numbers for numeric types, strings
/// for strings and textures, bools for bools); quoted `"true"` is a bool too.
fn check_kind(ty: &str, name: &str, values: &Values, src: &Source, pos: Pos) -> Result<(), SceneError> {
    let ok = match (ty, values) {
        ("string" | "texture", Values::Strings(_)) => true,
        ("bool", Values::Bools(_)) => true,
        ("bool", Values::Strings(v)) => v.iter().all(|s| s == "true" || s == "false"),
        ("spectrum", Values::Strings(_) | Values::Numbers(_)) => true,
        ("string" | "texture" | "bool" | "spectrum", _) => false,
        (_, Values::Numbers(_)) => true,
        _ => false,
    };
    if !ok {
        return Err(
            src.invalid(pos, format!("parameter '{name}' is declared '{ty}' but its values are not of that type"))
        );
    }
    Ok(())
}

/// Quoted `"true"`/`"false"` as bools (pbrt accepts both spellings).
fn as_bools(values: Values) -> Values {
    match values {
        Values::Strings(v) => Values::Bools(v.iter().map(|s| s == "true").collect()),
        other => other,
    }
}
