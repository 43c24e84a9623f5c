//! The instancing benchmark: a field of tens of thousands of flowering plants on a
//! terrain — hundreds of millions of instanced triangles — rendered at 1920×1080. Memory
//! must grow with the unique geometry (one plant, one terrain), not with the copies.
//!
//! Usage: `plants [OUT.png] [PLANTS] [WIDTH HEIGHT]` (defaults: plants.png, 30000,
//! 1920 1080). Run through `bench/instancing.sh`.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use glint_core::desc::*;
use glint_core::film::Transfer;
use glint_core::math::Vec3;
use glint_core::render::render;
use glint_core::sampling::hash;
use glint_core::scene::compile;
use glint_scene::image_out::{OutputFormat, write_image};

/// Side of the square field, world units.
const FIELD: f32 = 120.0;

fn terrain_height(x: f32, z: f32) -> f32 {
    0.8 * (0.11 * x).sin() * (0.09 * z).cos() + 0.35 * (0.31 * x + 0.23 * z).sin() + 0.15 * (0.7 * z).sin()
}

/// A triangle mesh with vertex normals averaged from its faces.
fn mesh(name: &str, positions: Vec<Vec3>, indices: Vec<u32>) -> MeshDesc {
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            normals[i as usize] += n;
        }
    }
    let normals = normals.into_iter().map(|n| n.normalize_or(Vec3::Y)).collect();
    MeshDesc {
        name: name.into(),
        path: String::new(),
        positions,
        normals,
        uvs: Vec::new(),
        colors: Vec::new(),
        indices,
    }
}

/// Revolves `profile` ((radius, height) pairs, bottom to top) around the y axis.
fn lathe(profile: &[(f32, f32)], segments: u32, out_positions: &mut Vec<Vec3>, out_indices: &mut Vec<u32>) {
    let base = out_positions.len() as u32;
    for &(r, y) in profile {
        for s in 0..segments {
            let a = std::f32::consts::TAU * s as f32 / segments as f32;
            out_positions.push(Vec3::new(r * a.cos(), y, r * a.sin()));
        }
    }
    for ring in 0..profile.len() as u32 - 1 {
        for s in 0..segments {
            let (i0, i1) = (base + ring * segments + s, base + ring * segments + (s + 1) % segments);
            let (j0, j1) = (i0 + segments, i1 + segments);
            out_indices.extend([i0, j0, i1, i1, j0, j1]);
        }
    }
}

/// Stem and a wavy skirt of leaves (green), about 5,300 triangles.
fn stem() -> MeshDesc {
    let (mut p, mut i) = (Vec::new(), Vec::new());
    let stem: Vec<(f32, f32)> = (0..60).map(|k| (0.035 - 0.01 * k as f32 / 59.0, 1.3 * k as f32 / 59.0)).collect();
    lathe(&stem, 24, &mut p, &mut i);
    let leaves: Vec<(f32, f32)> = (0..20)
        .map(|k| {
            let u = k as f32 / 19.0;
            (0.04 + 0.35 * u, 0.35 + 0.25 * u - 0.3 * u * u)
        })
        .collect();
    let start = p.len();
    lathe(&leaves, 64, &mut p, &mut i);
    // Ruffle the skirt into leaves.
    for (n, v) in p[start..].iter_mut().enumerate() {
        let angle = v.z.atan2(v.x);
        v.y += 0.08 * (5.0 * angle).sin() * (n % 64 != 0) as u8 as f32 * v.x.hypot(v.z);
    }
    mesh("stem", p, i)
}

/// Head and petals (yellow), about 5,300 triangles.
fn bloom() -> MeshDesc {
    let (mut p, mut i) = (Vec::new(), Vec::new());
    let head: Vec<(f32, f32)> = (0..32)
        .map(|k| {
            let a = std::f32::consts::PI * k as f32 / 31.0 - std::f32::consts::FRAC_PI_2;
            (0.16 * a.cos(), 1.35 + 0.06 * a.sin())
        })
        .collect();
    lathe(&head, 64, &mut p, &mut i);
    let petals: Vec<(f32, f32)> = (0..8).map(|k| (0.15 + 0.2 * k as f32 / 7.0, 1.33 - 0.04 * k as f32 / 7.0)).collect();
    let start = p.len();
    lathe(&petals, 96, &mut p, &mut i);
    for v in &mut p[start..] {
        let angle = v.z.atan2(v.x);
        let r = v.x.hypot(v.z);
        // Twelve petals: pull the rim in between them.
        let scale = 1.0 - 0.35 * ((r - 0.15) / 0.2) * (0.5 - 0.5 * (12.0 * angle).cos());
        v.x *= scale;
        v.z *= scale;
    }
    mesh("bloom", p, i)
}

