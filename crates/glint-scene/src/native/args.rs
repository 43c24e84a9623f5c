//! Typed readers for the values of property nodes (`translate [1 2 3]`, `fov 45`, …).
//!
//! Every scene property goes through these, so a wrong count or type reads the same
//! everywhere: `expected 3 numbers for 'translate', found 2`.

use glam::{Vec2, Vec3};

use super::builder::Source;
use super::lexer::Pos;
use super::tree::{Node, Value, ValueKind};
use crate::error::SceneError;

/// Result of the builder stages.
pub type Result<T> = std::result::Result<T, SceneError>;

/// Refuses a `{ … }` after a property that takes only values.
pub fn no_block(src: &Source, node: &Node) -> Result<()> {
    match &node.block {
        Some(block) => Err(src.invalid(block.open, format!("'{}' does not take a block", node.name))),
        None => Ok(()),
    }
}

/// Refuses values after a node that takes only a block (`sphere 2 { … }`).
pub fn no_values(src: &Source, node: &Node) -> Result<()> {
    match node.args.first() {
        Some(value) => Err(src.invalid(
            value.pos,
            format!("'{}' takes no values, found {}; write its properties inside {{ … }}", node.name, value.describe()),
        )),
        None => Ok(()),
    }
}

/// Where a property's value starts (its name when it has none), for range errors.
pub fn value_pos(node: &Node) -> Pos {
    node.args.first().map_or(node.pos(), |v| v.pos)
}

/// "3 numbers", "1 or 3 numbers", …, for arity messages.
fn describe_counts(counts: &[usize]) -> String {
    let words: Vec<String> = counts.iter().map(usize::to_string).collect();
    let last = counts.last().copied().unwrap_or(0);
    let noun = if last == 1 { "number" } else { "numbers" };
    format!("{} {noun}", words.join(" or "))
}

/// The numbers of a property written as one number or one `[vector]` whose length is
/// one of `counts` (1 means a bare number is accepted).
pub fn numbers(src: &Source, node: &Node, counts: &[usize]) -> Result<Vec<f32>> {
    no_block(src, node)?;
    let wanted = describe_counts(counts);
    // A count mismatch points at the property; a value of the wrong type at the value.
    let mut at = node.pos();
    let found = match node.args.as_slice() {
        [] => "none".to_owned(),
        [value] => match &value.kind {
            ValueKind::Number(x) if counts.contains(&1) => return Ok(vec![*x as f32]),
            ValueKind::Number(_) => "1".to_owned(),
            ValueKind::Vector(items) if counts.contains(&items.len()) => {
                return Ok(items.iter().map(|x| *x as f32).collect());
            }
            ValueKind::Vector(items) => items.len().to_string(),
            _ => {
                at = value.pos;
                value.describe()
            }
        },
        many if many.iter().all(|v| matches!(v.kind, ValueKind::Number(_))) => {
            format!("{} separate numbers; write a vector in brackets, like [1 2 3]", many.len())
        }
        many => format!("{} values", many.len()),
    };
    Err(src.invalid(at, format!("expected {wanted} for '{}', found {found}", node.name)))
}

/// A single number.
pub fn number(src: &Source, node: &Node) -> Result<f32> {
    Ok(numbers(src, node, &[1])?[0])
}

/// A single number that must satisfy `ok`; `rule` says what is allowed ("greater than 0").
pub fn number_where(src: &Source, node: &Node, rule: &str, ok: impl Fn(f32) -> bool) -> Result<f32> {
    let x = number(src, node)?;
    if ok(x) { Ok(x) } else { Err(src.invalid(value_pos(node), format!("'{}' must be {rule}, found {x}", node.name))) }
}

/// A whole number in `min..=max` (image size, sample count, …).
pub fn whole(src: &Source, node: &Node, min: u32, max: u32) -> Result<u32> {
    let x = f64::from(number(src, node)?);
    if x.fract() != 0.0 || x < f64::from(min) || x > f64::from(max) {
        return Err(src.invalid(
            value_pos(node),
            format!("'{}' must be a whole number from {min} to {max}, found {x}", node.name),
        ));
    }
    Ok(x as u32)
}

/// Exactly three numbers `[x y z]` (points, directions).
pub fn vec3(src: &Source, node: &Node) -> Result<Vec3> {
    let v = numbers(src, node, &[3])?;
    Ok(Vec3::new(v[0], v[1], v[2]))
}

/// A non-zero direction; zero has no direction to normalize.
pub fn direction(src: &Source, node: &Node) -> Result<Vec3> {
    let v = vec3(src, node)?;
    if v.length_squared() > 0.0 && v.length_squared().is_finite() {
        Ok(v)
    } else {
        Err(src.invalid(value_pos(node), format!("'{}' must be a non-zero, finite direction, found {v}", node.name)))
    }
}

