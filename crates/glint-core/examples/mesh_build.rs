//! Times a mesh build and fingerprints its result, for work on the builder: the binary
//! SAH build, the collapse to the 8-wide BVH and the whole `Mesh::compile`, best of
//! `ROUNDS` (7), on a generated bumpy sphere of `SCALE² · 10,000` triangles (`SCALE` 10:
//! 1M). The fingerprints (FNV-1a of the compiled nodes, packets, triangles and vertices)
//! tell whether a change to the builder left the traced mesh bit for bit as it was.
//!
//!     cargo run --release -p glint-core --example mesh_build
//!     RAYON_NUM_THREADS=1 SCALE=4 ROUNDS=1 valgrind --tool=callgrind target/release/examples/mesh_build
use std::time::Instant;

use glam::Vec3;
use glint_core::accel::{Bvh, WideBvh};
use glint_core::desc::MeshDesc;
use glint_core::math::Aabb;
use glint_core::mesh::Mesh;

fn env_or(name: &str, default: u32) -> u32 {
    std::env::var(name).ok().and_then(|s| s.parse().ok()).unwrap_or(default)
}

/// A UV sphere of `n_lat × n_lon × 2` triangles with a ripple, so boxes differ in size.
fn bumpy_sphere(n_lat: u32, n_lon: u32) -> MeshDesc {
    let mut desc = MeshDesc::default();
    for i in 0..=n_lat {
        for j in 0..n_lon {
            let theta = std::f32::consts::PI * i as f32 / n_lat as f32;
            let phi = std::f32::consts::TAU * j as f32 / n_lon as f32;
            let r = 1.0 + 0.05 * (7.0 * theta).sin() * (11.0 * phi).cos();
            desc.positions.push(r * Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()));
        }
    }
    for i in 0..n_lat {
        for j in 0..n_lon {
            let (a, b) = (i * n_lon + j, i * n_lon + (j + 1) % n_lon);
            let (c, d) = (a + n_lon, b + n_lon);
            desc.indices.extend([a, b, c, b, d, c]);
        }
    }
    desc
}

fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ b as u64).wrapping_mul(0x100_0000_01b3))
}

fn main() {
    let scale = env_or("SCALE", 10);
    let desc = bumpy_sphere(50 * scale, 100 * scale);
    let boxes: Vec<Aabb> = desc
        .indices
        .chunks(3)
        .map(|t| t.iter().fold(Aabb::EMPTY, |b, &i| b.grow(desc.positions[i as usize])))
        .collect();
    let mut best = [f64::INFINITY; 3];
    let mut mesh = None;
    for _ in 0..env_or("ROUNDS", 7) {
        let t = Instant::now();
        let (bvh, _order) = Bvh::build_blocks(&boxes, 4);
        let binary = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let wide = WideBvh::from_binary(&bvh);
        let collapse = t.elapsed().as_secs_f64();
        assert!(!wide.nodes.is_empty());
        drop((bvh, wide));
        let t = Instant::now();
        mesh = Some(Mesh::compile(&desc).expect("the generated mesh is valid"));
        let compile = t.elapsed().as_secs_f64();
        best = [best[0].min(binary), best[1].min(collapse), best[2].min(compile)];
    }
    let Some(mesh) = mesh else { return };
    println!(
        "{} triangles; best times: binary build {:.3} s, collapse {:.3} s, whole compile {:.3} s",
        boxes.len(),
        best[0],
        best[1],
        best[2]
    );
    println!(
        "fingerprints: nodes {:016x} packets {:016x} triangles {:016x} positions {:016x}",
        fnv1a(bytemuck::cast_slice(&mesh.bvh.nodes)),
        fnv1a(bytemuck::cast_slice(&mesh.packets)),
        fnv1a(bytemuck::cast_slice(&mesh.triangles)),
        fnv1a(bytemuck::cast_slice(&mesh.positions))
    );
}
