//! On the GPU as on the CPU, NaN and infinite samples never reach the film: each is left
//! out, counted and blamed on the surface whose shading produced it.

mod common;

use glam::Vec3;
use glint_core::desc::*;
use glint_core::scene::{RenderScene, compile};
use glint_core::shape::ShapeKind;
use glint_gpu::Progressive;

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// A sphere whose texture holds `texel` (an EXR texture can hold NaN or infinity) in
/// front of a grey plane; the plane's pixels are the control.
fn scene(texel: Vec3, integrator: IntegratorDesc) -> RenderScene {
    let reflectance = ColorParam { value: Vec3::ONE, texture: Some(0) };
    let textured = MaterialDesc {
        texture: Some(0),
        blend: 1.0,
        kd: 1.0,
        bsdf: Some(BsdfDesc::Diffuse { reflectance }),
        ..Default::default()
    };
    let desc = SceneDesc {
        settings: RenderSettings { width: 24, height: 16, integrator, spp: Some(4), ..Default::default() },
        camera: CameraDesc { eye: Vec3::new(0.0, 0.0, 6.0), look: Vec3::NEG_Z, up: Vec3::Y, ..Default::default() },
        lights: vec![LightDesc::Directional { direction: Vec3::new(-1.0, -1.0, -1.0), color: Vec3::ONE }],
        materials: vec![MaterialDesc { diffuse: Vec3::splat(0.5), ..Default::default() }, textured],
        textures: vec![TextureDesc::Image {
            name: "bad".into(),
            path: "bad.exr".into(),
            width: 1,
            height: 1,
            texels: vec![texel],
            sampling: Default::default(),
        }],
        objects: vec![
            node(
                ShapeDesc::Plane,
                0,
                vec![
                    TransformOp::Rotate { axis: Vec3::X, degrees: 90.0 },
                    TransformOp::Translate(Vec3::new(0.0, 0.0, -2.0)),
                ],
            ),
            node(ShapeDesc::Sphere, 1, vec![]),
        ],
        meshes: vec![],
        views: vec![],
    };
    compile(&desc).expect("valid scene")
}

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
            assert!(image.pixels.iter().all(|p| p.is_finite()), "{integrator:?} {poison}: a pixel is not finite");

            let sources = film.non_finite().expect("reads back").by_source();
            assert_eq!(sources.len(), 1, "{integrator:?} {poison}: {sources:?}");
            let (source, tally) = sources[0];
            let source = source.expect("blamed on a surface");
            assert_eq!(bad.instances[source.instance as usize].shape.kind, ShapeKind::Sphere);
            assert_eq!(source.material, 1);
            let samples = (24 * 16 * 4) as u64;
            assert!(tally.count > samples / 30 && tally.count < samples / 5, "{} of {samples}", tally.count);
            let (x, y) = tally.example_pixel;
            assert!((6..18).contains(&x) && (2..14).contains(&y), "example pixel {x},{y} is off the sphere");
            // Where no sample was poisoned the pixel is the control's, bit for bit.
            assert_eq!(image.get(0, 0), control.get(0, 0));
            assert_eq!(image.get(23, 15), control.get(23, 15));
        }
    }
}
