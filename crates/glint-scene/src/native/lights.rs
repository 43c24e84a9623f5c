//! `light point|directional|spot { … }`.

use glam::Vec3;
use glint_core::desc::LightDesc;

use super::args::{self, Result, Seen};
use super::builder::Source;
use super::tree::Node;

/// The light types, in the order the documentation lists them.
pub const KINDS: [&str; 3] = ["point", "directional", "spot"];

/// Default `attenuation`: `f_att = 1/(1 + 0·d + 0·d²)`, no falloff.
const NO_FALLOFF: Vec3 = Vec3::X;

/// Default spot cone half-angle and penumbra, in degrees.
const SPOT_ANGLE: f32 = 30.0;
const SPOT_PENUMBRA: f32 = 5.0;

/// Builds a light from its kind node (`point { … }`), which [`KINDS`] has already checked.
pub fn light(src: &Source, kind: &Node) -> Result<LightDesc> {
    let allowed: &[&str] = match kind.name.as_str() {
        "point" => &["position", "color", "attenuation"],
        "directional" => &["direction", "color"],
        _ => &["position", "direction", "color", "attenuation", "angle", "penumbra"],
    };
    let mut position = Vec3::ZERO;
    let mut direction = Vec3::NEG_Y;
    let mut color = Vec3::ONE;
    let mut attenuation = NO_FALLOFF;
    let mut angle = SPOT_ANGLE;
    let mut penumbra = SPOT_PENUMBRA;
    let mut seen = Seen::default();
    let place = format!("in 'light {}'", kind.name);
    for prop in kind.children() {
        if !allowed.contains(&prop.name.as_str()) {
            return Err(args::unknown(src, prop, "property", &place, allowed));
        }
        seen.once(src, prop, &kind.name)?;
        match prop.name.as_str() {
            "position" => position = args::vec3(src, prop)?,
            "direction" => direction = args::direction(src, prop)?,
            "color" => color = args::color(src, prop)?,
            "attenuation" => attenuation = self::attenuation(src, prop)?,
            "angle" => {
                angle = args::number_where(src, prop, "a half-angle above 0 and at most 90 degrees", |x| {
                    x > 0.0 && x <= 90.0
                })?;
            }
            _ => {
                penumbra = args::number_where(src, prop, "0 degrees or more", |x| x >= 0.0)?;
            }
        }
    }
    Ok(match kind.name.as_str() {
        "point" => LightDesc::Point { position, color, attenuation },
        "directional" => LightDesc::Directional { direction, color },
        _ => {
            if penumbra > angle {
                let at = seen.get("penumbra").unwrap_or(kind.pos());
                return Err(src.invalid(at, format!("'penumbra' {penumbra} must not exceed 'angle' {angle}")));
            }
            LightDesc::Spot {
                position,
                direction,
                color,
                attenuation,
                angle_degrees: angle,
                penumbra_degrees: penumbra,
            }
        }
    })
}

/// `[c1 c2 c3]` of `f_att = min(1, 1/(c1 + c2·d + c3·d²))`: none negative and not all
/// zero, so the denominator stays positive.
fn attenuation(src: &Source, prop: &Node) -> Result<Vec3> {
    let c = args::vec3(src, prop)?;
    if c.min_element() < 0.0 || c.max_element() <= 0.0 {
        return Err(src.invalid(
            args::value_pos(prop),
            format!(
                "'attenuation' {c} must have no negative and at least one positive coefficient; \
                 use [1 0 0] for no falloff"
            ),
        ));
    }
    Ok(c)
}
