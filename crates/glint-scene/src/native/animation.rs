//! Keyframed properties: any property may give its values per frame instead of once,
//!
//! ```glint
//! translate { frame 0 [0 0 0]  frame 48 [0 2 0] }
//! rotate { ease "smooth"  second 0 [0 1 0] 0  second 4 [0 1 0] 360 }
//! ```
//!
//! Tracks are resolved on the node tree, before the builder gives it meaning: at a
//! given frame each track becomes the plain property it describes there, so every
//! property of every node (transforms, camera, lights, materials, settings) can be
//! animated, and the builder checks the result as if it had been written by hand.

use super::args::Result;
use super::builder::Source;
use super::tree::{Node, Value, ValueKind};

/// Which moment of the animation a scene is read at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clock {
    /// The frame, fractional between frames.
    pub frame: f64,
    /// Frames per second: how `second` keys become frames.
    pub fps: f64,
}

impl Default for Clock {
    /// Frame 0 at 24 frames per second: a still read of an animated scene.
    fn default() -> Self {
        Self { frame: 0.0, fps: DEFAULT_FPS }
    }
}

/// Frames per second unless `settings { fps … }` says otherwise: film's rate.
pub const DEFAULT_FPS: f64 = 24.0;

/// How values between two keys are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ease {
    /// Straight from key to key.
    Linear,
    /// A cubic through every key with Catmull-Rom slopes, flat at the first and the
    /// last key: motion that starts and stops gently and has no corners at keys.
    Smooth,
}

/// Whether `node` is a track: no values, and a block of keys (`frame`, `second`) with
/// at most an `ease`.
pub fn is_track(node: &Node) -> bool {
    let children = node.children();
    node.args.is_empty()
        && children.iter().any(|k| matches!(k.name.as_str(), "frame" | "second"))
        && children.iter().all(|k| matches!(k.name.as_str(), "frame" | "second" | "ease"))
}

/// `nodes` with every track, at any depth, replaced by its property at `clock`.
pub fn at_clock(src: &Source, nodes: &[Node], clock: Clock) -> Result<Vec<Node>> {
    nodes.iter().map(|node| node_at(src, node, clock)).collect()
}

fn node_at(src: &Source, node: &Node, clock: Clock) -> Result<Node> {
    if is_track(node) {
        return track_at(src, node, clock);
    }
    let mut node = node.clone();
    if let Some(block) = &mut node.block {
        block.nodes = at_clock(src, &block.nodes, clock)?;
    }
    Ok(node)
}

/// One key: its time in frames and the values it gives.
struct Key<'a> {
    frame: f64,
    node: &'a Node,
}

/// The property `track` describes at `clock`.
fn track_at(src: &Source, track: &Node, clock: Clock) -> Result<Node> {
    let (keys, ease) = keys(src, track, clock.fps)?;
    let after = keys.partition_point(|k| k.frame <= clock.frame);
    let args = if after == 0 {
        keys[0].node.args[1..].to_vec()
    } else if after == keys.len() {
        keys[after - 1].node.args[1..].to_vec()
    } else {
        let (a, b) = (&keys[after - 1], &keys[after]);
        let s = (clock.frame - a.frame) / (b.frame - a.frame);
        let weights = match ease {
            Ease::Linear => Weights::linear(s),
            Ease::Smooth => Weights::smooth(s),
        };
        (1..a.node.args.len()).map(|i| weights.blend(&keys, after - 1, i)).collect()
    };
    Ok(Node { name: track.name.clone(), args, block: None, span: track.span })
}

/// The keys of `track` in time order, checked: at least one, times strictly
/// increasing, and every key giving values of the same shape as the first.
fn keys<'a>(src: &Source, track: &'a Node, fps: f64) -> Result<(Vec<Key<'a>>, Ease)> {
    let mut ease = Ease::Linear;
    let mut keys: Vec<Key> = Vec::new();
    for child in track.children() {
        if child.name == "ease" {
            ease = match child.args.as_slice() {
                [Value { kind: ValueKind::Str(s), .. }] if s == "linear" => Ease::Linear,
                [Value { kind: ValueKind::Str(s), .. }] if s == "smooth" => Ease::Smooth,
                _ => return Err(src.invalid(child.pos(), "'ease' takes \"linear\" or \"smooth\"")),
            };
            continue;
        }
        let time = match child.args.first() {
            Some(Value { kind: ValueKind::Number(t), .. }) => *t,
            _ => return Err(src.invalid(child.pos(), format!("a '{}' key starts with its time, a number", child.name))),
        };
        let frame = if child.name == "second" { time * fps } else { time };
        if let Some(last) = keys.last() {
            if frame <= last.frame {
                return Err(src.invalid(child.pos(), "keys must be in increasing time order, each later than the last"));
            }
            if !same_shape(&last.node.args[1..], &child.args[1..]) {
                return Err(src.invalid(
                    child.pos(),
                    format!("this key gives other kinds of values than the one before it in '{}'", track.name),
                ));
            }
        }
        if child.block.is_some() {
            return Err(src.invalid(child.pos(), "a key takes values, not a block"));
        }
        keys.push(Key { frame, node: child });
    }
    Ok((keys, ease))
}

