//! The GPU renders the Whitted integrator as the CPU does: the same pixel patterns, the
//! same 32-bit random stream drawn in the same depth-first order (lens, then every
//! light's jitter at every hit), the same shadow, reflection and refraction rays. Images
//! agree pixel by pixel up to f32 rounding.

mod common;

use common::*;
use glint_core::desc::IntegratorDesc;
use glint_core::sampling::{PixelSampler, SamplePattern};
use glint_core::scene::RenderScene;

/// A floor and a back wall; each test adds lights and objects.
const ROOM: &str = r#"
settings { max_depth 5 background [0.1 0.12 0.2] ambient 0.08 samples 2 }
camera { eye [0 1.2 4] look_at [0 0.8 0] fov 45 }
material "white" { diffuse 0.75 specular 0.1 shininess 10 reflective 0 }
material "red" { diffuse [0.7 0.15 0.1] specular 0.3 shininess 30 reflective 0.05 }
material "clay" { diffuse [0.3 0.5 0.7] specular 0.4 shininess 60 reflective 0 }
material "mirror" { diffuse 0.03 specular 0.9 shininess 200 reflective 0.85 }
material "glass" { diffuse 0 specular 1 shininess 300 transmissive 0.9 ior 1.5 reflective 0.08 }
texture "tiles" checker { even [0.9 0.8 0.2] odd [0.1 0.2 0.7] cells [4 4] }
material "tiled" { diffuse 0.8 texture "tiles" blend 0.7 repeat [2 3] specular 0.2 shininess 20 reflective 0 }
rectangle { material "white" scale 3 }
rectangle { material "red" scale 3 rotate [1 0 0] 90 translate [0 1 -1.5] }
"#;

/// Every kind of light: attenuated point, directional, smooth and linear spots, and the
/// rectangle, disk and sphere area lights with their stratified jitter.
const LIGHTS: &str = r#"
light point { position [1.5 2.5 2] color [0.5 0.5 0.45] attenuation [1 0.1 0.05] }
light directional { direction [-1 -2 -0.5] color [0.25 0.25 0.3] }
light spot { position [-1 2.5 1] direction [0.3 -1 -0.3] angle 30 penumbra 10 color [0.6 0.5 0.4] }
light spot { position [1 2 0.5] direction [-0.2 -1 -0.4] angle 20 penumbra 15 falloff "linear" color [0.3 0.4 0.6] }
light rectangle { corner [-0.5 2.8 -0.5] edge_u [1 0 0] edge_v [0 0 1] color 0.4 samples 3 }
light disk { position [0.8 2.2 1.2] normal [0 -1 0] radius 0.3 color [0.3 0.2 0.1] attenuation [1 0 0.1] samples 2 }
light sphere { position [-1.5 1.8 1.5] radius 0.25 color [0.2 0.3 0.2] samples 2 }
sphere { material "clay" scale 0.35 translate [-0.8 0.35 0] }
cube { material "red" scale 0.3 rotate [0 1 0] 30 translate [0.2 0.3 -0.5] }
cylinder { material "white" scale [0.2 0.5 0.2] translate [0.9 0.5 0.1] }
cone { material "clay" scale [0.25 0.4 0.25] translate [-0.2 0.4 0.7] }
mesh_instance "ball" { material "clay" scale 0.3 translate [0.6 0.3 0.9] }
"#;

/// A mirror sphere, a glass sphere, a glass cube turned so rays inside meet its side
/// faces beyond the critical angle (total internal reflection), and a pane of ior 1
/// that rays cross unbent.
const OPTICS: &str = r#"
light point { position [1 2.5 2.5] color 0.9 }
light directional { direction [0.5 -1 -0.3] color 0.3 }
material "pane" { diffuse 0 specular 0 transmissive [0.7 0.8 0.6] ior 1 reflective 0 }
sphere { material "mirror" scale 0.45 translate [-0.9 0.45 -0.3] }
sphere { material "glass" scale 0.4 translate [0.2 0.4 0.4] }
cube { material "glass" scale 0.3 rotate [1 0 0] 35 rotate [0 1 0] 45 translate [1 0.5 0] }
rectangle { material "pane" scale [0.4 1 0.6] rotate [1 0 0] 90 translate [-0.3 0.6 1.2] }
sphere { material "clay" scale 0.3 translate [0.3 0.3 -0.8] }
"#;

