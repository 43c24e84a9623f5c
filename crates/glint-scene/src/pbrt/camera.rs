//! `Camera`, `Film`, `Sampler`, `Integrator` and `PixelFilter`: the camera and the
//! render settings.
//!
//! pbrt's `fov` spans the shorter image axis (glint's [`FovAxis::Smaller`]); its
//! `maxdepth` counts bounces (0: emitters seen directly, 1: direct lighting) where
//! glint's [`PathDesc::max_depth`] counts as Mitsuba does (1: emitters, 2: direct), so
//! glint's depth is pbrt's plus one.

use glam::{Mat3, Mat4, Vec3};
use glint_core::desc::{CameraDesc, FilterDesc, FilterKind, FovAxis, IntegratorDesc, PathDesc, SamplerKind, SceneDesc};

use super::Reader;
use super::params::Params;
use crate::error::SceneError;

/// The settings a pbrt scene starts from: a 1280×720 film, 16 samples per pixel, the
/// path tracer with `maxdepth` 5, pbrt-v4's Gaussian filter (radius 1.5, σ 0.5), a
/// 90° perspective camera and no ambient light.
pub(super) fn pbrt_defaults(scene: &mut SceneDesc) {
    let s = &mut scene.settings;
    s.width = 1280;
    s.height = 720;
    s.spp = Some(16);
    s.integrator = IntegratorDesc::Path(PathDesc { max_depth: 6, ..PathDesc::default() });
    s.filter = FilterDesc { kind: FilterKind::Gaussian, radius: 1.5 };
    s.ambient_light = Vec3::ZERO;
    s.background = Vec3::ZERO;
    scene.camera = CameraDesc { fov_y_degrees: 90.0, fov_axis: FovAxis::Smaller, ..CameraDesc::default() };
    place(&mut scene.camera, Mat4::IDENTITY, true);
}

/// Whether glint must mirror the world to show pbrt's image: pbrt's image right is the
/// camera's +x, glint's is `look × up`; they agree only when `world_from_camera`
/// reverses handedness.
pub(super) fn needs_mirror(world_from_camera: Mat4) -> bool {
    Mat3::from_mat4(world_from_camera).determinant() > 0.0
}

/// Eye, look and up of glint's camera from pbrt's `world_from_camera` (in the
/// mirrored world when `mirror`).
pub(super) fn place(camera: &mut CameraDesc, world_from_camera: Mat4, mirror: bool) {
    let s = if mirror { Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)) } else { Mat4::IDENTITY };
    let m = s * world_from_camera;
    camera.eye = m.transform_point3(Vec3::ZERO);
    camera.look = m.transform_vector3(Vec3::Z);
    camera.up = m.transform_vector3(Vec3::Y);
}

/// `Camera "perspective"`: the view angle and the thin lens; other projections are
/// rendered as perspective with a warning.
pub(super) fn camera(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    if ty != "perspective" {
        r.warnings.push(p.warning("only the perspective camera is supported; rendering a perspective view"));
    }
    let fov = p.float_or("fov", 90.0)?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(p.error(format!("fov {fov} is not an angle between 0 and 180 degrees")));
    }
    let cam = &mut r.scene.camera;
    cam.fov_y_degrees = fov;
    cam.fov_axis = FovAxis::Smaller;
    let lens = p.float_or("lensradius", 0.0)?;
    if lens < 0.0 {
        return Err(p.error("lensradius must not be negative"));
    }
    cam.aperture_radius = lens;
    cam.focal_distance = p.float_or("focaldistance", 1e6)?;
    if cam.focal_distance <= 0.0 {
        return Err(p.error("focaldistance must be positive"));
    }
    for ignored in ["screenwindow", "frameaspectratio", "shutteropen", "shutterclose"] {
        if p.has(ignored) {
            p.get(ignored);
            r.warnings.push(p.warning(format!("\"{ignored}\" is not supported and is ignored")));
        }
    }
    Ok(())
}

