//! The obvhs crate's compressed wide BVH on the mesh and rays that
//! `bench/embree_compare.py` wrote, timed as `glint bench` times glint's: build (CPU
//! seconds of the process), closest-hit and any-hit rays per CPU second of one thread,
//! best of three. Prints one JSON line, its keys prefixed `obvhs_`.
//!
//! Usage: `cargo run --release -p glint-cli --example obvhs_bench -- DIR/scene.bin`

use glint_cli::bench::{best_of_3, process_cpu_seconds, thread_cpu_seconds};
use glint_core::math::{Ray, Vec3};
use glint_core::mesh::Mesh;

fn main() -> Result<(), String> {
    let path = std::env::args().nth(1).ok_or("usage: obvhs_bench DIR/scene.bin")?;
    let input = glint_cli::bench::read_input(std::path::Path::new(&path))?;
    let mesh = Mesh::compile(&input.mesh).map_err(|e| e.to_string())?;
    println!("{{{}}}", obvhs_report(&mesh, &input.coherent, &input.incoherent).join(", "));
    Ok(())
}

/// The same measurements with the `obvhs` crate's compressed wide BVH (CWBVH, Ylitie et
/// al. 2017, built by PLOC with its "medium" preset) over the same triangles and with
/// glint's watertight triangle test, so only the acceleration structure differs.
fn obvhs_report(mesh: &Mesh, coherent: &[Ray], incoherent: &[Ray]) -> Vec<String> {
    use glam_obvhs::Vec3A;
    use glint_core::mesh::{WatertightRay, triangle};
    use obvhs::BvhBuildParams;
    use obvhs::cwbvh::builder::build_cwbvh_from_tris;
    use obvhs::ray::{Ray as ORay, RayHit};
    use obvhs::triangle::Triangle;

    let a = |v: Vec3| Vec3A::new(v.x, v.y, v.z);
    let tris: Vec<[Vec3; 3]> = mesh.triangles.iter().map(|t| t.map(|i| mesh.positions[i as usize])).collect();
    let otris: Vec<Triangle> = tris.iter().map(|t| Triangle { v0: a(t[0]), v1: a(t[1]), v2: a(t[2]) }).collect();
    let (build_s, bvh) = best_of_3(process_cpu_seconds, || {
        build_cwbvh_from_tris(&otris, BvhBuildParams::medium_build(), &mut std::time::Duration::default())
    });
    // Store the triangles in the order the BVH's leaves expect, as glint does.
    let ordered: Vec<[Vec3; 3]> = bvh.primitive_indices.iter().map(|&i| tris[i as usize]).collect();
    let mut report = vec![format!("\"obvhs_build_s\": {build_s}")];
    for (name, rays) in [("coherent", coherent), ("incoherent", incoherent)] {
        let prepared: Vec<(ORay, Option<WatertightRay>)> =
            rays.iter().map(|r| (ORay::new_inf(a(r.origin), a(r.dir)), WatertightRay::new(r))).collect();
        let test = |w: &WatertightRay, id: usize, t_max: f32| {
            let [p0, p1, p2] = ordered[id];
            triangle::intersect(w, p0, p1, p2, t_max).map_or(f32::INFINITY, |h| h.t)
        };
        let (secs, hits) = best_of_3(thread_cpu_seconds, || {
            prepared
                .iter()
                .filter(|(ray, w)| {
                    let Some(w) = w else { return false };
                    let mut hit = RayHit::none();
                    bvh.ray_traverse(*ray, &mut hit, |r, id| test(w, id, r.tmax))
                })
                .count()
        });
        report.push(format!("\"obvhs_{name}_closest_rays_per_s\": {}", rays.len() as f64 / secs));
        report.push(format!("\"obvhs_{name}_hit_fraction\": {}", hits as f64 / rays.len() as f64));
        let (secs, _) = best_of_3(thread_cpu_seconds, || {
            prepared
                .iter()
                .filter(|(ray, w)| {
                    w.as_ref().is_some_and(|w| !bvh.ray_traverse_miss(*ray, |r, id| test(w, id, r.tmax)))
                })
                .count()
        });
        report.push(format!("\"obvhs_{name}_any_rays_per_s\": {}", rays.len() as f64 / secs));
    }
    report
}
