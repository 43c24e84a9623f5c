//! A scene written as plain data (maps, lists, numbers, strings) with the native format's
//! names, as Python's `glint.load_dict` receives it (see `docs/python.md`).
//!
//! The data is written out as `.glint` text, one node per line, and read by the native
//! parser, so both ways of writing a scene mean exactly the same thing and are checked by
//! the same code. Each line remembers the key path it came from, so an error points at
//! the key (`objects[2].sphere.materail: unknown property …`), not at generated text.

use std::path::Path;

use glint_core::desc::SceneDesc;

use crate::error::{SceneError, SceneErrorKind};

/// A value of the plain data: what JSON or a Python literal can hold.
#[derive(Clone, Debug, PartialEq)]
pub enum Data {
    /// `None`: a node with no values and no block (`"cube": None`).
    Null,
    /// `true` / `false`.
    Bool(bool),
    /// A number; whole numbers are written without a fraction.
    Number(f64),
    /// A string (a name, a path, a choice such as `"sobol"`).
    Str(String),
    /// A list: a vector when it holds only numbers, else values followed by blocks.
    List(Vec<Data>),
    /// A map in its written order: a block of nodes, key = node name.
    Map(Vec<(String, Data)>),
}

/// Top-level keys, in the order they are written out: everything a later key may
/// refer to comes first.
pub const TOP_LEVEL_KEYS: [&str; 9] =
    ["include", "settings", "camera", "textures", "materials", "meshes", "lights", "defines", "objects"];

/// Nodes whose kind is the next node (`integrator path { … }`), written in data as a
/// one-key map `{"path": {…}}` or a string `"whitted"`.
const KIND_WORDS: [&str; 3] = ["integrator", "bsdf", "component"];

/// Native text made from data, and the key path that each of its lines came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NativeText {
    /// The `.glint` text.
    pub text: String,
    /// `line_paths[n]` is the key path of line `n + 1`.
    pub line_paths: Vec<String>,
}

/// Reads a scene from data; `base_dir` is where relative paths (textures, meshes,
/// includes) are found.
///
/// # Errors
///
/// A [`SceneError`] whose `file` is the key path of the mistake (`materials.red.difuse`)
/// and whose line is 0; errors inside an included file keep that file's location.
pub fn parse_data(data: &Data, base_dir: &Path) -> Result<SceneDesc, SceneError> {
    const NAME: &str = "<data>";
    let native = to_native(data)?;
    super::parse_scene(&native.text, NAME, base_dir).map_err(|e| native.relocate(e, NAME))
}

/// Writes data as `.glint` text.
///
/// # Errors
///
/// A [`SceneError`] at the key path of data the format cannot hold (an unknown
/// top-level key, a key that is not a node name, a string with a line break, …).
pub fn to_native(data: &Data) -> Result<NativeText, SceneError> {
    let Data::Map(entries) = data else {
        return Err(invalid("", format!("a scene is a map of {}", TOP_LEVEL_KEYS.join(", "))));
    };
    if let Some((key, _)) = entries.iter().find(|(k, _)| !TOP_LEVEL_KEYS.contains(&k.as_str())) {
        let expected = TOP_LEVEL_KEYS.join(", ");
        return Err(invalid(key, format!("unknown key '{key}' of a scene; expected one of: {expected}")));
    }
    let mut writer = Writer::default();
    for key in TOP_LEVEL_KEYS {
        for (_, value) in entries.iter().filter(|(k, _)| k == key) {
            writer.top_level(key, value)?;
        }
    }
    Ok(NativeText { text: writer.text, line_paths: writer.line_paths })
}

impl NativeText {
    /// `error` as a mistake in the data: located at the key path of its line.
    pub fn relocate(&self, error: SceneError, name: &str) -> SceneError {
        let path =
            (error.file == name && error.line > 0).then(|| self.line_paths.get(error.line as usize - 1)).flatten();
        match path {
            Some(path) => SceneError::new(error.kind, path.clone(), 0, 0, error.message),
            None => error,
        }
    }
}

/// A data error at `path`, in the form every scene error has.
fn invalid(path: &str, message: impl Into<String>) -> SceneError {
    let file = if path.is_empty() { "<data>" } else { path };
    SceneError::new(SceneErrorKind::Invalid, file, 0, 0, message)
}

