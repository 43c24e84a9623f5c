//! A scene whose sphere wears a one-texel texture of any value (an EXR texture can hold
//! NaN or infinity) in front of a grey plane: the non-finite tests of the CPU and of
//! the GPU (which includes this file by path) render it.

use glam::Vec3;
use glint_core::desc::*;
use glint_core::film::Image;
use glint_core::render::NonFiniteSamples;
use glint_core::scene::{RenderScene, compile};
use glint_core::shape::ShapeKind;

fn node(shape: ShapeDesc, material: usize, transform: Vec<TransformOp>) -> NodeDesc {
    NodeDesc { transform, kind: NodeKind::Shape { shape, material }, origin: String::new() }
}

/// A sphere whose texture holds `texel` (an EXR texture can hold NaN or infinity)
/// in front of a grey plane; the plane's pixels are the control.
pub fn scene(texel: Vec3, integrator: IntegratorDesc) -> RenderScene {
    // Whitted reads the Phong texture; the path tracer the BSDF's.
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

/// The render of `bad` (`image`, next to the `control` render of a finite texel) left
/// its poisoned samples out, and `non_finite` counts them, blamed on the sphere.
pub fn assert_left_out_and_blamed(
    bad: &RenderScene,
    (image, control): (&Image, &Image),
    non_finite: &NonFiniteSamples,
    what: &str,
) {
    assert!(image.pixels.iter().all(|p| p.is_finite()), "{what}: a pixel is not finite");
    let sources = non_finite.by_source();
    assert_eq!(sources.len(), 1, "{what}: {sources:?}");
    let (source, tally) = sources[0];
    let source = source.expect("blamed on a surface");
    assert_eq!(bad.instances[source.instance as usize].shape.kind, ShapeKind::Sphere);
    assert_eq!(source.material, 1);
    // The sphere covers the middle of the image: some 7% of its samples.
    let samples = (24 * 16 * 4) as u64;
    assert!(tally.count > samples / 30 && tally.count < samples / 5, "{what}: {} of {samples}", tally.count);
    let (x, y) = tally.example_pixel;
    assert!((6..18).contains(&x) && (2..14).contains(&y), "{what}: example pixel {x},{y} is off the sphere");
    // Where no sample was poisoned the pixel is the control's, bit for bit.
    assert_eq!(image.get(0, 0), control.get(0, 0));
    assert_eq!(image.get(23, 15), control.get(23, 15));
}
