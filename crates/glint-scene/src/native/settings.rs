//! `settings { … }` and `camera { … }`: how the image is made and from where.

use glint_core::desc::{AdaptiveDesc, CameraDesc, FilterKind, RenderSettings, SamplePattern, Transfer};

use super::args::{self, Result, Seen};
use super::builder::{Builder, Source};
use super::integrator;
use super::tree::Node;

/// Largest image side accepted; larger images are almost certainly a typo and would
/// allocate gigabytes.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Most samples per pixel axis (64² = 4096 rays per pixel).
pub const MAX_SAMPLES_PER_AXIS: u32 = 64;

/// Deepest recursion accepted for `max_depth`.
pub const MAX_DEPTH: u32 = 64;

/// Most samples per pixel accepted for `spp` (2²⁰).
pub const MAX_SPP: u32 = 1 << 20;

const SETTINGS_PROPERTIES: [&str; 22] = [
    "fps",
    "frames",
    "width",
    "height",
    "samples",
    "max_depth",
    "min_contribution",
    "background",
    "ambient",
    "shadows",
    "reflections",
    "refractions",
    "textures",
    "transparent_shadows",
    "output_transfer",
    "pattern",
    "filter",
    "filter_radius",
    "adaptive",
    "seed",
    "integrator",
    "spp",
];

const CAMERA_PROPERTIES: [&str; 8] = ["eye", "look_at", "look", "up", "fov", "fov_axis", "aperture", "focal_distance"];

/// Most frames an animation may span.
pub const MAX_FRAME: u32 = 1_000_000;

/// Applies a `settings` block on top of `settings` (which starts at the defaults).
/// `clock_fps` is the rate the scene's keys were read at (from the main file's
/// settings): an `fps` here must agree with it.
pub fn settings(src: &Source, node: &Node, settings: &mut RenderSettings, clock_fps: f64) -> Result<()> {
    args::no_values(src, node)?;
    let mut seen = Seen::default();
    let mut rest = node.children().iter();
    while let Some(prop) = rest.next() {
        seen.once(src, prop, "settings")?;
        match prop.name.as_str() {
            "integrator" => {
                args::no_values(src, prop)?;
                let kind = Builder::kind_node(src, prop, rest.next(), &integrator::KINDS)?;
                settings.integrator = integrator::integrator(src, kind)?;
            }
            "spp" => settings.spp = Some(args::whole(src, prop, 1, MAX_SPP)?),
            "fps" => {
                settings.fps = args::number_where(src, prop, "above 0 and at most 1000", |x| x > 0.0 && x <= 1000.0)?;
                if f64::from(settings.fps) != clock_fps {
                    return Err(src.invalid(
                        prop.pos(),
                        "'fps' must be in the settings of the main scene file, where keys in seconds are read",
                    ));
                }
            }
            "frames" => settings.frames = Some(frames(src, prop)?),
            "width" => settings.width = args::whole(src, prop, 1, MAX_IMAGE_SIDE)?,
            "height" => settings.height = args::whole(src, prop, 1, MAX_IMAGE_SIDE)?,
            "samples" => {
                settings.samples_per_axis = args::whole(src, prop, 1, MAX_SAMPLES_PER_AXIS)?;
            }
            "max_depth" => settings.max_depth = args::whole(src, prop, 0, MAX_DEPTH)?,
            "min_contribution" => {
                settings.min_contribution = args::number_where(src, prop, "from 0 to 1", |x| (0.0..=1.0).contains(&x))?;
            }
            "background" => settings.background = args::color(src, prop)?,
            "ambient" => settings.ambient_light = args::color(src, prop)?,
            "shadows" => settings.features.shadows = args::boolean(src, prop)?,
            "reflections" => settings.features.reflections = args::boolean(src, prop)?,
            "refractions" => settings.features.refractions = args::boolean(src, prop)?,
            "textures" => settings.features.textures = args::boolean(src, prop)?,
            "transparent_shadows" => settings.features.transparent_shadows = args::boolean(src, prop)?,
            "pattern" => settings.pattern = pattern(src, prop)?,
            "filter" => settings.filter.kind = filter_kind(src, prop)?,
            "filter_radius" => {
                settings.filter.radius =
                    args::number_where(src, prop, "above 0 and at most 8 pixels", |x| x > 0.0 && x <= 8.0)?;
            }
            "adaptive" => settings.adaptive = Some(adaptive(src, prop)?),
            "seed" => settings.seed = args::whole(src, prop, 0, u32::MAX)?,
            "output_transfer" => {
                settings.output_transfer = match args::string(src, prop, "a transfer")?.0.as_str() {
                    "srgb" => Transfer::Srgb,
                    "identity" => Transfer::Identity,
                    other => {
                        return Err(src.invalid(
                            args::value_pos(prop),
                            format!("unknown output_transfer \"{other}\"; expected \"srgb\" or \"identity\""),
                        ));
                    }
                }
            }
            _ => {
                return Err(args::unknown(src, prop, "property", "in 'settings'", &SETTINGS_PROPERTIES));
            }
        }
    }
    Ok(())
}

/// `frames [first last]`: whole frame numbers, first ≤ last.
fn frames(src: &Source, prop: &Node) -> Result<[u32; 2]> {
    let numbers = args::numbers(src, prop, &[2])?;
    let whole = |x: f32| x.fract() == 0.0 && (0.0..=MAX_FRAME as f32).contains(&x);
    match numbers.as_slice() {
        &[first, last] if whole(first) && whole(last) && first <= last => Ok([first as u32, last as u32]),
        _ => Err(src.invalid(
            args::value_pos(prop),
            format!("'frames' takes [first last]: whole frame numbers from 0 to {MAX_FRAME}, first <= last"),
        )),
    }
}

