//! Compiling the path tracer's light: area emitters on emissive instances, the lights
//! of the description, the environment, and the power-proportional choice among them.

use glam::{Mat3, Vec3};

use super::{CompileError, Instance, invalid, node_transform};
use crate::bsdf::Bsdf;
use crate::desc::{LightDesc, SceneDesc, TextureDesc};
use crate::emitter::{Emitter, EmitterKind, Environment, emitters_of_instances};
use crate::math::Aabb;
use crate::mesh::Mesh;
use crate::sampling::Distribution1D;

/// The compiled light of a scene.
pub(super) struct Lighting {
    pub emitters: Vec<Emitter>,
    pub instance_emitters: Vec<u32>,
    pub selection: Option<Distribution1D>,
    pub environment: Option<Environment>,
    pub environment_emitter: u32,
}

pub(super) fn compile(
    desc: &SceneDesc,
    instances: &[Instance],
    meshes: &[Mesh],
    bsdfs: &[Bsdf],
    bounds: Aabb,
) -> Result<Lighting, CompileError> {
    let (mut emitters, instance_emitters) = emitters_of_instances(instances, meshes, bsdfs);
    emitters.extend(desc.lights.iter().filter_map(Emitter::from_light));
    let environment = environment(desc)?;
    let mut environment_emitter = u32::MAX;
    if environment.is_some() {
        environment_emitter = emitters.len() as u32;
        emitters.push(Emitter { kind: EmitterKind::Environment, ..emitters_template() });
    }
    let radius = if bounds.is_finite() && bounds.min.cmple(bounds.max).all() {
        (0.5 * (bounds.max - bounds.min).length()).max(1e-3)
    } else {
        1.0
    };
    let powers: Vec<f32> = emitters.iter().map(|e| e.power(radius, environment.as_ref())).collect();
    if powers.iter().any(|p| !p.is_finite()) {
        return Err(invalid("lights", "an emitter's power is not finite"));
    }
    let powers = powers.into_iter().map(|p| p.max(0.0)).collect();
    Ok(Lighting {
        selection: Distribution1D::new(powers),
        emitters,
        instance_emitters,
        environment,
        environment_emitter,
    })
}

fn emitters_template() -> Emitter {
    Emitter::from_light(&LightDesc::Directional { direction: Vec3::NEG_Y, color: Vec3::ZERO })
        .expect("a directional light always compiles")
}

/// The one environment light of the scene, if any.
fn environment(desc: &SceneDesc) -> Result<Option<Environment>, CompileError> {
    let mut found = desc.lights.iter().filter_map(|l| match l {
        LightDesc::Environment(env) => Some(env),
        _ => None,
    });
    let Some(env) = found.next() else {
        // A background colour is a constant sky: sampled like one, seen the same.
        let background = desc.settings.background;
        let sky = background.max_element() > 0.0 && background.min_element() >= 0.0;
        return Ok(sky.then(|| Environment::new(background, Vec::new(), 0, 0, Mat3::IDENTITY)));
    };
    if found.next().is_some() {
        return Err(invalid("lights", "a scene can have at most one environment light"));
    }
    if !env.radiance.is_finite() || env.radiance.min_element() < 0.0 {
        return Err(invalid("environment light", "radiance must be finite and non-negative"));
    }
    let m = node_transform(&env.transform, "environment light")?.world_from_object;
    // Only the rotation matters: normalize the columns, then re-orthogonalize.
    let x = m.x_axis.truncate().normalize_or(Vec3::X);
    let y = m.y_axis.truncate();
    let z = x.cross(y).normalize_or(Vec3::Z);
    let rotation = Mat3::from_cols(x, z.cross(x), z);
    let Some(index) = env.texture else {
        return Ok(Some(Environment::new(env.radiance, Vec::new(), 0, 0, rotation)));
    };
    match desc.textures.get(index) {
        Some(TextureDesc::Image { width, height, texels, .. })
            if *height >= 2 && *width >= 1 && texels.len() == *width as usize * *height as usize =>
        {
            if texels.iter().any(|t| !t.is_finite()) {
                return Err(invalid("environment light", "the map has non-finite texels"));
            }
            Ok(Some(Environment::new(env.radiance, texels.clone(), *width as usize, *height as usize, rotation)))
        }
        Some(_) => Err(invalid(
            "environment light",
            "the map must be an image at least 2 pixels high with width × height texels",
        )),
        None => Err(invalid("environment light", format!("texture index {index} out of range"))),
    }
}