/// Shadows through coloured panes and a glass sphere, from a point light and from a
/// directional light straight down (its shadow rays run to infinity through two panes).
const SHADOWS: &str = r#"
light point { position [0.5 2.8 0.8] color 0.8 }
light directional { direction [0 -1 0] color 0.4 }
material "amber" { diffuse 0 specular 0 transmissive [0.9 0.6 0.2] ior 1 reflective 0 }
material "teal" { diffuse 0 specular 0 transmissive [0.2 0.7 0.8] ior 1 reflective 0 }
sphere { material "glass" scale 0.35 translate [-0.7 0.7 0.2] }
rectangle { material "amber" scale 0.5 translate [0.5 1.2 0.3] }
rectangle { material "teal" scale 0.4 translate [0.6 1.6 0.4] }
cube { material "clay" scale 0.2 translate [0.6 0.9 0.3] }
sphere { material "tiled" scale 0.25 translate [0 0.25 -0.6] }
material "ghost" { diffuse [0.6 0.5 0.2] specular 0.2 shininess 20 reflective 0 casts_shadows false }
sphere { material "ghost" scale 0.25 translate [-0.3 1.5 0.6] }
"#;

fn with_ball(scene: &str) -> String {
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meshes/icosphere.obj");
    format!("{ROOM}\nmesh \"ball\" {{ file \"{mesh}\" }}\n{scene}")
}

fn whitted(source: &str, width: u32, height: u32) -> RenderScene {
    let s = scene_as_written(source, width, height);
    assert_eq!(s.settings.integrator, IntegratorDesc::Whitted);
    s
}

#[test]
fn every_light_kind_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    check("whitted lights", &whitted(&with_ball(LIGHTS), 40, 32), &gpu);
}

#[test]
fn every_pixel_pattern_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let patterns = [
        (SamplePattern::Grid, 2),
        (SamplePattern::CornersAndCentre, 1),
        (SamplePattern::Jittered, 3),
        (SamplePattern::Sobol, 2),
    ];
    for (pattern, per_axis) in patterns {
        let mut s = whitted(&with_ball(LIGHTS), 24, 20);
        s.settings.sampler = PixelSampler { pattern, per_axis, seed: 7 };
        s.settings.seed = 11;
        s.settings.spp = s.settings.sampler.count();
        check(&format!("whitted {pattern:?} {per_axis}"), &s, &gpu);
    }
    // A wide filter gathers samples from neighbouring pixels' patterns too.
    let mut s = whitted(&with_ball(LIGHTS), 24, 20);
    s.settings.sampler = PixelSampler { pattern: SamplePattern::Jittered, per_axis: 2, seed: 3 };
    s.settings.spp = 4;
    s.settings.filter = glint_core::sampling::Filter::new(glint_core::sampling::FilterKind::Gaussian, 1.5).unwrap();
    check("whitted jittered, gaussian 1.5", &s, &gpu);
}

#[test]
fn reflection_refraction_and_total_internal_reflection_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let mut s = whitted(&with_ball(OPTICS), 40, 32);
    check("whitted optics", &s, &gpu);
    // Deep recursion, and a contribution cut that prunes the ray tree.
    s.settings.max_depth = 12;
    s.settings.min_contribution = 0.05;
    check("whitted optics, depth 12, cut 0.05", &s, &gpu);
}

#[test]
fn transparent_and_opaque_shadows_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let s = whitted(&with_ball(SHADOWS), 40, 32);
    check("whitted transparent shadows", &s, &gpu);
    let mut opaque = s.clone();
    opaque.settings.features.transparent_shadows = false;
    check("whitted opaque shadows", &opaque, &gpu);
}

#[test]
fn every_feature_switch_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let base = whitted(&with_ball(&format!("{OPTICS}{SHADOWS}")), 24, 20);
    type Switch = fn(&mut glint_core::desc::Features);
    let switches: [(&str, Switch); 4] = [
        ("no shadows", |f| f.shadows = false),
        ("no reflections", |f| f.reflections = false),
        ("no refractions", |f| f.refractions = false),
        ("no textures", |f| f.textures = false),
    ];
    for (name, switch) in switches {
        let mut s = base.clone();
        switch(&mut s.settings.features);
        check(&format!("whitted {name}"), &s, &gpu);
    }
}

