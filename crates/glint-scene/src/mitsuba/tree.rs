//! The XML document as an owned element tree with every position kept, after the three
//! textual steps Mitsuba applies before it reads any plugin: `<include>` files are
//! spliced in, `$name` is replaced by its `<default>`, and scenes older than version
//! 2.0 get their camelCase parameter names upgraded (`toWorld` → `to_world`).

use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

use roxmltree::{Document, Node};

use crate::error::{SceneError, SceneErrorKind};
use crate::source::{Pos, Source};

/// How deep `<include>` may nest: deeper is almost surely a file including itself.
const MAX_INCLUDE_DEPTH: usize = 16;

/// One attribute with the position of its value, so errors point at the value.
#[derive(Clone, Debug)]
pub(super) struct Attr {
    pub name: String,
    pub value: String,
    pub pos: Pos,
}

/// One XML element, owned so that elements from included files can sit in one tree.
#[derive(Clone)]
pub(super) struct Elem {
    pub tag: String,
    pub attrs: Vec<Attr>,
    pub children: Vec<Elem>,
    pub pos: Pos,
    /// The file the element was written in (errors name it, paths start from its folder).
    pub file: Rc<Source>,
}

impl Elem {
    /// The value of attribute `name`, if present.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs.iter().find(|a| a.name == name).map(|a| a.value.as_str())
    }

    /// Where attribute `name`'s value starts (the element itself when absent).
    pub fn attr_pos(&self, name: &str) -> Pos {
        self.attrs.iter().find(|a| a.name == name).map_or(self.pos, |a| a.pos)
    }

    /// An error about this element.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        self.file.invalid(self.pos, message)
    }

    /// An error about attribute `name` of this element.
    pub fn attr_error(&self, name: &str, message: impl Into<String>) -> SceneError {
        self.file.invalid(self.attr_pos(name), message)
    }

    /// The attribute `name`, which must be present.
    pub fn required(&self, name: &str) -> Result<&str, SceneError> {
        self.attr(name).ok_or_else(|| self.error(format!("<{}> needs a '{name}' attribute", self.tag)))
    }

    /// A path written in this element, resolved against its file's folder.
    pub fn resolve(&self, file: &str) -> std::path::PathBuf {
        self.file.dir.join(file)
    }
}

/// Parses `text` (from `src`) into the root `<scene>` element with includes spliced in,
/// defaults substituted and old parameter names upgraded.
pub(super) fn parse(text: &str, src: Rc<Source>) -> Result<Elem, SceneError> {
    let root = raw_tree(text, &src)?;
    check_root(&root)?;
    let upgrade = version_below_2(&root)?;
    let mut defaults = HashMap::new();
    collect_defaults(&root, &mut defaults)?;
    let mut root = expand(root, &defaults, 0)?;
    if upgrade {
        upgrade_names(&mut root);
    }
    Ok(root)
}

/// The document as an [`Elem`] tree, attributes untouched.
fn raw_tree(text: &str, src: &Rc<Source>) -> Result<Elem, SceneError> {
    let doc = Document::parse(text).map_err(|e| {
        let p = e.pos();
        let message = e.to_string();
        let message = message.strip_suffix(&format!(" at {}:{}", p.row, p.col)).unwrap_or(&message);
        src.error(SceneErrorKind::Syntax, Pos { line: p.row, column: p.col }, format!("malformed XML: {message}"))
    })?;
    Ok(convert(&doc, doc.root_element(), src))
}

fn convert(doc: &Document, node: Node, src: &Rc<Source>) -> Elem {
    let at = |offset: usize| {
        let p = doc.text_pos_at(offset);
        Pos { line: p.row, column: p.col }
    };
    Elem {
        tag: node.tag_name().name().to_owned(),
        attrs: node
            .attributes()
            .map(|a| Attr { name: a.name().to_owned(), value: a.value().to_owned(), pos: at(a.range_value().start) })
            .collect(),
        children: node.children().filter(Node::is_element).map(|c| convert(doc, c, src)).collect(),
        pos: at(node.range().start),
        file: Rc::clone(src),
    }
}

fn check_root(root: &Elem) -> Result<(), SceneError> {
    if root.tag != "scene" {
        return Err(root.error(format!("the document element is <{}>; a Mitsuba scene starts with <scene>", root.tag)));
    }
    if root.attr("version").is_none() {
        return Err(root.error("<scene> needs a 'version' attribute (e.g. version=\"3.0.0\")"));
    }
    Ok(())
}

/// Whether the file predates Mitsuba 2, whose parameter names were camelCase.
fn version_below_2(root: &Elem) -> Result<bool, SceneError> {
    let version = root.required("version")?;
    let major = version.split('.').next().and_then(|m| m.trim().parse::<u32>().ok());
    match major {
        Some(m) => Ok(m < 2),
        None => Err(root.attr_error("version", format!("version '{version}' is not of the form MAJOR.MINOR.PATCH"))),
    }
}