/// `Film`: the image size (the output name comes from glint's command line).
pub(super) fn film(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    if !matches!(ty, "rgb" | "gbuffer" | "spectral" | "image") {
        r.warnings.push(p.warning("unknown film type; reading its resolution only"));
    }
    let size = |name: &str, default: i64| -> Result<u32, SceneError> {
        let v = p.int(name)?.unwrap_or(default);
        u32::try_from(v).ok().filter(|&v| v > 0).ok_or_else(|| p.error(format!("{name} {v} is not a positive size")))
    };
    r.scene.settings.width = size("xresolution", 1280)?;
    r.scene.settings.height = size("yresolution", 720)?;
    for harmless in ["filename", "savefp16", "iso", "whitebalance", "exposuretime", "sensor", "maxcomponentvalue"] {
        p.get(harmless);
    }
    if p.has("cropwindow") || p.has("pixelbounds") {
        p.get("cropwindow");
        p.get("pixelbounds");
        r.warnings.push(p.warning("crop windows are not supported; the whole image is rendered"));
    }
    Ok(())
}

/// `Sampler`: the number of samples per pixel; the independent sampler keeps its kind,
/// every stratified or low-discrepancy one becomes glint's Sobol sampler.
pub(super) fn sampler(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    let kind = if ty == "independent" { SamplerKind::Independent } else { SamplerKind::Sobol };
    let n = p.int("pixelsamples")?.unwrap_or(16);
    let n =
        u32::try_from(n).ok().filter(|&n| n > 0).ok_or_else(|| p.error(format!("pixelsamples {n} is not positive")))?;
    r.scene.settings.spp = Some(n);
    if let Some(seed) = p.int("seed")? {
        r.scene.settings.seed = seed as u32;
    }
    for harmless in ["randomization", "jitter", "xsamples", "ysamples"] {
        p.get(harmless);
    }
    if let IntegratorDesc::Path(path) = &mut r.scene.settings.integrator {
        path.sampler = kind;
    }
    Ok(())
}

/// `Integrator`: glint path-traces; `path` and `volpath` map exactly (without media),
/// others are rendered with the path tracer and a warning.
pub(super) fn integrator(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    if !matches!(ty, "path" | "volpath") {
        r.warnings.push(p.warning("rendered with glint's path tracer instead"));
    }
    let depth = p.int("maxdepth")?.unwrap_or(5);
    let depth = u32::try_from(depth).map_err(|_| p.error(format!("maxdepth {depth} must not be negative")))?;
    for harmless in ["regularize", "lightsampler"] {
        p.get(harmless);
    }
    let sampler = match r.scene.settings.integrator {
        IntegratorDesc::Path(old) => old.sampler,
        IntegratorDesc::Whitted => SamplerKind::Sobol,
    };
    r.scene.settings.integrator =
        IntegratorDesc::Path(PathDesc { max_depth: depth.saturating_add(1), sampler, ..PathDesc::default() });
    Ok(())
}

/// `PixelFilter`: box, gaussian, mitchell, lanczos (sinc) and triangle; glint's filters
/// are round, so pbrt's x and y radii are averaged.
pub(super) fn filter(r: &mut Reader, ty: &str, p: &Params) -> Result<(), SceneError> {
    let radius = |default: f32| -> Result<f32, SceneError> {
        Ok(0.5 * (p.float_or("xradius", default)? + p.float_or("yradius", default)?))
    };
    let filter = match ty {
        "box" => FilterDesc { kind: FilterKind::Box, radius: radius(0.5)? },
        "gaussian" => {
            radius(1.5)?;
            FilterDesc { kind: FilterKind::Gaussian, radius: 3.0 * p.float_or("sigma", 0.5)? }
        }
        "mitchell" => {
            p.get("B");
            p.get("C");
            FilterDesc { kind: FilterKind::Mitchell, radius: radius(2.0)? }
        }
        "sinc" | "lanczos" => {
            p.get("tau");
            FilterDesc { kind: FilterKind::Lanczos, radius: radius(4.0)? }
        }
        "triangle" => FilterDesc { kind: FilterKind::Tent, radius: radius(2.0)? },
        other => {
            r.warnings.push(p.warning(format!("filter '{other}' is not supported; keeping the default")));
            return Ok(());
        }
    };
    if !(filter.radius > 0.0 && filter.radius.is_finite()) {
        return Err(p.error("the filter needs a positive radius"));
    }
    r.scene.settings.filter = filter;
    Ok(())
}