#[test]
fn textures_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let board =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../glint-scene/tests/course/json/illuminate/required/textures/board.png");
    let source = format!(
        "{ROOM}\nlight point {{ position [1 2.5 2] color 0.9 }}\n\
         texture \"board\" image {{ file \"{board}\" }}\n\
         material \"boarded\" {{ diffuse 1 texture \"board\" repeat [1 1] specular 0 reflective 0 }}\n\
         texture \"edges\" image {{ file \"{board}\" wrap_u \"clamp\" wrap_v \"mirror\" filter \"nearest\" }}\n\
         material \"edged\" {{ diffuse 1 texture \"edges\" repeat [2.5 3] specular 0 reflective 0 }}\n\
         sphere {{ material \"tiled\" scale 0.4 translate [-0.6 0.4 0] }}\n\
         sphere {{ material \"edged\" scale 0.3 translate [0 0.3 0.6] }}\n\
         cube {{ material \"boarded\" scale 0.35 rotate [0 1 0] 25 translate [0.6 0.35 0] }}\n\
         rectangle {{ material \"tiled\" scale 0.5 rotate [1 0 0] 70 translate [0 1.4 -0.8] }}\n"
    );
    check("whitted textures", &whitted(&source, 40, 32), &gpu);
}

#[test]
fn blinn_highlights_and_textured_ambient_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let source = format!(
        "{room}\nlight point {{ position [1 2.5 2] color 0.9 }}\n\
         material \"satin\" {{ diffuse [0.6 0.3 0.2] specular 0.6 shininess 40 highlight \"blinn\" reflective 0 }}\n\
         material \"pov\" {{ diffuse 0.8 texture \"tiles\" blend 0.8 textured_ambient true \
         specular 0.4 shininess 80 highlight \"blinn\" reflective 0 }}\n\
         sphere {{ material \"satin\" scale 0.4 translate [-0.6 0.4 0] }}\n\
         cube {{ material \"pov\" scale 0.35 rotate [0 1 0] 25 translate [0.6 0.35 0] }}\n\
         sphere {{ material \"pov\" scale 0.3 translate [0 0.3 0.7] }}\n",
        room = ROOM.replace("ambient 0.08", "ambient 0.4")
    );
    check("whitted blinn, textured ambient", &whitted(&source, 40, 32), &gpu);
}

#[test]
fn checkers_filtered_over_the_pixel_footprint_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    // A uv-mapped quad, so the mesh's footprint (least squares in its uv frame) is tested.
    let quad = std::env::temp_dir().join(format!("glint-filtered-quad-{}.obj", std::process::id()));
    std::fs::write(
        &quad,
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n",
    )
    .expect("temporary mesh");
    // Fine checks to the horizon on an infinite plane, round a sphere's seam, over a
    // cube's faces, through a CSG difference and on the quad: each shape's own uvs at
    // the neighbouring pixels.
    let source = format!(
        "settings {{ max_depth 3 background [0.1 0.12 0.2] ambient 0.1 }}\n\
         camera {{ eye [0 0.6 4] look_at [0 0.3 -4] fov 50 }}\n\
         light point {{ position [1 2.5 2] color 0.9 }}\n\
         mesh \"quad\" {{ file \"{quad}\" }}\n\
         texture \"fine\" checker {{ even [0.9 0.8 0.2] odd [0.1 0.2 0.7] cells [16 16] filtered true }}\n\
         material \"fine\" {{ diffuse 0.8 texture \"fine\" blend 1 repeat [4 4] specular 0.2 shininess 20 reflective 0.2 }}\n\
         plane {{ material \"fine\" }}\n\
         sphere {{ material \"fine\" scale 0.35 rotate [0 1 0] -90 translate [-0.8 0.35 0] }}\n\
         cube {{ material \"fine\" scale 0.3 rotate [0 1 0] 30 translate [0.2 0.3 -0.5] }}\n\
         difference {{ material \"fine\" sphere {{ scale 0.3 }} cube {{ scale 0.2 translate [0.2 0.2 0.2] }} translate [1 0.35 0.5] }}\n\
         mesh_instance \"quad\" {{ material \"fine\" scale 0.3 rotate [0 1 0] 40 translate [0.4 0.3 1.2] }}\n",
        quad = quad.display()
    );
    let mut scene = whitted(&source, 48, 32);
    std::fs::remove_file(&quad).ok();
    check("whitted filtered checkers", &scene, &gpu);
    // Adaptive sampling narrows the footprint sample by sample, on both backends.
    scene.settings.adaptive = Some(glint_core::desc::AdaptiveDesc { min_samples: 1, max_samples: 8, threshold: 0.05 });
    // Each pixel takes as many samples on both: one where its neighbours agree with its
    // first, more along edges (a rule the GPU once lost after its first round).
    let cancel = std::sync::atomic::AtomicBool::new(false);
    let cpu_counts = glint_core::render::render(&scene, &|_, _| {}, &cancel).unwrap().1.samples_per_pixel;
    let gpu_counts = glint_gpu::render(&gpu, &scene, &|_, _| {}, &cancel).unwrap().1.samples_per_pixel;
    let differing = cpu_counts.iter().zip(&gpu_counts).filter(|(c, g)| c != g).count();
    assert!(differing <= cpu_counts.len() / 100, "{differing} pixels take other counts");
    assert!(cpu_counts.contains(&1) && cpu_counts.iter().any(|&n| n > 2), "flat pixels and edges both occur");
    // Filtered textures: a pixel stops at its pilot or drops it for at least four.
    assert!(gpu_counts.iter().all(|&n| n == 1 || n >= 4), "a pixel past its pilot takes four or more");
    check("whitted filtered checkers, adaptive", &scene, &gpu);
}

