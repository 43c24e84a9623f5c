//! GPU traversal finds the hits the CPU's BVH finds: the same instance, the same part
//! (triangle or face) and the same distance within f32 rounding, on random rays
//! through scenes of every shape the GPU intersects, meshes and instancing included.

mod common;

use glam::Vec3;
use glint_core::sampling::Rng;
use glint_gpu::RayQuery;
use proptest::prelude::*;

const SHAPES: &str = r#"
settings { width 8 height 8 integrator path {} }
camera { eye [0 0 6] look_at [0 0 0] fov 40 }
material "m" { bsdf diffuse { reflectance 0.5 } }
mesh "tri" { file "MESH" }
sphere { material "m" scale 0.7 translate [-2 1 0] }
cube { material "m" rotate [1 1 0] 30 translate [0 1.2 -0.5] }
cylinder { material "m" scale [0.5 0.8 0.5] rotate [0 0 1] 20 translate [2 1 0] }
cone { material "m" scale 0.6 translate [-2 -1 0.5] }
disk { material "m" rotate [1 0 0] 70 translate [0 -1.3 0] }
rectangle { material "m" scale 0.5 rotate [0 1 1] 40 translate [2 -1 0] }
plane { material "m" translate [0 -2.5 0] }
difference {
  material "m"
  intersection { cube { } sphere { scale 1.35 } }
  union { cylinder { scale [0.55 1.6 0.55] } cylinder { scale [0.55 1.6 0.55] rotate [1 0 0] 90 } }
  scale 0.5 rotate [1 1 0] 25 translate [-1.8 1.6 -1]
}
torus { minor_radius 0.3 material "m" rotate [1 0 0] 60 scale 0.6 translate [-1.5 -0.2 1.5] }
quadric { coefficients [1 -0.25 1 0 0 0 0 0 0 -0.16] bounds [-1 -1 -1] [1 1 1] material "m" scale 0.6 translate [1.2 1.6 1] }
quadric { coefficients [1 0 1 0.3 0 0 0 0.1 0 -0.05] material "m" rotate [1 0 0] 90 translate [0 0 -3] }
mesh_instance "tri" { material "m" scale 0.8 translate [-0.8 -0.4 1.5] }
mesh_instance "tri" { material "m" rotate [0 1 0] 60 scale [1 0.5 1] translate [1 0 2] }
"#;

fn compare(scene: &glint_core::scene::RenderScene, rays: &[RayQuery]) -> (usize, usize) {
    let gpu = common::gpu().expect("adapter");
    let gpu_hits = glint_gpu::trace_rays(&gpu, scene, rays).expect("GPU traces");
    let mut hits = 0;
    let mut mismatches = 0;
    for (ray, gpu_hit) in rays.iter().zip(&gpu_hits) {
        let cpu = scene.intersect(&glint_core::math::Ray::new(ray.origin, ray.dir), ray.t_max);
        match (cpu, gpu_hit) {
            (None, None) => {}
            (Some(c), Some(g)) => {
                hits += 1;
                let same = c.instance == g.instance && c.part == g.part && (c.t - g.t).abs() <= 1e-4 * c.t.max(1.0);
                if !same {
                    mismatches += 1;
                    eprintln!("ray {ray:?}: CPU ({}, {}, {}) GPU {g:?}", c.t, c.instance, c.part);
                }
            }
            (c, g) => {
                mismatches += 1;
                eprintln!("ray {ray:?}: CPU {:?} GPU {g:?}", c.map(|c| (c.t, c.instance, c.part)));
            }
        }
    }
    (hits, mismatches)
}

fn random_rays(seed: u32, count: usize) -> Vec<RayQuery> {
    let mut rng = Rng::new(seed);
    let mut unit = || 2.0 * rng.next_f32() - 1.0;
    (0..count)
        .map(|_| {
            let origin = Vec3::new(unit(), unit(), unit()) * 5.0;
            let target = Vec3::new(unit() * 2.5, unit() * 2.0, unit());
            let t_max = if unit() > 0.8 { 0.5 + 3.0 * (unit() + 1.0) } else { f32::INFINITY };
            RayQuery { origin, dir: (target - origin) * (0.5 + unit().abs()), t_max }
        })
        .collect()
}

#[test]
fn gpu_hits_are_the_cpu_hits_on_every_shape() {
    if common::gpu().is_none() {
        return;
    }
    let mesh = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/meshes/icosphere.obj");
    let scene = common::scene(&SHAPES.replace("MESH", mesh), 8, 8, 1);
    let rays = random_rays(1, 4096);
    let (hits, mismatches) = compare(&scene, &rays);
    eprintln!("{hits} hits, {mismatches} mismatches of {}", rays.len());
    assert!(hits > 1000, "the rays must mostly hit something: {hits}");
    // Rays grazing an edge can differ by rounding (the GPU has no f64 fallback).
    assert!(mismatches * 1000 <= rays.len(), "{mismatches} of {} rays differ", rays.len());
}

