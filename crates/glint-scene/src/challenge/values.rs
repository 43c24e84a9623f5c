//! Typed readers for YAML values (`at: [1, 2, 3]`, `diffuse: 0.7`, `closed: true`), so a
//! wrong type or count reads the same everywhere: "'at' must be a list of 3 numbers".

use glam::Vec3;

use super::yaml::{Value, Yaml};
use crate::error::{SceneError, SceneErrorKind};
use crate::native::lexer::Pos;

/// Result of the YAML scene reader.
pub type Result<T> = std::result::Result<T, SceneError>;

/// The file being read, named in errors, warnings and node origins.
pub struct Src {
    /// The file as it appears in messages and node origins.
    pub name: String,
    /// The folder relative file names (OBJ files) start from.
    pub dir: std::path::PathBuf,
}

impl Src {
    /// A scene-meaning error located in this file.
    pub fn invalid(&self, pos: Pos, message: impl Into<String>) -> SceneError {
        SceneError::new(SceneErrorKind::Invalid, self.name.clone(), pos.line, pos.column, message)
    }

    /// `file:line:col`, the origin recorded on scene nodes and the prefix of warnings.
    pub fn origin(&self, pos: Pos) -> String {
        format!("{}:{}:{}", self.name, pos.line, pos.column)
    }

    /// A warning located in this file.
    pub fn warning(&self, pos: Pos, message: impl std::fmt::Display) -> String {
        format!("{}: {message}", self.origin(pos))
    }
}

/// The entries of a mapping, or an error saying that `what` must be one.
pub fn mapping<'y>(src: &Src, node: &'y Yaml, what: &str) -> Result<&'y [(Yaml, Yaml)]> {
    node.map().ok_or_else(|| {
        src.invalid(node.pos, format!("{what} must be a mapping of 'key: value' lines, found {}", node.describe()))
    })
}

/// The items of a list, or an error saying that `key` must be one.
pub fn list<'y>(src: &Src, node: &'y Yaml, key: &str) -> Result<&'y [Yaml]> {
    node.seq().ok_or_else(|| src.invalid(node.pos, format!("'{key}' must be a list, found {}", node.describe())))
}

/// A single word or text (a name, a kind, a file).
pub fn word<'y>(src: &Src, node: &'y Yaml, key: &str) -> Result<&'y str> {
    match node.scalar() {
        Some(text) if !text.is_empty() => Ok(text),
        _ => Err(src.invalid(node.pos, format!("'{key}' must be a name, found {}", node.describe()))),
    }
}

/// Parses a scalar as a finite number (also in `f32`); `None` when it is not one.
fn parse_number(node: &Yaml) -> Option<f32> {
    let Value::Scalar { text, .. } = &node.value else { return None };
    let x: f64 = text.trim().parse().ok()?;
    // Rust also reads "inf" and "NaN"; a scene number must be finite.
    (x.is_finite() && (x as f32).is_finite()).then_some(x as f32)
}

/// A finite number.
pub fn number(src: &Src, node: &Yaml, key: &str) -> Result<f32> {
    parse_number(node).ok_or_else(|| {
        src.invalid(
            node.pos,
            format!("'{key}' must be a finite number like 1, -0.5 or 1e-3, found {}", node.describe()),
        )
    })
}

/// A number satisfying `ok`; `rule` says what is allowed ("0 or more").
pub fn number_where(src: &Src, node: &Yaml, key: &str, rule: &str, ok: impl Fn(f32) -> bool) -> Result<f32> {
    let x = number(src, node, key)?;
    if ok(x) { Ok(x) } else { Err(src.invalid(node.pos, format!("'{key}' must be {rule}, found {x}"))) }
}

/// A number that may also be YAML's infinity (`.inf`, `-.inf`), as cylinder and cone
/// bounds are in the book.
pub fn bound(src: &Src, node: &Yaml, key: &str) -> Result<f32> {
    match node.scalar().map(str::trim) {
        Some(".inf" | "+.inf" | ".Inf" | ".INF" | "inf" | "infinity") => Ok(f32::INFINITY),
        Some("-.inf" | "-.Inf" | "-.INF" | "-inf" | "-infinity") => Ok(f32::NEG_INFINITY),
        _ => parse_number(node).ok_or_else(|| {
            src.invalid(
                node.pos,
                format!("'{key}' must be a number or .inf / -.inf (unbounded), found {}", node.describe()),
            )
        }),
    }
}