#[test]
fn a_smooth_mesh_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    // A low light grazes the coarse icosphere: its terminator needs the lifted shadow
    // origins (Hanika 2021) on both backends.
    let source = with_ball(
        "light point { position [-2.5 0.6 1.5] color 1 }\n\
         material \"shiny\" { diffuse [0.6 0.6 0.5] specular 0.5 shininess 40 reflective 0.3 }\n\
         mesh_instance \"ball\" { material \"clay\" scale 0.5 translate [-0.3 0.5 0] }\n\
         mesh_instance \"ball\" { material \"shiny\" scale [0.4 0.3 0.4] rotate [0 0 1] 20 translate [0.7 0.4 0.3] }\n",
    );
    check("whitted smooth mesh", &whitted(&source, 40, 32), &gpu);
}

#[test]
fn normal_maps_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let board =
        concat!(env!("CARGO_MANIFEST_DIR"), "/../glint-scene/tests/course/json/illuminate/required/textures/board.png");
    let source = with_ball(&format!(
        "light point {{ position [1 2.5 2] color 0.9 }}\n\
         texture \"bumps\" image {{ file \"{board}\" encoding \"linear\" }}\n\
         material \"bumpy\" {{ diffuse [0.6 0.6 0.5] specular 0.5 shininess 40 reflective 0.2 normal_map \"bumps\" repeat [3 2] }}\n\
         mesh_instance \"ball\" {{ material \"bumpy\" scale 0.5 translate [-0.3 0.5 0] }}\n\
         mesh_instance \"ball\" {{ material \"clay\" scale 0.3 translate [0.7 0.3 0.3] }}\n"
    ));
    check("whitted normal maps", &uv_mapped_scene(&source, 40, 32, None), &gpu);
}

#[test]
fn vertex_colours_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let source = with_ball(
        "light point { position [1 2.5 2] color 0.9 }\n\
         mesh_instance \"ball\" { material \"clay\" scale 0.5 translate [-0.4 0.5 0] }\n\
         mesh_instance \"ball\" { material \"tiled\" scale 0.4 translate [0.6 0.4 0.2] }\n",
    );
    check("whitted vertex colours", &painted_scene(&source, 40, 32, None), &gpu);
}

#[test]
fn an_environment_map_background_matches_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let map = concat!(env!("CARGO_MANIFEST_DIR"), "/../../bench/mitsuba/assets/envmap.exr");
    let source = format!(
        "{ROOM}\ntexture \"sky\" image {{ file \"{map}\" }}\n\
         light environment {{ texture \"sky\" radiance 1.2 rotate [0 1 0] 30 }}\n\
         light point {{ position [1 2.5 2] color 0.6 }}\n\
         sphere {{ material \"mirror\" scale 0.4 translate [0.5 0.6 0] }}\n\
         sphere {{ material \"clay\" scale 0.4 translate [-0.5 0.4 0] }}\n"
    );
    check("whitted envmap", &whitted(&source, 40, 32), &gpu);
}

/// The repository's example scenes rendered the Whitted way (path-traced ones too),
/// where the GPU renders all they contain.
#[test]
fn example_scenes_match_the_cpu() {
    let Some(gpu) = gpu() else { return };
    let names = example_scene_names();
    let mut rendered = Vec::new();
    for name in &names {
        let mut s = scene_file(name, 32, 24, 4);
        s.settings.integrator = IntegratorDesc::Whitted;
        s.settings.adaptive = None;
        if let Some(why) = glint_gpu::upload::beyond_adapter(&gpu, &s) {
            eprintln!("{name}: not on this GPU ({why})");
            continue;
        }
        check(&format!("whitted {name}"), &s, &gpu);
        rendered.push(name.clone());
    }
    for expected in [
        "cornell-path.glint",
        "cornell-whitted.glint",
        "csg.glint",
        "default.glint",
        "mesh-instances.glint",
        "soft-shadows.glint",
    ] {
        assert!(rendered.iter().any(|n| n == expected), "{expected} was not compared: {rendered:?}");
    }
}