/// Superellipsoids, found by interval bisection in f32 on the GPU and in f64 on the
/// CPU: from nearly a cube to a four-pointed star, turned and squashed.
const SUPERELLIPSOIDS: &str = r#"
settings { width 8 height 8 integrator path {} }
camera { eye [0 0 6] look_at [0 0 0] fov 40 }
material "m" { bsdf diffuse { reflectance 0.5 } }
superellipsoid { material "m" exponents [0.05 0.05] scale 0.6 rotate [1 1 0] 30 translate [-1.6 1 0] }
superellipsoid { material "m" exponents [0.25 0.25] scale 0.7 translate [0.4 1.1 -0.5] }
superellipsoid { material "m" exponents [0.3 1] scale [1 0.55 1] rotate [1 0 0] 20 translate [1.8 -0.2 0.5] }
superellipsoid { material "m" exponents [1 1] scale 0.5 translate [-1.7 -1.1 1] }
superellipsoid { material "m" exponents [2 2] scale 0.8 rotate [0 1 0] 20 translate [-0.2 -1 0] }
superellipsoid { material "m" exponents [3 3] scale 1.1 rotate [0 1 0] 30 translate [0.6 -0.8 2] }
"#;

#[test]
fn gpu_hits_are_the_cpu_hits_on_superellipsoids() {
    if common::gpu().is_none() {
        return;
    }
    let scene = common::scene(SUPERELLIPSOIDS, 8, 8, 1);
    let rays = random_rays(2, 4096);
    let (hits, mismatches) = compare(&scene, &rays);
    eprintln!("{hits} hits, {mismatches} mismatches of {}", rays.len());
    assert!(hits > 1000, "the rays must mostly hit something: {hits}");
    assert!(mismatches * 1000 <= rays.len(), "{mismatches} of {} rays differ", rays.len());
}

/// Implicit surfaces, their bytecode run on the GPU with f32 intervals: a polynomial
/// (Goursat's tangle cube), a heart with odd powers, a gyroid sheet of sines and
/// cosines under max and abs with a Lipschitz bound, and a ball with an exponential
/// bump that fills its box (its faces are the surface). Each is traced alone:
/// lavapipe stops a kernel's loops after 65 535 iterations in all
/// (`Gpu::caps_loop_iterations`), which a ray crossing several of these can reach.
const IMPLICITS: [&str; 4] = [
    r#"implicit { material "m" function "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8" bounds [-2.6 -2.6 -2.6] [2.6 2.6 2.6] scale 0.8 rotate [0 1 0] 30 }"#,
    r#"implicit { material "m" function "(x^2 + 2.25*z^2 + y^2 - 1)^3 - x^2*y^3 - 0.1125*z^2*y^3" bounds [-1.4 -1.4 -1.4] [1.4 1.4 1.4] scale 1.5 }"#,
    r#"implicit { material "m" function "max(abs(sin(4*x)*cos(4*y) + sin(4*y)*cos(4*z) + sin(4*z)*cos(4*x)) - 0.4, x^2 + y^2 + z^2 - 1)" bounds [-1.05 -1.05 -1.05] [1.05 1.05 1.05] lipschitz 14 scale 2 }"#,
    r#"implicit { material "m" function "sqrt(x^2 + y^2 + z^2) - 1.2 + exp(-4*x^2)/(2 + y)" bounds [-0.8 -0.8 -0.8] [0.8 0.8 0.8] scale 2 }"#,
];

#[test]
fn gpu_hits_are_the_cpu_hits_on_implicit_surfaces() {
    compare_each_alone("implicit", &IMPLICITS, 3);
}

/// Traces 2048 random rays through each of `shapes` alone (seeds from `first_seed` on)
/// on both backends and asserts the hits agree: lavapipe's loop cap allows one solved
/// surface per ray, not several.
fn compare_each_alone(what: &str, shapes: &[&str], first_seed: u32) {
    if common::gpu().is_none() {
        return;
    }
    let head = "settings { width 8 height 8 integrator path {} }\ncamera { eye [0 0 6] look_at [0 0 0] fov 40 }\nmaterial \"m\" { bsdf diffuse { reflectance 0.5 } }\n";
    for (k, shape) in shapes.iter().enumerate() {
        let scene = common::scene(&format!("{head}{shape}\n"), 8, 8, 1);
        let rays = random_rays(first_seed + k as u32, 2048);
        let (hits, mismatches) = compare(&scene, &rays);
        eprintln!("{what} {k}: {hits} hits, {mismatches} mismatches of {}", rays.len());
        assert!(hits > 300, "{what} {k}: the rays must often hit it: {hits}");
        assert!(mismatches * 1000 <= rays.len(), "{what} {k}: {mismatches} of {} rays differ", rays.len());
    }
}

