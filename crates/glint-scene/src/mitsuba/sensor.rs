//! The camera and the render settings: `sensor` (`perspective`, `thinlens`) with its
//! `film` (`hdrfilm`), `rfilter` and `sampler`, and the `integrator` (`path`).

use glam::{Mat3, Vec3};
use glint_core::desc::{
    CameraDesc, FilterDesc, FilterKind, FovAxis, IntegratorDesc, PathDesc, RenderSettings, SamplerKind, SceneDesc,
};

use super::tree::Elem;
use super::values::Plugin;
use crate::error::SceneError;

/// Sensor parameters that do not change a still image of glint's.
const SENSOR_HARMLESS: [&str; 4] = ["near_clip", "far_clip", "shutter_open", "shutter_close"];

/// Film parameters that only choose the output file's encoding.
const FILM_HARMLESS: [&str; 7] =
    ["file_format", "pixel_format", "component_format", "banner", "high_quality_edges", "sample_border", "compensate"];

/// Sampler parameters that only change which (equally valid) random points are drawn.
const SAMPLER_HARMLESS: [&str; 2] = ["jitter", "scramble_type"];

/// The settings a Mitsuba scene starts from: the `path` integrator with unlimited
/// depth, the `independent` sampler with 4 samples, a 768×576 `hdrfilm` with a
/// Gaussian filter of standard deviation 0.5, and no ambient light (a Mitsuba scene
/// is lit by its emitters only).
pub(super) fn mitsuba_defaults(s: &mut RenderSettings) {
    s.integrator = IntegratorDesc::Path(PathDesc { sampler: SamplerKind::Independent, ..PathDesc::default() });
    s.spp = Some(4);
    s.width = 768;
    s.height = 576;
    s.filter = gaussian(0.5);
    s.ambient_light = Vec3::ZERO;
    s.background = Vec3::ZERO;
}

/// glint's Gaussian has σ = radius/3, so Mitsuba's σ = `stddev` needs radius 3σ.
fn gaussian(stddev: f32) -> FilterDesc {
    FilterDesc { kind: FilterKind::Gaussian, radius: 3.0 * stddev }
}

/// Reads a `<sensor>` into the camera and the image settings.
pub(super) fn sensor(e: &Elem, scene: &mut SceneDesc) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    if p.ty != "perspective" && p.ty != "thinlens" {
        return Err(p.error(format!("sensor type '{}' is not supported; glint reads perspective and thinlens", p.ty)));
    }
    for f in p.objects("film") {
        film(f, &mut scene.settings)?;
    }
    for s in p.objects("sampler") {
        sampler(s, &mut scene.settings)?;
    }
    let (fov, fov_axis) = field_of_view(&p)?;
    for axis in ["principal_point_offset_x", "principal_point_offset_y"] {
        if p.float_or(axis, 0.0)? != 0.0 {
            return Err(p.param_error(axis, "an off-centre principal point is not supported"));
        }
    }
    let mut camera = camera_frame(&p)?;
    // The angle stays along Mitsuba's axis, so `--width`/`--height` keep its meaning.
    camera.fov_y_degrees = fov;
    camera.fov_axis = fov_axis;
    if p.ty == "thinlens" {
        let need = |name: &str| p.float(name)?.ok_or_else(|| p.error(format!("needs '{name}'")));
        camera.aperture_radius = need("aperture_radius")?;
        camera.focal_distance = need("focus_distance")?;
    }
    scene.camera = camera;
    p.finish(&SENSOR_HARMLESS)
}

/// Mitsuba's field of view in degrees and the axis it spans: `fov` along `fov_axis`
/// (x, y, diagonal, smaller, larger), or a 35 mm `focal_length` (default 50mm) across
/// the film diagonal.
fn field_of_view(p: &Plugin) -> Result<(f32, FovAxis), SceneError> {
    let (fov, axis) = match (p.float("fov")?, p.has("focal_length")) {
        (Some(_), true) => return Err(p.param_error("fov", "give either 'fov' or 'focal_length', not both")),
        (Some(fov), false) => (fov, p.string("fov_axis")?.unwrap_or("x").to_ascii_lowercase()),
        (None, _) => {
            let text = p.string("focal_length")?.unwrap_or("50mm");
            let mm: f32 = text.trim().trim_end_matches("mm").parse().map_err(|_| {
                p.param_error("focal_length", format!("'{text}' is not a length in millimetres (e.g. 50mm)"))
            })?;
            (2.0 * (36f32.hypot(24.0) / (2.0 * mm)).atan().to_degrees(), "diagonal".to_owned())
        }
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(p.param_error("fov", format!("{fov} is not an angle between 0 and 180 degrees")));
    }
    let axis = match axis.as_str() {
        "x" => FovAxis::X,
        "y" => FovAxis::Y,
        "diagonal" => FovAxis::Diagonal,
        "smaller" => FovAxis::Smaller,
        "larger" => FovAxis::Larger,
        other => {
            return Err(p.param_error(
                "fov_axis",
                format!("'{other}' is not an axis; expected x, y, diagonal, smaller or larger"),
            ));
        }
    };
    Ok((fov, axis))
}

