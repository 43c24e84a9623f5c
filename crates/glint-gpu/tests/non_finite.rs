//! On the GPU as on the CPU, NaN and infinite samples never reach the film: each is left
//! out, counted and blamed on the surface whose shading produced it.

mod common;
#[path = "../../glint-core/tests/support/poisoned.rs"]
mod poisoned;

use glam::Vec3;
use glint_core::desc::{IntegratorDesc, PathDesc};
use glint_gpu::Progressive;
use poisoned::scene;

#[test]
fn non_finite_samples_are_left_out_counted_and_blamed_on_the_gpu() {
    let Some(gpu) = common::gpu() else { return };
    let integrators = [IntegratorDesc::Whitted, IntegratorDesc::Path(PathDesc { max_depth: 2, ..Default::default() })];
    for integrator in integrators {
        let good = scene(Vec3::splat(0.5), integrator);
        let mut control = Progressive::new(&gpu, &good).expect("uploads");
        control.add_samples(4).expect("renders");
        assert!(control.non_finite().expect("reads back").is_empty());
        let control = control.image().expect("reads back");
        for poison in [Vec3::new(f32::NAN, 0.5, 0.5), Vec3::splat(f32::INFINITY)] {
            let bad = scene(poison, integrator);
            let mut film = Progressive::new(&gpu, &bad).expect("uploads");
            film.add_samples(4).expect("renders");
            let image = film.image().expect("reads back");
            let what = format!("{integrator:?} {poison}");
            let non_finite = film.non_finite().expect("reads back");
            poisoned::assert_left_out_and_blamed(&bad, (&image, &control), &non_finite, &what);
        }
    }
}