/// `[x y z]` or one number meaning `[n n n]` (scale factors, colours).
pub fn vec3_broadcast(src: &Source, node: &Node) -> Result<Vec3> {
    let v = numbers(src, node, &[1, 3])?;
    Ok(match v.as_slice() {
        [x, y, z] => Vec3::new(*x, *y, *z),
        _ => Vec3::splat(v[0]),
    })
}

/// `[u v]` or one number meaning `[n n]`, each positive (texture repeats and cells).
pub fn vec2_positive(src: &Source, node: &Node) -> Result<Vec2> {
    let v = numbers(src, node, &[1, 2])?;
    let v = match v.as_slice() {
        [u, v] => Vec2::new(*u, *v),
        _ => Vec2::splat(v[0]),
    };
    if v.min_element() > 0.0 {
        Ok(v)
    } else {
        Err(src.invalid(value_pos(node), format!("'{}' must be greater than 0, found {v}", node.name)))
    }
}

/// A colour: `[r g b]` or one grey level, never negative (negative light is not a thing).
pub fn color(src: &Source, node: &Node) -> Result<Vec3> {
    let c = vec3_broadcast(src, node)?;
    if c.min_element() >= 0.0 {
        Ok(c)
    } else {
        Err(src.invalid(
            value_pos(node),
            format!("colour '{}' must not be negative, found {c}; components are 0 or more", node.name),
        ))
    }
}

/// The single `true`/`false` of a switch like `shadows false`.
pub fn boolean(src: &Source, node: &Node) -> Result<bool> {
    let found = match node.args.as_slice() {
        [Value { kind: ValueKind::Bool(b), .. }] => return Ok(*b),
        [] => "nothing".to_owned(),
        [value] => value.describe(),
        many => format!("{} values", many.len()),
    };
    Err(src.invalid(value_pos(node), format!("expected true or false after '{}', found {found}", node.name)))
}

/// One of a fixed list of quoted words (`sampler "sobol"`), as the value it stands for.
pub fn choice<T: Copy>(src: &Source, node: &Node, options: &[(&str, T)]) -> Result<T> {
    no_block(src, node)?;
    let found = match node.args.as_slice() {
        [Value { kind: ValueKind::Str(word), .. }] => match options.iter().find(|(name, _)| name == word) {
            Some(&(_, value)) => return Ok(value),
            None => format!("\"{word}\""),
        },
        [] => "nothing".to_owned(),
        [value] => value.describe(),
        many => format!("{} values", many.len()),
    };
    let quoted: Vec<String> = options.iter().map(|(name, _)| format!("\"{name}\"")).collect();
    let list = match quoted.split_last() {
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
        None => String::new(),
    };
    Err(src.invalid(value_pos(node), format!("'{}' must be {list} (in quotes), found {found}", node.name)))
}

/// The single quoted string of a node (`material "glass"`), with its position.
pub fn string(src: &Source, node: &Node, what: &str) -> Result<(String, Pos)> {
    let found = match node.args.as_slice() {
        [Value { kind: ValueKind::Str(text), pos }] => return Ok((text.clone(), *pos)),
        [] => "nothing".to_owned(),
        [value] => value.describe(),
        many => format!("{} values", many.len()),
    };
    Err(src.invalid(
        value_pos(node),
        format!("expected {what} in quotes after '{}', like {} \"name\", found {found}", node.name, node.name),
    ))
}

/// Remembers which properties a block has set, so that a repeated one is refused instead
/// of silently overriding the first.
#[derive(Default)]
pub struct Seen {
    set: Vec<(String, Pos)>,
}

impl Seen {
    /// Records `node`, failing if the same property was already set in this block.
    pub fn once(&mut self, src: &Source, node: &Node, parent: &str) -> Result<()> {
        if let Some((_, first)) = self.set.iter().find(|(name, _)| *name == node.name) {
            return Err(src.invalid(
                node.pos(),
                format!(
                    "'{}' is set twice in '{parent}'; the first is at line {}, column {}",
                    node.name, first.line, first.column
                ),
            ));
        }
        self.set.push((node.name.clone(), node.pos()));
        Ok(())
    }

    /// Where `name` was set in this block, if it was.
    pub fn get(&self, name: &str) -> Option<Pos> {
        self.set.iter().find(|(n, _)| n == name).map(|(_, p)| *p)
    }
}

/// The error for a node name that is not allowed where it stands.
///
/// `place` reads like "in 'sphere'" or "at the top level".
pub fn unknown(src: &Source, node: &Node, what: &str, place: &str, allowed: &[&str]) -> SceneError {
    src.invalid(node.pos(), format!("unknown {what} '{}' {place}; expected one of: {}", node.name, allowed.join(", ")))
}