/// Blobs, solved on the GPU by interval bisection over the summed field and on the
/// CPU by root isolation of its quartic pieces: spheres with a carving negative
/// component, a capsule with a squashed sphere, and two spheres joined by a thin neck.
/// Each is traced alone, as the implicit surfaces are.
const BLOBS: [&str; 3] = [
    r#"blob { material "m" threshold 0.5
        component sphere { center [0 0 0] radius 1.1 strength 1 }
        component sphere { center [0.75 0.3 0] radius 0.8 strength 1 }
        component sphere { center [-0.6 0.5 0.3] radius 0.8 strength 1 }
        component sphere { center [0 -0.2 0.7] radius 0.7 strength 1 }
        component sphere { center [0.3 0.75 0.75] radius 0.7 strength -1.5 }
        scale 1.5 }"#,
    r#"blob { material "m" threshold 0.4
        component cylinder { from [-0.9 0 0] to [0.9 0 0] radius 0.55 strength 1 }
        component sphere { radius 1 strength 1 scale [0.5 1.3 0.5] translate [0 0.6 0] }
        component sphere { center [-1.1 0 0] radius 0.7 strength 0.9 }
        rotate [0 1 0] 25 scale 1.4 }"#,
    r#"blob { material "m" threshold 0.255
        component sphere { center [-0.8 0 0] radius 1 strength 1 }
        component sphere { center [0.8 0 0] radius 1 strength 1 }
        scale 1.5 }"#,
];

#[test]
fn gpu_hits_are_the_cpu_hits_on_blobs() {
    compare_each_alone("blob", &BLOBS, 7);
}

/// CSG with numerically solved operands, whose spans are every crossing in their box
/// paired by direction: a superellipsoid cut by a cube, a ball with a bump that fills its
/// box (whose faces bound it where the function is negative there) less a sphere, a
/// blob joined to a cylinder, and an implicit ball intersected with a blob.
const SOLVED_CSG: [&str; 4] = [
    r#"intersection { material "m" superellipsoid { exponents [0.3 1] scale 1.3 } cube { scale 0.8 rotate [0 1 1] 30 translate [0.6 0.5 0] } scale 1.4 }"#,
    r#"difference { material "m" implicit { function "sqrt(x^2 + y^2 + z^2) - 1.2 + exp(-4*x^2)/(2 + y)" bounds [-0.8 -0.8 -0.8] [0.8 0.8 0.8] } sphere { scale 0.6 translate [0.5 0.5 0.5] } scale 2 }"#,
    r#"union { material "m" blob { threshold 0.5
        component sphere { center [0 0 0] radius 1.1 strength 1 }
        component sphere { center [0.75 0.3 0] radius 0.8 strength 1 } }
        cylinder { scale [0.3 1.5 0.3] translate [0.4 0 0] } scale 1.5 }"#,
    r#"intersection { material "m" implicit { function "x^2 + y^2 + z^2 - 1" bounds [-1.1 -1.1 -1.1] [1.1 1.1 1.1] translate [0.3 -0.3 0] }
        blob { threshold 0.3 component sphere { center [0 0.5 0] radius 1.2 strength 1 } component sphere { center [0.5 -0.5 0] radius 1 strength 1 } }
        scale 1.5 }"#,
];

/// Operands whose spans cost more loop iterations than lavapipe allows one invocation
/// (`Gpu::caps_loop_iterations`): a tangle cube, cut by its box, less a sphere, and a
/// heart intersected with a blob. Past the cap every loop stops after one pass, so on
/// such a driver these rays come out wrong; they are compared where there is no cap.
const COSTLY_SOLVED_CSG: [&str; 2] = [
    r#"difference { material "m" implicit { function "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8" bounds [-2.6 -2.6 -2.2] [2.6 2.6 2.6] } sphere { scale 1.4 translate [1 1 1.5] } scale 0.8 rotate [0 1 0] 30 }"#,
    r#"intersection { material "m" implicit { function "(x^2 + 2.25*z^2 + y^2 - 1)^3 - x^2*y^3 - 0.1125*z^2*y^3" bounds [-1.4 -1.4 -1.4] [1.4 1.4 1.4] }
        blob { threshold 0.3 component sphere { center [0 0.5 0] radius 1.2 strength 1 } component sphere { center [0.5 -0.5 0] radius 1 strength 1 } }
        scale 1.5 }"#,
];

#[test]
fn gpu_hits_are_the_cpu_hits_on_csg_of_solved_shapes() {
    compare_each_alone("solved CSG", &SOLVED_CSG, 10);
}

#[test]
fn gpu_hits_are_the_cpu_hits_on_costly_csg_of_solved_shapes_where_loops_are_not_capped() {
    match common::gpu() {
        Some(gpu) if gpu.caps_loop_iterations() => {
            eprintln!("SKIPPED: the driver caps loop iterations ({})", gpu.describe());
        }
        Some(_) => compare_each_alone("costly solved CSG", &COSTLY_SOLVED_CSG, 14),
        None => {}
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 4, ..ProptestConfig::default() })]

    #[test]
    fn gpu_hits_are_the_cpu_hits_on_a_mesh(seed in 0u32..1000) {
        if common::gpu().is_none() {
            return Ok(());
        }
        let scene = common::scene_file("mesh-instances.glint", 8, 8, 1);
        let (hits, mismatches) = compare(&scene, &random_rays(seed, 512));
        prop_assert!(mismatches <= 1, "{mismatches} of 512 rays differ ({hits} hits)");
    }
}