/// Text being written, one node per line.
#[derive(Default)]
struct Writer {
    text: String,
    line_paths: Vec<String>,
}

impl Writer {
    fn line(&mut self, depth: usize, text: &str, path: &str) {
        self.text.push_str(&"  ".repeat(depth));
        self.text.push_str(text);
        self.text.push('\n');
        self.line_paths.push(path.to_owned());
    }

    /// One top-level key and everything under it.
    fn top_level(&mut self, key: &str, value: &Data) -> Result<(), SceneError> {
        match key {
            "include" => self.includes(value),
            "settings" | "camera" => self.node(key, &[], value, key, 0),
            "textures" => self.named(key, value, |w, name, value, path| {
                w.line(0, &format!("texture {}", quote(name, path)?), path);
                w.kind(value, path, 0)
            }),
            "materials" | "meshes" | "defines" => {
                let node = match key {
                    "materials" => "material",
                    "meshes" => "mesh",
                    _ => "define",
                };
                self.named(key, value, |w, name, value, path| w.node(node, &[quote(name, path)?], value, path, 0))
            }
            "lights" => self.each(key, value, |w, item, path| {
                w.line(0, "light", path);
                w.kind(item, path, 0)
            }),
            _ => self.children(value, key, 0),
        }
    }

    /// `include "file"` for a string or each string of a list.
    fn includes(&mut self, value: &Data) -> Result<(), SceneError> {
        self.each("include", value, |w, item, path| match item {
            Data::Str(file) => {
                let line = format!("include {}", quote(file, path)?);
                w.line(0, &line, path);
                Ok(())
            }
            _ => Err(invalid(path, "expected the path of a .glint file")),
        })
    }

    /// Calls `write` for each item of a list (or for a single item).
    fn each(
        &mut self,
        key: &str,
        value: &Data,
        mut write: impl FnMut(&mut Self, &Data, &str) -> Result<(), SceneError>,
    ) -> Result<(), SceneError> {
        match value {
            Data::List(items) => {
                items.iter().enumerate().try_for_each(|(i, item)| write(self, item, &format!("{key}[{i}]")))
            }
            item => write(self, item, key),
        }
    }

    /// Calls `write` for each entry of a map of names (materials, textures, …).
    fn named(
        &mut self,
        key: &str,
        value: &Data,
        mut write: impl FnMut(&mut Self, &str, &Data, &str) -> Result<(), SceneError>,
    ) -> Result<(), SceneError> {
        let Data::Map(entries) = value else {
            return Err(invalid(key, format!("'{key}' is a map from names to their properties")));
        };
        entries.iter().try_for_each(|(name, value)| write(self, name, value, &format!("{key}.{name}")))
    }

    /// A kind and its properties after a kind word: `"whitted"` or `{"path": {…}}`.
    fn kind(&mut self, value: &Data, path: &str, depth: usize) -> Result<(), SceneError> {
        match value {
            Data::Str(kind) => self.node(kind, &[], &Data::Null, &format!("{path}.{kind}"), depth),
            Data::Map(entries) if entries.len() == 1 => {
                let (kind, properties) = &entries[0];
                self.node(kind, &[], properties, &format!("{path}.{kind}"), depth)
            }
            _ => Err(invalid(
                path,
                "expected a kind: a string such as \"point\" or a one-key map such as {\"point\": {…}}",
            )),
        }
    }

    /// The nodes of a block: a map, or a list of maps when a name repeats.
    fn children(&mut self, value: &Data, path: &str, depth: usize) -> Result<(), SceneError> {
        match value {
            Data::Map(entries) => entries.iter().try_for_each(|(k, v)| self.child(k, v, &format!("{path}.{k}"), depth)),
            Data::List(items) => items.iter().enumerate().try_for_each(|(i, item)| {
                let Data::Map(entries) = item else {
                    return Err(invalid(&format!("{path}[{i}]"), "expected a map of nodes"));
                };
                entries.iter().try_for_each(|(k, v)| self.child(k, v, &format!("{path}[{i}].{k}"), depth))
            }),
            Data::Null => Ok(()),
            _ => Err(invalid(path, "expected a map of nodes or a list of such maps")),
        }
    }