/// `pattern "grid"|"corners"|"jittered"|"sobol"`.
fn pattern(src: &Source, prop: &Node) -> Result<SamplePattern> {
    let (name, pos) = args::string(src, prop, "a sample pattern")?;
    Ok(match name.as_str() {
        "grid" => SamplePattern::Grid,
        "corners" => SamplePattern::CornersAndCentre,
        "jittered" => SamplePattern::Jittered,
        "sobol" => SamplePattern::Sobol,
        other => {
            return Err(src.invalid(
                pos,
                format!("unknown pattern \"{other}\"; expected \"grid\", \"corners\", \"jittered\" or \"sobol\""),
            ));
        }
    })
}

/// `filter "box"|"tent"|"gaussian"|"mitchell"|"lanczos"`.
fn filter_kind(src: &Source, prop: &Node) -> Result<FilterKind> {
    let (name, pos) = args::string(src, prop, "a filter")?;
    Ok(match name.as_str() {
        "box" => FilterKind::Box,
        "tent" => FilterKind::Tent,
        "gaussian" => FilterKind::Gaussian,
        "mitchell" => FilterKind::Mitchell,
        "lanczos" => FilterKind::Lanczos,
        other => {
            return Err(src.invalid(
                pos,
                format!(
                    "unknown filter \"{other}\"; expected \"box\", \"tent\", \"gaussian\", \"mitchell\" or \"lanczos\""
                ),
            ));
        }
    })
}

/// `adaptive [min max threshold]`.
fn adaptive(src: &Source, prop: &Node) -> Result<AdaptiveDesc> {
    let v = args::numbers(src, prop, &[3])?;
    let ok = v[0] >= 1.0 && v[1] >= v[0] && v[1] <= 4096.0 && v[2] >= 0.0 && v[0].fract() == 0.0 && v[1].fract() == 0.0;
    if !ok {
        return Err(src.invalid(
            args::value_pos(prop),
            "'adaptive [min max threshold]' needs whole 1 <= min <= max <= 4096 and threshold >= 0",
        ));
    }
    Ok(AdaptiveDesc { min_samples: v[0] as u32, max_samples: v[1] as u32, threshold: v[2] })
}

/// Builds a `camera` block; unset properties keep [`CameraDesc::default`].
pub fn camera(src: &Source, node: &Node) -> Result<CameraDesc> {
    args::no_values(src, node)?;
    let mut camera = CameraDesc::default();
    let mut look_at = None;
    let mut seen = Seen::default();
    for prop in node.children() {
        seen.once(src, prop, "camera")?;
        match prop.name.as_str() {
            "eye" => camera.eye = args::vec3(src, prop)?,
            "look_at" => look_at = Some((args::vec3(src, prop)?, prop)),
            "look" => camera.look = args::direction(src, prop)?,
            "up" => camera.up = args::direction(src, prop)?,
            "fov" => {
                camera.fov_y_degrees =
                    args::number_where(src, prop, "between 0 and 180 degrees (both excluded)", |x| {
                        x > 0.0 && x < 180.0
                    })?;
            }
            "fov_axis" => camera.fov_axis = fov_axis(src, prop)?,
            "aperture" => camera.aperture_radius = args::number_where(src, prop, "0 or more", |x| x >= 0.0)?,
            "focal_distance" => camera.focal_distance = args::number_where(src, prop, "above 0", |x| x > 0.0)?,
            _ => {
                return Err(args::unknown(src, prop, "property", "in 'camera'", &CAMERA_PROPERTIES));
            }
        }
    }
    if let Some((target, prop)) = look_at {
        if let Some(look) = seen.get("look") {
            return Err(src.invalid(
                prop.pos(),
                format!(
                    "give either 'look_at' (a point) or 'look' (a direction), not both; 'look' is at line {}, column {}",
                    look.line, look.column
                ),
            ));
        }
        let look = target - camera.eye;
        if !(look.length_squared() > 0.0 && look.length_squared().is_finite()) {
            return Err(src.invalid(
                args::value_pos(prop),
                format!(
                    "'look_at' {target} must be a point away from 'eye' {}; the camera would look nowhere",
                    camera.eye
                ),
            ));
        }
        camera.look = look;
        if seen.get("focal_distance").is_none() {
            // An open lens focuses on the point looked at unless told otherwise.
            camera.focal_distance = look.length();
        }
    }
    let sine = camera.look.normalize().cross(camera.up.normalize()).length();
    if sine.is_nan() || sine < 1e-4 {
        let at = seen.get("up").or_else(|| seen.get("look")).or_else(|| seen.get("look_at")).unwrap_or(node.pos());
        return Err(src.invalid(
            at,
            format!(
                "'up' {} is parallel to the viewing direction {}; choose an up vector that is not along the direction the camera looks",
                camera.up, camera.look
            ),
        ));
    }
    Ok(camera)
}

/// `fov_axis "y"|"x"|"diagonal"|"smaller"|"larger"`: the extent `fov` spans.
fn fov_axis(src: &Source, prop: &Node) -> Result<glint_core::desc::FovAxis> {
    use glint_core::desc::FovAxis;
    let axes = [
        ("y", FovAxis::Y),
        ("x", FovAxis::X),
        ("diagonal", FovAxis::Diagonal),
        ("smaller", FovAxis::Smaller),
        ("larger", FovAxis::Larger),
    ];
    args::choice(src, prop, &axes)
}
