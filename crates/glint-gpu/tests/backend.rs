//! The GPU renders the same image as the CPU. Both backends draw the same samples from
//! the same 32-bit sampler and trace the same paths, so path-traced images agree pixel
//! by pixel, up to the rare path that f32 rounding (the GPU has no f64 fallback, and
//! may fuse multiply-adds) sends another way.

mod common;

use common::*;
use glint_core::desc::{IntegratorDesc, PathDesc};

const ROOM: &str = r#"
settings { width 8 height 8 integrator path { max_depth 6 } background 0 }
camera { eye [0 1 3.6] look_at [0 0.9 0] fov 45 }
material "white" { bsdf diffuse { reflectance [0.7 0.7 0.65] } }
material "red" { bsdf diffuse { reflectance [0.6 0.1 0.1] } }
rectangle { material "white" scale 3 }
rectangle { material "red" scale 3 rotate [1 0 0] 90 translate [0 1 -1.5] }
"#;

/// Every primitive the GPU intersects, lit by an emissive rectangle and a point light.
const SHAPES: &str = r#"
material "lamp" { bsdf diffuse { reflectance 0 } emission [6 6 5] two_sided false }
rectangle { material "lamp" scale 0.5 rotate [1 0 0] 180 translate [0 2.6 0.3] }
light point { position [1.5 2 2] color [2 2 2] }
sphere { material "white" scale 0.35 translate [-1.1 0.35 0] }
cube { material "red" scale 0.3 rotate [0 1 0] 30 translate [-0.3 0.3 -0.4] }
cylinder { material "white" scale [0.25 0.4 0.25] translate [0.4 0.4 0] }
cone { material "red" scale [0.3 0.4 0.3] translate [1.1 0.4 -0.2] }
disk { material "white" scale 0.3 rotate [1 0 0] 60 translate [-0.6 1.3 -0.5] }
torus { minor_radius 0.25 material "white" rotate [1 0 0] 50 scale 0.3 translate [-0.2 1.6 0] }
quadric { coefficients [1 -0.25 1 0 0 0 0 0 0 -0.16] bounds [-1 -1 -1] [1 1 1] material "red" scale 0.3 translate [0.8 1.3 0.2] }
plane { material "white" translate [0 -0.01 0] }
mesh_instance "ball" { material "red" scale 0.3 translate [0.2 1.3 -0.6] }
material "ghost" { bsdf diffuse { reflectance [0.6 0.5 0.2] } casts_shadows false }
sphere { material "ghost" scale 0.25 translate [0.9 1.5 0.6] }
superellipsoid { material "red" exponents [0.3 0.3] scale 0.22 rotate [0 1 0] 30 translate [-1.2 1.2 0.3] }
superellipsoid { material "white" exponents [2.5 2.5] scale 0.3 translate [1.4 1.1 0.5] }
"#;