    /// One node of a block; a kind word takes its kind (or a list of kinds) as its value.
    fn child(&mut self, key: &str, value: &Data, path: &str, depth: usize) -> Result<(), SceneError> {
        if !KIND_WORDS.contains(&key) {
            return self.node(key, &[], value, path, depth);
        }
        self.each(path, value, |w, item, path| {
            w.line(depth, key, path);
            w.kind(item, path, depth)
        })
    }

    /// `name values… { block }` from a node's data, after the `leading` values.
    fn node(
        &mut self,
        name: &str,
        leading: &[String],
        value: &Data,
        path: &str,
        depth: usize,
    ) -> Result<(), SceneError> {
        check_name(name, path)?;
        let mut head = std::iter::once(name.to_owned()).chain(leading.iter().cloned()).collect::<Vec<_>>();
        // The block's maps and their paths: a list's items keep their index.
        let mut parts: Vec<(&Data, String)> = Vec::new();
        match value {
            Data::Map(_) => parts.push((value, path.to_owned())),
            Data::List(items) => {
                let first_block = items.iter().position(|d| matches!(d, Data::Map(_))).unwrap_or(items.len());
                head.extend(values(&items[..first_block], path)?);
                for (i, part) in items.iter().enumerate().skip(first_block) {
                    if !matches!(part, Data::Map(_)) {
                        return Err(invalid(path, "a value cannot follow a block: give the values first, then maps"));
                    }
                    parts.push((part, format!("{path}[{i}]")));
                }
            }
            Data::Null => {}
            scalar => head.push(value_text(scalar, path)?),
        }
        if parts.is_empty() {
            self.line(depth, &head.join(" "), path);
            return Ok(());
        }
        self.line(depth, &format!("{} {{", head.join(" ")), path);
        for (part, part_path) in parts {
            self.children(part, &part_path, depth + 1)?;
        }
        self.line(depth, "}", path);
        Ok(())
    }
}

/// The values of a list written before its block: numbers alone make one vector,
/// otherwise each item is a value of its own (a list of numbers inside is a vector).
fn values(items: &[Data], path: &str) -> Result<Vec<String>, SceneError> {
    if items.is_empty() {
        return Ok(Vec::new());
    }
    if items.iter().all(|d| matches!(d, Data::Number(_))) {
        return Ok(vec![value_text(&Data::List(items.to_vec()), path)?]);
    }
    items.iter().map(|item| value_text(item, path)).collect()
}

/// One value as `.glint` text.
fn value_text(value: &Data, path: &str) -> Result<String, SceneError> {
    Ok(match value {
        Data::Bool(b) => b.to_string(),
        Data::Number(x) => number(*x),
        Data::Str(s) => quote(s, path)?,
        Data::List(items) => {
            let numbers: Option<Vec<String>> =
                items.iter().map(|d| if let Data::Number(x) = d { Some(number(*x)) } else { None }).collect();
            let numbers = numbers.ok_or_else(|| invalid(path, "a vector holds numbers only"))?;
            format!("[{}]", numbers.join(" "))
        }
        Data::Null | Data::Map(_) => {
            return Err(invalid(path, "expected a number, string, boolean or list of numbers"));
        }
    })
}

/// A number as the lexer reads it back exactly (non-finite ones stay refused there).
fn number(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 { format!("{}", x as i64) } else { format!("{x:?}") }
}

/// A string literal; the format's strings are single-line with `\"` and `\\` escapes.
fn quote(text: &str, path: &str) -> Result<String, SceneError> {
    if text.chars().any(char::is_control) {
        return Err(invalid(path, format!("the string {text:?} holds a line break or control character")));
    }
    Ok(format!("\"{}\"", text.replace('\\', "\\\\").replace('"', "\\\"")))
}

