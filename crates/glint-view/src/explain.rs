//! A pixel's ray tree as text: every ray with its origin, direction, the distance t to
//! what it hit, the object and material there, its shadow rays and each term of the
//! lecture's lighting equation it added — what a student checks by hand.

use std::fmt::Write;

use glam::Vec3;
use glint_core::desc::SceneDesc;
use glint_core::integrator::observe::{RayKind, RayRecord, RayTree};
use glint_core::scene::RenderScene;

/// The tree of pixel (`x`, `y`), one ray per paragraph, indented by depth.
pub fn describe(tree: &RayTree, (x, y): (u32, u32), scene: &RenderScene, desc: &SceneDesc) -> String {
    let mut text = format!("pixel ({x}, {y}): colour {}\n", v(tree.color()));
    for (index, ray) in tree.rays.iter().enumerate() {
        describe_ray(&mut text, index, ray, scene, desc);
    }
    text
}

fn describe_ray(text: &mut String, index: usize, ray: &RayRecord, scene: &RenderScene, desc: &SceneDesc) {
    let pad = "  ".repeat(ray.depth as usize);
    let parent = ray.parent.map(|p| format!(" of #{p}")).unwrap_or_default();
    let _ = writeln!(
        text,
        "{pad}#{index} {} ray{parent}, depth {}: origin {} dir {}",
        kind_name(ray.kind),
        ray.depth,
        v(ray.origin),
        v(ray.dir)
    );
    match &ray.hit {
        None => {
            let _ = writeln!(text, "{pad}   misses: background {}", v(ray.color));
        }
        Some(hit) => {
            let _ = writeln!(
                text,
                "{pad}   hits {} at t = {:.4}, point {}, normal {}, material {}",
                object_name(scene, hit.instance),
                hit.distance,
                v(hit.point),
                v(hit.normal),
                material_name(desc, hit.material),
            );
        }
    }
    for shadow in &ray.shadow_rays {
        let verdict = if shadow.filter == Vec3::ZERO { "blocked" } else { "lit" };
        let _ = writeln!(
            text,
            "{pad}   shadow ray from {} dir {} to the light at t = {:.4}: {verdict}, filter {}",
            v(shadow.origin),
            v(shadow.dir),
            shadow.distance,
            v(shadow.filter)
        );
    }
    for (name, value) in &ray.terms {
        let _ = writeln!(text, "{pad}   + {name} {}", v(*value));
    }
    let _ = writeln!(text, "{pad}   = {}", v(ray.color));
}

/// How the viewer names each kind of ray.
pub fn kind_name(kind: RayKind) -> &'static str {
    match kind {
        RayKind::Camera => "camera",
        RayKind::Reflected => "reflected",
        RayKind::Refracted => "refracted",
        RayKind::TotalInternalReflection => "totally internally reflected",
    }
}

/// "sphere #3": the shape kind and the instance's index.
pub fn object_name(scene: &RenderScene, instance: u32) -> String {
    match scene.instances.get(instance as usize) {
        Some(i) => format!("{:?} #{instance}", i.shape.kind).to_lowercase(),
        None => format!("object #{instance}"),
    }
}

/// The material's name in the scene file, or its number when it has none.
pub fn material_name(desc: &SceneDesc, material: u32) -> String {
    match desc.materials.get(material as usize).map(|m| m.name.as_str()) {
        Some(name) if !name.is_empty() => format!("'{name}'"),
        _ => format!("#{material}"),
    }
}

/// A vector with four decimals.
fn v(value: Vec3) -> String {
    format!("[{:.4} {:.4} {:.4}]", value.x, value.y, value.z)
}