/// Every BSDF kind, textured parameters, and a Phong material read as a BSDF.
const BSDFS: &str = r#"
material "lamp" { bsdf diffuse { reflectance 0 } emission [5 5 5] }
sphere { material "lamp" scale 0.3 translate [0 2.4 0.8] }
light directional { direction [-1 -2 -1] color [0.8 0.8 0.7] }
texture "checks" checker { even [0.9 0.8 0.2] odd [0.1 0.2 0.7] cells [4 4] }
material "smooth_metal" { bsdf conductor { eta [0.2 0.4 1.4] k [3.9 2.4 1.6] } }
material "rough_metal" { bsdf conductor { eta [0.2 0.9 1.1] k [3.9 2.5 2.2] roughness 0.25 } }
material "beckmann" { bsdf conductor { roughness 0.3 } microfacet "beckmann" }
material "glass" { bsdf dielectric { ior 1.5 } }
material "frosted" { bsdf dielectric { ior 1.33 roughness 0.2 } }
material "pane" { bsdf thin_dielectric { ior 1.5 } }
material "plastic" { bsdf plastic { diffuse [0.1 0.5 0.2] } }
material "rough_plastic" { bsdf plastic { texture "checks" roughness 0.15 nonlinear true } }
material "textured" { bsdf diffuse { texture "checks" } }
material "phong" { diffuse [0.6 0.3 0.2] specular 0.3 shininess 40 reflective 0.2 }
material "paint" { bsdf metallic_roughness { base [0.8 0.3 0.1] metallic 0.4 roughness 0.2 } }
material "mottled" { bsdf metallic_roughness { texture "checks" metallic_texture "checks" } }
sphere { material "paint" scale 0.25 translate [-0.9 1.7 0] }
sphere { material "mottled" scale 0.25 translate [0.9 1.7 0] }
sphere { material "smooth_metal" scale 0.3 translate [-1.2 0.3 0] }
sphere { material "rough_metal" scale 0.3 translate [-0.6 0.3 0] }
sphere { material "beckmann" scale 0.3 translate [0 0.3 0] }
sphere { material "glass" scale 0.3 translate [0.6 0.3 0] }
sphere { material "frosted" scale 0.3 translate [1.2 0.3 0] }
rectangle { material "pane" scale 0.3 rotate [1 0 0] 90 translate [-0.9 1.1 0.3] }
sphere { material "plastic" scale 0.3 translate [-0.3 1.1 0] }
cube { material "rough_plastic" scale 0.25 rotate [1 1 0] 40 translate [0.3 1.1 0] }
sphere { material "textured" scale 0.3 translate [0.9 1.1 0] }
sphere { material "phong" scale 0.25 translate [0 1.7 0] }
"#;

/// Every emitter: emissive sphere, disk, cube and mesh; point, spot and directional
/// lights; and a constant environment.
const EMITTERS: &str = r#"
material "warm" { bsdf diffuse { reflectance 0 } emission [4 2 1] }
material "cool" { bsdf diffuse { reflectance 0 } emission [1 2 4] two_sided false }
sphere { material "warm" scale 0.15 translate [-1 1.6 0] }
disk { material "cool" scale 0.3 rotate [1 0 0] 180 translate [0.8 2 0] }
cube { material "warm" scale 0.1 translate [0 0.1 0.5] }
mesh_instance "ball" { material "cool" scale 0.12 translate [-0.5 0.5 0.6] }
light spot { position [0 2.5 1] direction [0 -1 -0.3] angle 25 penumbra 8 color [5 5 5] }
light point { position [-1 1 2] color [0.5 0.5 0.5] }
light directional { direction [1 -1 -1] color [0.3 0.3 0.3] }
light environment { radiance [0.2 0.25 0.3] }
sphere { material "white" scale 0.35 translate [0.3 0.35 0] }
texture "screen" checker { even [1 0.9 0.2] odd [0.1 0.3 1] cells [3 2] }
material "sign" { bsdf diffuse { reflectance 0.2 } emission [3 3 3] emission_texture "screen" }
rectangle { material "sign" scale [0.4 1 0.25] rotate [1 0 0] 90 translate [-0.3 1.2 -1.2] }
"#;

fn with_ball(scene: &str) -> String {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meshes/icosphere.obj");
    format!("{ROOM}\nmesh \"ball\" {{ file \"{mesh}\" }}\n{scene}")
}

#[test]
fn every_primitive_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    check("shapes", &scene(&with_ball(SHAPES), 40, 40, 8), &gpu);
}

#[test]
fn every_bsdf_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    check("bsdfs", &scene(&with_ball(BSDFS), 48, 40, 8), &gpu);
}

#[test]
fn every_emitter_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    check("emitters", &scene(&with_ball(EMITTERS), 40, 40, 8), &gpu);
}

