//! `integrator whitted` and `integrator path { … }` inside `settings`: which
//! light-transport algorithm renders the image, and the path tracer's limits.

use glint_core::desc::{IntegratorDesc, PathDesc, SamplerKind};

use super::args::{self, Result, Seen};
use super::builder::Source;
use super::tree::{Node, Value, ValueKind};

/// The integrator types, in the order the documentation lists them.
pub const KINDS: [&str; 2] = ["whitted", "path"];

/// Properties of `integrator path { … }`.
const PATH_PROPERTIES: [&str; 3] = ["max_depth", "rr_depth", "sampler"];

/// Largest finite path depth (and roulette depth): 2²⁴, the largest whole number every
/// `.glint` number holds exactly; `-1` or `"unlimited"` stands for no limit.
pub const MAX_PATH_DEPTH: u32 = 1 << 24;

/// Builds the integrator from its kind node (`whitted` or `path { … }`), which
/// [`KINDS`] has already checked.
pub fn integrator(src: &Source, kind: &Node) -> Result<IntegratorDesc> {
    if kind.name == "whitted" {
        if let Some(block) = &kind.block {
            return Err(src.invalid(
                block.open,
                "'integrator whitted' takes no properties; its limits are the settings 'max_depth' and \
                 'min_contribution'",
            ));
        }
        return Ok(IntegratorDesc::Whitted);
    }
    let mut path = PathDesc::default();
    let mut seen = Seen::default();
    for prop in kind.children() {
        if !PATH_PROPERTIES.contains(&prop.name.as_str()) {
            return Err(args::unknown(src, prop, "property", "in 'integrator path'", &PATH_PROPERTIES));
        }
        seen.once(src, prop, "integrator path")?;
        match prop.name.as_str() {
            "max_depth" => path.max_depth = max_depth(src, prop)?,
            "rr_depth" => path.rr_depth = args::whole(src, prop, 1, MAX_PATH_DEPTH)?,
            _ => path.sampler = sampler(src, prop)?,
        }
    }
    Ok(IntegratorDesc::Path(path))
}

/// `max_depth N`, counted as Mitsuba counts it; `-1` or `"unlimited"` is `u32::MAX`.
fn max_depth(src: &Source, prop: &Node) -> Result<u32> {
    args::no_block(src, prop)?;
    match prop.args.as_slice() {
        [Value { kind: ValueKind::Str(word), .. }] if word == "unlimited" => return Ok(u32::MAX),
        [Value { kind: ValueKind::Number(x), .. }] if *x == -1.0 => return Ok(u32::MAX),
        [Value { kind: ValueKind::Number(x), .. }]
            if x.fract() == 0.0 && (0.0..=f64::from(MAX_PATH_DEPTH)).contains(x) =>
        {
            return Ok(*x as u32);
        }
        _ => {}
    }
    let found = match prop.args.as_slice() {
        [] => "nothing".to_owned(),
        [Value { kind: ValueKind::Number(x), .. }] => x.to_string(),
        [Value { kind: ValueKind::Str(word), .. }] => format!("\"{word}\""),
        [value] => value.describe(),
        many => format!("{} values", many.len()),
    };
    Err(src.invalid(
        args::value_pos(prop),
        format!(
            "'max_depth' must be a whole number from 0 to {MAX_PATH_DEPTH}, or -1 or \"unlimited\" for no limit, \
             found {found}"
        ),
    ))
}

/// `sampler "sobol"|"independent"`.
fn sampler(src: &Source, prop: &Node) -> Result<SamplerKind> {
    args::choice(src, prop, &[("sobol", SamplerKind::Sobol), ("independent", SamplerKind::Independent)])
}