/// Keys become node names: `[A-Za-z_][A-Za-z0-9_-]*`.
fn check_name(name: &str, path: &str) -> Result<(), SceneError> {
    let mut chars = name.chars();
    let first = chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_');
    if first && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') && name != "true" && name != "false" {
        return Ok(());
    }
    Err(invalid(path, format!("'{name}' is not a property or node name of the scene format")))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(entries: &[(&str, Data)]) -> Data {
        Data::Map(entries.iter().map(|(k, v)| (k.to_string(), v.clone())).collect())
    }

    fn nums(xs: &[f64]) -> Data {
        Data::List(xs.iter().map(|&x| Data::Number(x)).collect())
    }

    fn s(text: &str) -> Data {
        Data::Str(text.to_owned())
    }

    /// The scene's Debug text less the `origin: "file:line:col"` of each object, which
    /// differs between the two layouts.
    fn without_origins(desc: &SceneDesc) -> String {
        let text = format!("{desc:?}");
        let mut parts = text.split("origin: \"");
        let mut out = parts.next().unwrap_or_default().to_owned();
        for part in parts {
            out.push_str(part.split_once('"').map_or(part, |(_, rest)| rest));
        }
        out
    }

    #[test]
    fn data_means_what_the_same_text_means() {
        let data = map(&[
            (
                "objects",
                Data::List(vec![map(&[(
                    "sphere",
                    map(&[
                        ("material", s("red")),
                        ("rotate", Data::List(vec![nums(&[0.0, 1.0, 0.0]), Data::Number(30.0)])),
                    ]),
                )])]),
            ),
            (
                "settings",
                map(&[
                    ("width", Data::Number(64.0)),
                    ("integrator", map(&[("path", map(&[("max_depth", Data::Number(4.0))]))])),
                ]),
            ),
            ("materials", map(&[("red", map(&[("diffuse", nums(&[1.0, 0.0, 0.0])), ("bsdf", s("diffuse"))]))])),
            ("lights", Data::List(vec![map(&[("point", map(&[("position", nums(&[0.0, 5.0, 0.5]))]))])])),
        ]);
        let text = "settings { width 64 integrator path { max_depth 4 } }\n\
                    material \"red\" { diffuse [1 0 0] bsdf diffuse }\n\
                    light point { position [0 5 0.5] }\n\
                    sphere { material \"red\" rotate [0 1 0] 30 }\n";
        let from_data = parse_data(&data, Path::new("")).expect("data parses");
        let from_text = crate::parse_scene(text, "<data>", Path::new("")).expect("text parses");
        assert_eq!(without_origins(&from_data), without_origins(&from_text));
    }

    #[test]
    fn errors_name_the_key_path() {
        let data = map(&[(
            "objects",
            Data::List(vec![map(&[("cube", Data::Null)]), map(&[("sphere", map(&[("materail", s("red"))]))])]),
        )]);
        let err = parse_data(&data, Path::new("")).expect_err("a wrong key");
        assert_eq!(err.location(), "objects[1].sphere.materail");
        assert!(err.message.contains("unknown property 'materail'"), "{}", err.message);
        let err = parse_data(&map(&[("lightz", Data::List(vec![]))]), Path::new("")).expect_err("unknown top level");
        assert_eq!(err.location(), "lightz");
        let bad_value = map(&[("settings", map(&[("width", s("wide"))]))]);
        assert_eq!(parse_data(&bad_value, Path::new("")).expect_err("a string width").location(), "settings.width");
    }

    #[test]
    fn repeated_names_go_in_a_list_of_maps() {
        let group = Data::List(vec![
            map(&[("translate", nums(&[1.0, 0.0, 0.0]))]),
            map(&[("cube", Data::Null)]),
            map(&[("translate", nums(&[0.0, 2.0, 0.0]))]),
        ]);
        let native = to_native(&map(&[("objects", map(&[("group", group)]))])).expect("writes");
        assert_eq!(native.text, "group {\n  translate [1 0 0]\n  cube\n  translate [0 2 0]\n}\n");
        assert_eq!(native.line_paths[2], "objects.group[1].cube");
        let used = map(&[(
            "objects",
            Data::List(vec![map(&[(
                "use",
                Data::List(vec![s("leg"), map(&[("translate", nums(&[1.0, 0.0, 0.0]))])]),
            )])]),
        )]);
        let native = to_native(&used).expect("writes");
        assert_eq!(native.text, "use \"leg\" {\n  translate [1 0 0]\n}\n");
        assert_eq!(native.line_paths[1], "objects[0].use[1].translate");
    }

    #[test]
    fn numbers_and_strings_read_back_exactly() {
        for x in [0.1, -2.5, 1e-7, 3.0, 1e20] {
            assert_eq!(number(x).parse::<f64>().unwrap(), x);
        }
        assert_eq!(quote("a\"b\\c", "p").unwrap(), "\"a\\\"b\\\\c\"");
        assert!(quote("two\nlines", "p").is_err());
        assert!(check_name("my key", "p").is_err());
    }
}