fn terrain(n: u32) -> MeshDesc {
    let mut p = Vec::new();
    let mut i = Vec::new();
    for row in 0..n {
        for col in 0..n {
            let x = FIELD * (col as f32 / (n - 1) as f32 - 0.5);
            let z = FIELD * (row as f32 / (n - 1) as f32 - 0.5);
            p.push(Vec3::new(x, terrain_height(x, z), z));
        }
    }
    for row in 0..n - 1 {
        for col in 0..n - 1 {
            let a = row * n + col;
            i.extend([a, a + n, a + 1, a + 1, a + n, a + n + 1]);
        }
    }
    mesh("terrain", p, i)
}

fn unit(h: u32) -> f32 {
    (h >> 8) as f32 / (1u32 << 24) as f32
}

fn scene(plants: u32, width: u32, height: u32) -> SceneDesc {
    let material = |c: Vec3, s: f32| MaterialDesc {
        diffuse: c,
        specular: Vec3::splat(s),
        shininess: 20.0,
        reflective: Some(Vec3::ZERO),
        ..Default::default()
    };
    let meshes = vec![terrain(384), stem(), bloom()];
    let mut objects = vec![NodeDesc {
        transform: vec![],
        kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index: 0 }, material: 0 },
        origin: "terrain".into(),
    }];
    for k in 0..plants {
        let (x, z) = ((unit(hash(&[k, 1])) - 0.5) * FIELD * 0.98, (unit(hash(&[k, 2])) - 0.5) * FIELD * 0.98);
        let size = 0.8 + 0.6 * unit(hash(&[k, 3]));
        let turn = 360.0 * unit(hash(&[k, 4]));
        let lean = 12.0 * (unit(hash(&[k, 5])) - 0.5);
        let part = |index: usize, material: usize| NodeDesc {
            transform: vec![],
            kind: NodeKind::Shape { shape: ShapeDesc::Mesh { index }, material },
            origin: String::new(),
        };
        objects.push(NodeDesc {
            transform: vec![
                TransformOp::Scale(Vec3::splat(size)),
                TransformOp::Rotate { axis: Vec3::X, degrees: lean },
                TransformOp::Rotate { axis: Vec3::Y, degrees: turn },
                TransformOp::Translate(Vec3::new(x, terrain_height(x, z) - 0.02, z)),
            ],
            kind: NodeKind::Group(vec![part(1, 1), part(2, 2)]),
            origin: format!("plant {k}"),
        });
    }
    SceneDesc {
        settings: RenderSettings {
            width,
            height,
            background: Vec3::new(0.55, 0.7, 0.95),
            ambient_light: Vec3::splat(0.25),
            max_depth: 2,
            ..Default::default()
        },
        camera: CameraDesc {
            eye: Vec3::new(0.0, 6.0, FIELD * 0.5 + 4.0),
            look: Vec3::new(0.0, -0.12, -1.0),
            up: Vec3::Y,
            fov_y_degrees: 38.0,
            ..Default::default()
        },
        lights: vec![LightDesc::Directional { direction: Vec3::new(-0.5, -1.0, -0.4), color: Vec3::splat(0.95) }],
        materials: vec![
            material(Vec3::new(0.35, 0.28, 0.16), 0.0),
            material(Vec3::new(0.2, 0.55, 0.15), 0.1),
            material(Vec3::new(0.95, 0.7, 0.08), 0.2),
        ],
        textures: vec![],
        meshes,
        objects,
        views: vec![],
    }
}

/// Peak resident memory of this process (Linux `VmHWM`), in MiB.
fn peak_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let out = args.get(1).cloned().unwrap_or_else(|| "plants.png".into());
    let plants: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(30_000);
    let width: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1920);
    let height: u32 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1080);

    let start = Instant::now();
    let desc = scene(plants, width, height);
    let unique: usize = desc.meshes.iter().map(|m| m.indices.len() / 3).sum();
    let plant_tris = (desc.meshes[1].indices.len() + desc.meshes[2].indices.len()) / 3;
    let instanced = plant_tris as u64 * plants as u64 + (desc.meshes[0].indices.len() / 3) as u64;
    let built = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let compiled = compile(&desc).expect("the generated scene compiles");
    drop(desc);
    let compiled_in = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let (image, stats) = render(&compiled, &|_, _| {}, &AtomicBool::new(false)).expect("not cancelled");
    let rendered = start.elapsed().as_secs_f64();
    write_image(&image, std::path::Path::new(&out), OutputFormat::Png8, Transfer::Srgb).expect("write the image");
    println!(
        "| plants | instances | unique triangles | instanced triangles | scene built (s) | compiled (s) | rendered {width}×{height} (s) | Mrays/s | peak memory (MiB) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    println!(
        "| {plants} | {} | {unique} | {instanced} | {built:.2} | {compiled_in:.2} | {rendered:.2} | {:.2} | {:.0} |",
        compiled.instances.len(),
        stats.rays as f64 / rendered / 1e6,
        peak_mib()
    );
}