/// A whole number in `min..=max`.
pub fn whole(src: &Src, node: &Yaml, key: &str, min: u32, max: u32) -> Result<u32> {
    let x = f64::from(number(src, node, key)?);
    if x.fract() != 0.0 || x < f64::from(min) || x > f64::from(max) {
        return Err(src.invalid(node.pos, format!("'{key}' must be a whole number from {min} to {max}, found {x}")));
    }
    Ok(x as u32)
}

/// `n` numbers written as a list `[a, b, …]`.
pub fn numbers(src: &Src, node: &Yaml, key: &str, n: usize) -> Result<Vec<f32>> {
    let wrong = || {
        src.invalid(
            node.pos,
            format!("'{key}' must be a list of {n} numbers like [1, 0.5, -2], found {}", node.describe()),
        )
    };
    let items = node.seq().ok_or_else(wrong)?;
    if items.len() != n {
        return Err(wrong());
    }
    items.iter().map(|item| number(src, item, key)).collect()
}

/// A point or vector `[x, y, z]`.
pub fn vec3(src: &Src, node: &Yaml, key: &str) -> Result<Vec3> {
    let v = numbers(src, node, key, 3)?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// A colour `[r, g, b]`, never negative.
pub fn color(src: &Src, node: &Yaml, key: &str) -> Result<Vec3> {
    let c = vec3(src, node, key)?;
    if c.min_element() < 0.0 {
        return Err(src.invalid(node.pos, format!("colour '{key}' must not be negative, found {c}")));
    }
    Ok(c)
}

/// `true` or `false`.
pub fn boolean(src: &Src, node: &Yaml, key: &str) -> Result<bool> {
    match node.scalar() {
        Some("true" | "True" | "TRUE") => Ok(true),
        Some("false" | "False" | "FALSE") => Ok(false),
        _ => Err(src.invalid(node.pos, format!("'{key}' must be true or false, found {}", node.describe()))),
    }
}

/// Warnings for keys of `entries` that are not in `known` (they are ignored); `place`
/// reads like "in 'sphere'".
pub fn unknown_keys(src: &Src, entries: &[(Yaml, Yaml)], known: &[&str], place: &str, warnings: &mut Vec<String>) {
    for (key, _) in entries {
        let name = key.scalar().unwrap_or("");
        if !known.contains(&name) {
            warnings.push(src.warning(key.pos, unknown_key(name, place, known)));
        }
    }
}

/// "unknown key 'k' {place} is ignored", with the nearest known key when one is close
/// (`field_of_view` for `field-of-view`, a letter or two amiss) and every known key.
pub fn unknown_key(name: &str, place: &str, known: &[&str]) -> String {
    format!("unknown key '{name}' {place} is ignored{}; known keys: {}", did_you_mean(name, known), known.join(", "))
}

/// " (did you mean 'x'?)" when a word of `known` is close to `word`, else nothing.
pub fn did_you_mean(word: &str, known: &[&str]) -> String {
    nearest(word, known).map(|k| format!(" (did you mean '{k}'?)")).unwrap_or_default()
}

/// The word of `known` closest to `word`, when it is close enough to be a slip: at most
/// a third of its letters amiss, `_`, `-` and case aside.
pub fn nearest<'k>(word: &str, known: &[&'k str]) -> Option<&'k str> {
    let fold = |w: &str| w.to_lowercase().replace(['_', ' '], "-");
    let word = fold(word);
    known
        .iter()
        .map(|&k| (edit_distance(&word, &fold(k)), k))
        .filter(|&(d, k)| d <= (k.chars().count().max(word.chars().count()) / 3).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, k)| k)
}

/// Levenshtein distance: insertions, deletions and substitutions to turn `a` into `b`.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (diagonal + usize::from(ca != cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diagonal = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The value of `key` in `entries`, or an error naming the mapping that needs it.
pub fn required<'y>(src: &Src, entries: &'y [(Yaml, Yaml)], pos: Pos, key: &str, what: &str) -> Result<&'y Yaml> {
    get(entries, key).ok_or_else(|| src.invalid(pos, format!("{what} needs '{key}'")))
}

/// The value of `key` in `entries`, if given.
pub fn get<'y>(entries: &'y [(Yaml, Yaml)], key: &str) -> Option<&'y Yaml> {
    entries.iter().find(|(k, _)| k.scalar() == Some(key)).map(|(_, v)| v)
}
