//! `light point|directional|spot|rectangle|disk|sphere|environment { … }`.

use glam::Vec3;
use glint_core::desc::{AreaShape, EnvironmentDesc, LightDesc, TextureDesc};

use super::args::{self, Result, Seen};
use super::builder::{Registry, Source};
use super::objects::{TRANSFORMS, transform_op};
use super::tree::Node;

/// The light types, in the order the documentation lists them.
pub const KINDS: [&str; 7] = ["point", "directional", "spot", "rectangle", "disk", "sphere", "environment"];

/// Default stratified samples per axis of an area light (4×4 = 16 shadow rays).
const AREA_SAMPLES: u32 = 4;

/// Default `attenuation`: `f_att = 1/(1 + 0·d + 0·d²)`, no falloff.
const NO_FALLOFF: Vec3 = Vec3::X;

/// Default spot cone half-angle and penumbra, in degrees.
const SPOT_ANGLE: f32 = 30.0;
const SPOT_PENUMBRA: f32 = 5.0;

/// Builds a light from its kind node (`point { … }`), which [`KINDS`] has already checked;
/// an environment's texture is looked up by name in `textures`, whose descriptions are
/// `texture_descs`.
pub fn light(src: &Source, kind: &Node, textures: &Registry, texture_descs: &[TextureDesc]) -> Result<LightDesc> {
    if kind.name == "environment" {
        return environment(src, kind, textures, texture_descs).map(LightDesc::Environment);
    }
    let allowed: &[&str] = match kind.name.as_str() {
        "point" => &["position", "color", "attenuation"],
        "directional" => &["direction", "color"],
        "spot" => &["position", "direction", "color", "attenuation", "angle", "penumbra", "falloff"],
        "rectangle" => &["corner", "edge_u", "edge_v", "color", "attenuation", "samples"],
        "disk" => &["position", "normal", "radius", "color", "attenuation", "samples"],
        _ => &["position", "radius", "color", "attenuation", "samples"],
    };
    let mut corner = Vec3::ZERO;
    let mut edges = (Vec3::X, Vec3::Z);
    let mut normal = Vec3::NEG_Y;
    let mut radius = 0.5;
    let mut samples = AREA_SAMPLES;
    let mut position = Vec3::ZERO;
    let mut direction = Vec3::NEG_Y;
    let mut color = Vec3::ONE;
    let mut attenuation = NO_FALLOFF;
    let mut angle = SPOT_ANGLE;
    let mut penumbra = SPOT_PENUMBRA;
    let mut falloff = glint_core::desc::SpotFalloff::Smooth;
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
            "corner" => corner = args::vec3(src, prop)?,
            "edge_u" => edges.0 = args::direction(src, prop)?,
            "edge_v" => edges.1 = args::direction(src, prop)?,
            "normal" => normal = args::direction(src, prop)?,
            "radius" => radius = args::number_where(src, prop, "above 0", |x| x > 0.0)?,
            "samples" => samples = args::whole(src, prop, 1, 64)?,
            "angle" => {
                angle = args::number_where(src, prop, "a half-angle above 0 and at most 90 degrees", |x| {
                    x > 0.0 && x <= 90.0
                })?;
            }
            "falloff" => {
                use glint_core::desc::SpotFalloff;
                falloff = args::choice(src, prop, &[("smooth", SpotFalloff::Smooth), ("linear", SpotFalloff::Linear)])?;
            }
            _ => {
                penumbra = args::number_where(src, prop, "0 degrees or more", |x| x >= 0.0)?;
            }
        }
    }
    Ok(match kind.name.as_str() {
        "point" => LightDesc::Point { position, color, attenuation },
        "directional" => LightDesc::Directional { direction, color },
        "rectangle" => {
            let shape = AreaShape::Rectangle { corner, edge_u: edges.0, edge_v: edges.1 };
            LightDesc::Area { shape, color, attenuation, samples }
        }
        "disk" => {
            LightDesc::Area { shape: AreaShape::Disk { center: position, normal, radius }, color, attenuation, samples }
        }
        "sphere" => {
            LightDesc::Area { shape: AreaShape::Sphere { center: position, radius }, color, attenuation, samples }
        }
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
                falloff,
            }
        }
    })
}

/// `light environment { radiance [r g b]  texture "sky"  rotate [0 1 0] 90 … }`: the
/// transform statements turn the map, in written order.
fn environment(
    src: &Source,
    kind: &Node,
    textures: &Registry,
    texture_descs: &[TextureDesc],
) -> Result<EnvironmentDesc> {
    let mut env = EnvironmentDesc { radiance: Vec3::ONE, texture: None, transform: Vec::new() };
    let mut seen = Seen::default();
    for prop in kind.children() {
        if let Some(op) = transform_op(src, prop)? {
            env.transform.push(op);
            continue;
        }
        seen.once(src, prop, "environment")?;
        match prop.name.as_str() {
            "radiance" => env.radiance = args::color(src, prop)?,
            "texture" => {
                args::no_block(src, prop)?;
                let (name, pos) = args::string(src, prop, "a texture name")?;
                let index = textures.lookup(src, pos, "texture", &name)?;
                if !matches!(texture_descs.get(index), Some(TextureDesc::Image { .. })) {
                    return Err(src.invalid(
                        pos,
                        format!(
                            "texture '{name}' is not an image; an environment needs an image texture \
                             (a latitude-longitude map), as in `texture \"sky\" image {{ file \"sky.exr\" }}`"
                        ),
                    ));
                }
                env.texture = Some(index);
            }
            _ => {
                let mut allowed = vec!["radiance", "texture"];
                allowed.extend(TRANSFORMS);
                return Err(args::unknown(src, prop, "property", "in 'light environment'", &allowed));
            }
        }
    }
    Ok(env)
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