/// Every `<default name= value=>` directly inside `root` (the first of a name wins, as
/// a value given on Mitsuba's command line would).
fn collect_defaults(root: &Elem, defaults: &mut HashMap<String, String>) -> Result<(), SceneError> {
    for e in root.children.iter().filter(|e| e.tag == "default") {
        let name = e.required("name")?;
        let value = e.required("value")?;
        defaults.entry(name.to_owned()).or_insert_with(|| value.to_owned());
    }
    Ok(())
}

/// Substitutes defaults into every attribute and splices `<include>`d scenes in.
fn expand(mut elem: Elem, defaults: &HashMap<String, String>, depth: usize) -> Result<Elem, SceneError> {
    for a in &mut elem.attrs {
        a.value = substitute(&a.value, defaults).map_err(|name| {
            elem.file.invalid(a.pos, format!("'${name}' has no <default name=\"{name}\" value=\"…\"/>"))
        })?;
    }
    let mut children = Vec::with_capacity(elem.children.len());
    for child in std::mem::take(&mut elem.children) {
        let child = expand(child, defaults, depth)?;
        match child.tag.as_str() {
            "default" => {}
            "include" => children.extend(include(&child, defaults, depth)?),
            _ => children.push(child),
        }
    }
    elem.children = children;
    Ok(elem)
}

/// Replaces each `$name` by its default; `Err(name)` for the first one without.
fn substitute(value: &str, defaults: &HashMap<String, String>) -> Result<String, String> {
    if !value.contains('$') {
        return Ok(value.to_owned());
    }
    let mut out = String::with_capacity(value.len());
    let mut rest = value;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        let after = &rest[at + 1..];
        let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
        let name = &after[..len];
        if name.is_empty() {
            out.push('$');
        } else {
            out.push_str(defaults.get(name).ok_or_else(|| name.to_owned())?);
        }
        rest = &after[len..];
    }
    out.push_str(rest);
    Ok(out)
}

/// The children of the `<scene>` in the file an `<include filename=…>` names.
fn include(elem: &Elem, defaults: &HashMap<String, String>, depth: usize) -> Result<Vec<Elem>, SceneError> {
    let file = elem.required("filename")?;
    if depth >= MAX_INCLUDE_DEPTH {
        return Err(
            elem.error(format!("includes nest deeper than {MAX_INCLUDE_DEPTH} files; does '{file}' include itself?"))
        );
    }
    let path = elem.resolve(file);
    let text = crate::input::read_text(&path, crate::input::InputKind::Scene).map_err(|e| {
        elem.file.error(
            SceneErrorKind::Io,
            elem.attr_pos("filename"),
            format!("cannot read included file '{}': {}", path.display(), e.problem),
        )
    })?;
    let src = Rc::new(source_for(&path));
    let root = raw_tree(&text, &src)?;
    check_root(&root)?;
    let root = expand(root, defaults, depth + 1)?;
    Ok(root.children)
}

/// The [`Source`] of a scene file: its name for messages, its folder for paths.
pub(super) fn source_for(path: &Path) -> Source {
    Source { name: path.display().to_string(), dir: path.parent().map(Path::to_path_buf).unwrap_or_default() }
}

/// Mitsuba 0.x names (`toWorld`, `sampleCount`, `intIOR`) in Mitsuba 3 spelling.
fn upgrade_names(elem: &mut Elem) {
    for a in elem.attrs.iter_mut().filter(|a| a.name == "name") {
        a.value = snake_case(&a.value);
    }
    elem.children.iter_mut().for_each(upgrade_names);
}

/// `camelCase` → `camel_case`: an underscore before each capital that follows a small
/// letter, then everything in lower case (Mitsuba's own upgrade rule).
fn snake_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let mut prev_lower = false;
    for c in name.chars() {
        if c.is_ascii_uppercase() && prev_lower {
            out.push('_');
        }
        prev_lower = c.is_ascii_lowercase();
        out.push(c.to_ascii_lowercase());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn old_names_upgrade_to_snake_case() {
        assert_eq!(snake_case("toWorld"), "to_world");
        assert_eq!(snake_case("intIOR"), "int_ior");
        assert_eq!(snake_case("sampleCount"), "sample_count");
        assert_eq!(snake_case("fov"), "fov");
    }

    #[test]
    fn substitution_replaces_every_name() {
        let d: HashMap<String, String> = [("a".to_owned(), "1".to_owned()), ("b_2".to_owned(), "x".to_owned())].into();
        assert_eq!(substitute("$a, $b_2 $a", &d).unwrap(), "1, x 1");
        assert_eq!(substitute("$c", &d), Err("c".to_owned()));
        assert_eq!(substitute("no dollars", &d).unwrap(), "no dollars");
    }
}
