//! Looking inside a render: what the first hit of each pixel looks like (normal,
//! depth, uv, albedo), how much work its ray took, how deep its ray tree went, and the
//! whole ray tree of one pixel with every term of the lighting equation.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use super::camera_sample;
use crate::film::Image;
use crate::integrator::observe::{NoObserver, Observer, RayKind, RayTree};
use crate::integrator::whitted;
use crate::material::NO_TEXTURE;
use crate::math::Ray;
use crate::scene::{Hit, RenderScene};

/// A picture of one property of the scene instead of its light.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DebugView {
    /// The shading normal as a colour: `(n + 1) / 2`.
    Normal,
    /// Distance to the first hit, near white fading to black far away.
    Depth,
    /// Texture coordinates: u red, v green (their fractional parts).
    Uv,
    /// The surface's diffuse colour with its texture.
    Albedo,
    /// Shapes and triangle packets the camera ray is tested against, as a heat map.
    TraversalCost,
    /// How many bounces the deepest ray of the pixel's Whitted tree took, as a heat map.
    RecursionDepth,
}

/// The camera ray through the centre of pixel (`px`, `py`), the ray a render's first
/// sample of a one-sample grid takes.
fn centre_ray(scene: &RenderScene, px: u32, py: u32) -> Ray {
    let s = &scene.settings;
    let (x, y) = ((px as f32 + 0.5) / s.width as f32 * 2.0 - 1.0, 1.0 - (py as f32 + 0.5) / s.height as f32 * 2.0);
    scene.camera.ray(x, y, Vec2::splat(0.5))
}

/// `view` of the whole image, one ray through each pixel's centre, on all cores.
pub fn debug_image(scene: &RenderScene, view: DebugView) -> Image {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let values: Vec<f32> =
        (0..width * height).into_par_iter().map(|i| raw_value(scene, view, i % width, i / width)).collect();
    let most = values.iter().copied().filter(|v| v.is_finite()).fold(0.0f32, f32::max).max(1e-6);
    let pixels = (0..width * height)
        .into_par_iter()
        .map(|i| match view {
            DebugView::Normal | DebugView::Uv | DebugView::Albedo => colour_value(scene, view, i % width, i / width),
            DebugView::Depth => {
                let d = values[i as usize];
                if d.is_finite() { Vec3::splat(1.0 - d / most) } else { Vec3::ZERO }
            }
            DebugView::TraversalCost | DebugView::RecursionDepth => heat(values[i as usize] / most),
        })
        .collect();
    Image { width, height, pixels }
}

/// The number a scalar view shows at a pixel (0 for the colour views).
fn raw_value(scene: &RenderScene, view: DebugView, px: u32, py: u32) -> f32 {
    let ray = centre_ray(scene, px, py);
    match view {
        DebugView::Depth => scene.intersect(&ray, f32::INFINITY).map_or(f32::INFINITY, |h| h.t * ray.dir.length()),
        DebugView::TraversalCost => scene.traversal_cost(&ray) as f32,
        DebugView::RecursionDepth => {
            let mut deepest = Deepest(0);
            let mut ctx = camera_sample(scene, &scene.settings.sampler, px, py, 0).ctx;
            whitted::radiance_observed(scene, &ray, &mut ctx, &mut deepest);
            deepest.0 as f32
        }
        _ => 0.0,
    }
}

/// The colour a colour view shows at a pixel: black where the ray meets nothing.
fn colour_value(scene: &RenderScene, view: DebugView, px: u32, py: u32) -> Vec3 {
    let ray = centre_ray(scene, px, py);
    let Some(hit) = scene.intersect(&ray, f32::INFINITY) else { return Vec3::ZERO };
    match view {
        DebugView::Normal => (hit.normal + Vec3::ONE) * 0.5,
        DebugView::Uv => Vec3::new(hit.uv.x.rem_euclid(1.0), hit.uv.y.rem_euclid(1.0), 0.0),
        _ => albedo(scene, &hit, ray.time),
    }
}

/// The diffuse colour at `hit` (met at `time`), textured as the Whitted integrator
/// textures it.
fn albedo(scene: &RenderScene, hit: &Hit, time: f32) -> Vec3 {
    let m = &scene.materials[hit.material as usize];
    let texel = (scene.settings.features.textures && m.texture != NO_TEXTURE)
        .then(|| scene.texture_at_hit(m.texture, hit, m.texture_repeat, time, scene.settings.footprint_scale));
    m.diffuse_with(texel) * hit.color
}

/// Blue (0) through green and yellow to red (1): a heat map that stays readable.
fn heat(x: f32) -> Vec3 {
    let x = x.clamp(0.0, 1.0);
    let stops =
        [Vec3::new(0.05, 0.1, 0.5), Vec3::new(0.1, 0.7, 0.3), Vec3::new(1.0, 0.85, 0.1), Vec3::new(0.9, 0.1, 0.05)];
    let at = x * (stops.len() - 1) as f32;
    let i = (at as usize).min(stops.len() - 2);
    stops[i].lerp(stops[i + 1], at - i as f32)
}

/// The deepest bounce a ray tree reaches.
struct Deepest(u32);

impl Observer for Deepest {
    fn ray(&mut self, _ray: &Ray, _kind: RayKind, depth: u32, _hit: Option<&Hit>) {
        self.0 = self.0.max(depth);
    }
}

/// The Whitted ray tree of pixel (`px`, `py`)'s first sample — the very rays and random
/// numbers a render with the Whitted integrator traces for it — with every ray's hit
/// and every term of the lighting equation.
pub fn explain_pixel(scene: &RenderScene, px: u32, py: u32) -> RayTree {
    let mut sample = camera_sample(scene, &scene.settings.sampler, px, py, 0);
    let mut tree = RayTree::default();
    whitted::radiance_observed(scene, &sample.ray, &mut sample.ctx, &mut tree);
    tree
}

/// The Whitted value of pixel (`px`, `py`)'s first sample, traced unobserved: what
/// [`explain_pixel`]'s tree must add up to.
pub fn first_sample_value(scene: &RenderScene, px: u32, py: u32) -> Vec3 {
    let mut sample = camera_sample(scene, &scene.settings.sampler, px, py, 0);
    whitted::radiance_observed(scene, &sample.ray, &mut sample.ctx, &mut NoObserver)
}