/// Whether two keys' values can be blended: the same kinds in the same order, vectors
/// of the same length.
fn same_shape(a: &[Value], b: &[Value]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match (&x.kind, &y.kind) {
            (ValueKind::Number(_), ValueKind::Number(_)) => true,
            (ValueKind::Vector(u), ValueKind::Vector(v)) => u.len() == v.len(),
            (ValueKind::Str(_), ValueKind::Str(_)) | (ValueKind::Bool(_), ValueKind::Bool(_)) => true,
            _ => false,
        })
}

/// How much the keys around a moment count: the Hermite basis over the interval from
/// key `k` to key `k + 1`, with the slopes it uses.
struct Weights {
    /// Weights of the values at keys k and k+1.
    ends: [f64; 2],
    /// Weights of the slopes at keys k and k+1 (per frame, times the interval).
    slopes: [f64; 2],
}

impl Weights {
    fn linear(s: f64) -> Self {
        Self { ends: [1.0 - s, s], slopes: [0.0, 0.0] }
    }

    /// Cubic Hermite: h00, h10, h01, h11 at `s`.
    fn smooth(s: f64) -> Self {
        let (s2, s3) = (s * s, s * s * s);
        Self { ends: [2.0 * s3 - 3.0 * s2 + 1.0, -2.0 * s3 + 3.0 * s2], slopes: [s3 - 2.0 * s2 + s, s3 - s2] }
    }

    /// Value `i` of the property between keys `k` and `k + 1`; strings and booleans
    /// hold the earlier key's until the next key.
    fn blend(&self, keys: &[Key], k: usize, i: usize) -> Value {
        let (a, b) = (&keys[k].node.args[i], &keys[k + 1].node.args[i]);
        let number = |pick: &dyn Fn(&Value) -> f64| {
            let slope = |j: usize| catmull_rom_slope(keys, j, i, pick) * (keys[k + 1].frame - keys[k].frame);
            let tangents = if self.slopes == [0.0, 0.0] { [0.0, 0.0] } else { [slope(k), slope(k + 1)] };
            self.ends[0] * pick(a)
                + self.ends[1] * pick(b)
                + self.slopes[0] * tangents[0]
                + self.slopes[1] * tangents[1]
        };
        let kind = match (&a.kind, &b.kind) {
            (ValueKind::Number(_), ValueKind::Number(_)) => ValueKind::Number(number(&|v| scalar(v, None))),
            (ValueKind::Vector(u), ValueKind::Vector(_)) => {
                ValueKind::Vector((0..u.len()).map(|c| number(&|v| scalar(v, Some(c)))).collect())
            }
            _ => a.kind.clone(),
        };
        Value { kind, pos: a.pos }
    }
}

/// Number `component` of a value (the number itself when `None`).
fn scalar(value: &Value, component: Option<usize>) -> f64 {
    match (&value.kind, component) {
        (ValueKind::Number(x), _) => *x,
        (ValueKind::Vector(v), Some(c)) => v[c],
        _ => 0.0,
    }
}

/// The slope (per frame) at key `j` of value `i`: the Catmull-Rom slope through its
/// neighbours, flat at the first and last key.
fn catmull_rom_slope(keys: &[Key], j: usize, i: usize, pick: &dyn Fn(&Value) -> f64) -> f64 {
    if j == 0 || j + 1 >= keys.len() {
        return 0.0;
    }
    let (before, after) = (&keys[j - 1], &keys[j + 1]);
    (pick(&after.node.args[i]) - pick(&before.node.args[i])) / (after.frame - before.frame)
}