/// Eye, look and up from `to_world`: the camera looks along local +z with +y up, and
/// local +x is the image's left, which is glint's `up × look` too; a mirroring matrix
/// would flip the image, so it is refused.
fn camera_frame(p: &Plugin) -> Result<CameraDesc, SceneError> {
    let m = p.transform("to_world")?.unwrap_or_default().matrix();
    if Mat3::from_mat4(m).determinant() <= 0.0 {
        return Err(p.param_error(
            "to_world",
            "the camera transform mirrors (negative determinant); glint would render a mirrored image",
        ));
    }
    let look = m.transform_vector3(Vec3::Z);
    let up = m.transform_vector3(Vec3::Y);
    if look.cross(up).length_squared() == 0.0 {
        return Err(p.param_error("to_world", "the camera's view and up directions are degenerate"));
    }
    Ok(CameraDesc { eye: m.transform_point3(Vec3::ZERO), look, up, ..CameraDesc::default() })
}

/// `hdrfilm`: size and reconstruction filter.
fn film(e: &Elem, s: &mut RenderSettings) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    if p.ty != "hdrfilm" {
        return Err(p.error(format!("film type '{}' is not supported; glint reads hdrfilm", p.ty)));
    }
    let size = |name: &str, default: i64| -> Result<u32, SceneError> {
        let v = p.int(name)?.unwrap_or(default);
        u32::try_from(v)
            .ok()
            .filter(|&v| v > 0)
            .ok_or_else(|| p.param_error(name, format!("{v} is not a positive size")))
    };
    s.width = size("width", 768)?;
    s.height = size("height", 576)?;
    let crop = [("crop_offset_x", 0), ("crop_offset_y", 0), ("crop_width", s.width), ("crop_height", s.height)];
    for (name, full) in crop {
        if p.int(name)?.is_some_and(|v| v != i64::from(full)) {
            return Err(p.param_error(name, "cropped films are not supported"));
        }
    }
    for f in p.objects("rfilter") {
        s.filter = rfilter(f)?;
    }
    p.finish(&FILM_HARMLESS)
}

/// Reconstruction filters with glint equivalents.
fn rfilter(e: &Elem) -> Result<FilterDesc, SceneError> {
    let p = Plugin::open(e)?;
    let filter = match p.ty {
        "box" => FilterDesc { kind: FilterKind::Box, radius: 0.5 },
        "tent" => FilterDesc { kind: FilterKind::Tent, radius: p.float_or("radius", 1.0)? },
        "gaussian" => gaussian(p.float_or("stddev", 0.5)?),
        "mitchell" => {
            let third = 1.0 / 3.0;
            if (p.float_or("B", third)? - third).abs() > 1e-4 || (p.float_or("C", third)? - third).abs() > 1e-4 {
                return Err(p.error("only B = C = 1/3 is supported"));
            }
            FilterDesc { kind: FilterKind::Mitchell, radius: 2.0 }
        }
        "lanczos" => FilterDesc { kind: FilterKind::Lanczos, radius: p.int("lobes")?.unwrap_or(3) as f32 },
        other => {
            return Err(p.error(format!(
                "filter '{other}' is not supported; glint reads box, tent, gaussian, mitchell and lanczos"
            )));
        }
    };
    if !(filter.radius > 0.0 && filter.radius.is_finite()) {
        return Err(p.error("the filter needs a positive size"));
    }
    p.finish(&[])?;
    Ok(filter)
}

/// The sample count, seed and kind of random sequence.
fn sampler(e: &Elem, s: &mut RenderSettings) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    let kind = match p.ty {
        "independent" => SamplerKind::Independent,
        "stratified" | "multijitter" | "ldsampler" | "orthogonal" => SamplerKind::Sobol,
        other => {
            return Err(p.error(format!(
                "sampler '{other}' is not supported; glint reads independent, stratified, multijitter, ldsampler \
                 and orthogonal"
            )));
        }
    };
    let count = p.int("sample_count")?.unwrap_or(4);
    s.spp = Some(
        u32::try_from(count)
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| p.param_error("sample_count", format!("{count} is not a positive number of samples")))?,
    );
    if let Some(seed) = p.int("seed")? {
        s.seed = seed as u32;
    }
    if let IntegratorDesc::Path(path) = &mut s.integrator {
        path.sampler = kind;
    }
    p.finish(&SAMPLER_HARMLESS)
}

/// `path`: unidirectional path tracing with Mitsuba's depth counting.
pub(super) fn integrator(e: &Elem, s: &mut RenderSettings) -> Result<(), SceneError> {
    let p = Plugin::open(e)?;
    if p.ty != "path" {
        return Err(p.error(format!("integrator '{}' is not supported; glint reads path", p.ty)));
    }
    let max_depth = match p.int("max_depth")?.unwrap_or(-1) {
        -1 => u32::MAX,
        d => u32::try_from(d).map_err(|_| p.param_error("max_depth", format!("{d} is not −1 or a depth ≥ 0")))?,
    };
    let rr = p.int("rr_depth")?.unwrap_or(5);
    let rr_depth = u32::try_from(rr)
        .ok()
        .filter(|&d| d > 0)
        .ok_or_else(|| p.param_error("rr_depth", format!("{rr} is not ≥ 1")))?;
    if p.bool_or("hide_emitters", false)? {
        return Err(p.param_error("hide_emitters", "hiding directly visible emitters is not supported"));
    }
    let sampler = match s.integrator {
        IntegratorDesc::Path(old) => old.sampler,
        IntegratorDesc::Whitted => SamplerKind::Independent,
    };
    s.integrator = IntegratorDesc::Path(PathDesc { max_depth, rr_depth, sampler });
    p.finish(&[])
}