#[test]
fn vertex_colours_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let source = with_ball(
        "light point { position [1.5 2 2] color [2 2 2] }\n\
         material \"gold\" { bsdf conductor { roughness 0.2 } }\n\
         mesh_instance \"ball\" { material \"white\" scale 0.5 translate [-0.5 0.5 0] }\n\
         mesh_instance \"ball\" { material \"gold\" scale 0.4 translate [0.6 0.4 0.2] }\n",
    );
    check("vertex colours", &painted_scene(&source, 40, 32, Some(8)), &gpu);
}

#[test]
fn an_environment_map_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let map = concat!(env!("CARGO_MANIFEST_DIR"), "/../../bench/mitsuba/assets/envmap.exr");
    let source = format!(
        "{ROOM}\ntexture \"sky\" image {{ file \"{map}\" }}\n\
         light environment {{ texture \"sky\" radiance 1.2 rotate [0 1 0] 30 }}\n\
         material \"metal\" {{ bsdf conductor {{ roughness 0.1 }} }}\n\
         sphere {{ material \"metal\" scale 0.4 translate [0.5 0.4 0] }}\n\
         sphere {{ material \"white\" scale 0.4 translate [-0.5 0.4 0] }}\n"
    );
    check("envmap", &scene(&source, 40, 32, 8), &gpu);
}

#[test]
fn wide_filters_and_independent_samples_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let mut s = scene(&with_ball(SHAPES), 32, 32, 6);
    s.settings.filter = glint_core::sampling::Filter::new(glint_core::sampling::FilterKind::Gaussian, 1.5).unwrap();
    check("gaussian 1.5", &s, &gpu);
    let mut s = scene(&with_ball(SHAPES), 32, 32, 6);
    s.settings.filter = glint_core::sampling::Filter::new(glint_core::sampling::FilterKind::Mitchell, 2.0).unwrap();
    if let IntegratorDesc::Path(p) = &mut s.settings.integrator {
        p.sampler = glint_core::desc::SamplerKind::Independent;
    }
    check("mitchell 2, independent", &s, &gpu);
}

/// The repository's example scenes, path traced (Whitted scenes through the Phong
/// mapping), where the GPU renders all they contain.
#[test]
fn example_scenes_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let names = example_scene_names();
    let mut rendered = Vec::new();
    for name in &names {
        let mut s = scene_file(name, 32, 24, 4);
        if let IntegratorDesc::Whitted = s.settings.integrator {
            s.settings.integrator = IntegratorDesc::Path(PathDesc { max_depth: 5, ..PathDesc::default() });
        }
        s.settings.adaptive = None;
        if let Some(why) = glint_gpu::upload::beyond_adapter(&gpu, &s) {
            eprintln!("{name}: not on this GPU ({why})");
            continue;
        }
        check(name, &s, &gpu);
        rendered.push(name.clone());
    }
    for expected in ["cornell-path.glint", "cornell-whitted.glint", "default.glint", "mesh-instances.glint"] {
        assert!(rendered.iter().any(|n| n == expected), "{expected} was not compared: {rendered:?}");
    }
}

/// Implicit surfaces and superellipsoids render as on the CPU where the driver lets a
/// kernel loop as long as they need; lavapipe, which stops a kernel's loops after
/// 65 535 iterations in all, refuses implicit scenes in one sentence instead of
/// drawing wrong pixels.
#[test]
fn implicit_surfaces_match_the_cpu_or_are_refused_where_loops_are_capped() {
    let Some(gpu) = gpu() else { return };
    let scene = scene_file("implicit.glint", 32, 24, 2);
    if gpu.caps_loop_iterations() {
        let Err(e) = glint_gpu::Progressive::new(&gpu, &scene) else { panic!("a capped driver must refuse") };
        let message = e.to_string();
        assert!(message.contains("65535 iterations") && message.contains("--device cpu"), "{message}");
        eprintln!("SKIPPED the comparison: {message}");
        return;
    }
    check("implicit surfaces", &scene, &gpu);
}
