//! NaN and infinite samples never reach the film: each is left out, counted and
//! blamed on the surface whose shading produced it.

use std::sync::atomic::AtomicBool;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::{RenderStats, render};

#[path = "support/poisoned.rs"]
mod poisoned;
use glint_core::scene::RenderScene;
use poisoned::scene;

fn render_scene(scene: &RenderScene) -> (Image, RenderStats) {
    render(scene, &|_, _| {}, &AtomicBool::new(false)).expect("renders")
}

#[test]
fn non_finite_samples_are_left_out_counted_and_blamed() {
    let integrators = [IntegratorDesc::Whitted, IntegratorDesc::Path(PathDesc { max_depth: 2, ..Default::default() })];
    for integrator in integrators {
        for poison in [Vec3::new(f32::NAN, 0.5, 0.5), Vec3::splat(f32::INFINITY)] {
            let bad = scene(poison, integrator);
            let (image, stats) = render_scene(&bad);
            let (control, control_stats) = render_scene(&scene(Vec3::splat(0.5), integrator));
            assert!(control_stats.non_finite.is_empty());
            let what = format!("{integrator:?} {poison}");
            poisoned::assert_left_out_and_blamed(&bad, (&image, &control), &stats.non_finite, &what);
        }
    }
}
