//! Times glint's mesh BVH on the mesh and rays that `bench/embree_compare.py` wrote, so
//! both libraries see identical input: build time, closest-hit and any-hit rays per
//! second for coherent (camera) and incoherent (random) rays, one thread, best of three.
//! Also checks that glint's hits agree with Embree's. Prints one JSON line. Times are CPU
//! seconds, so a busy machine skews them less: of the whole process for the build (which
//! runs on every core, as Embree's does, whose process CPU time the script measures), of
//! the tracing thread for rays. The build's wall-clock time is reported too.
//!
//! Usage: `cargo run --release -p glint-cli --example mesh_bench -- DIR/scene.bin`

use std::time::Instant;

use glint_core::desc::MeshDesc;
use glint_core::math::{Ray, Vec3};
use glint_core::mesh::Mesh;

fn words(bytes: &[u8], at: &mut usize, n: usize) -> Vec<u32> {
    let out = bytes[*at..*at + 4 * n].chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    *at += 4 * n;
    out
}

fn floats(bytes: &[u8], at: &mut usize, n: usize) -> Vec<f32> {
    words(bytes, at, n).into_iter().map(f32::from_bits).collect()
}

fn rays(f: &[f32]) -> Vec<Ray> {
    f.chunks_exact(6).map(|r| Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]))).collect()
}

/// CPU time of this thread in seconds (Linux's schedstat), so that other processes on a
/// busy machine do not count against glint; wall time elsewhere.
fn cpu_seconds(wall: Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .map_or_else(|| wall.elapsed().as_secs_f64(), |ns| ns * 1e-9)
}

/// The process's resident set in bytes (Linux's `/proc/self/statm`, second field, in
/// 4 KiB pages), or 0 where that file is missing.
fn resident_bytes() -> usize {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<usize>().ok())
        .map_or(0, |pages| pages * 4096)
}

/// Returns the heap's free pages to the OS (glibc's `malloc_trim`), so that the resident
/// set counts what is in use rather than what the allocator kept; a no-op elsewhere.
fn release_free_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        unsafe extern "C" {
            fn malloc_trim(pad: usize) -> i32;
        }
        // SAFETY: glibc's malloc_trim takes a byte count and only touches the allocator's own state.
        unsafe { malloc_trim(0) };
    }
}

/// CPU time of the whole process, every thread, in seconds (`CLOCK_PROCESS_CPUTIME_ID`
/// on Linux); `None` elsewhere.
fn process_cpu_seconds() -> Option<f64> {
    #[cfg(target_os = "linux")]
    {
        #[repr(C)]
        struct Timespec {
            sec: i64,
            nsec: i64,
        }
        unsafe extern "C" {
            fn clock_gettime(clock: i32, out: *mut Timespec) -> i32;
        }
        const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
        let mut t = Timespec { sec: 0, nsec: 0 };
        // SAFETY: clock_gettime writes one timespec (two 64-bit fields on 64-bit Linux) to `t`.
        let ok = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut t) } == 0;
        return ok.then_some(t.sec as f64 + t.nsec as f64 * 1e-9);
    }
    #[allow(unreachable_code)]
    None
}

/// CPU seconds of the whole process, or wall-clock seconds since `wall` where unknown.
fn process_cpu(wall: Instant) -> f64 {
    process_cpu_seconds().unwrap_or_else(|| wall.elapsed().as_secs_f64())
}

/// Best of three runs of `f` by `clock` (seconds since `origin`, any zero point).
fn best_of_3_by<T>(clock: impl Fn(Instant) -> f64, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    let origin = Instant::now();
    for _ in 0..3 {
        let start = clock(origin);
        out = Some(f());
        best = best.min(clock(origin) - start);
    }
    (best, out.expect("ran three times"))
}

/// Best of three in CPU seconds of this thread.
fn best_of_3<T>(f: impl FnMut() -> T) -> (f64, T) {
    best_of_3_by(cpu_seconds, f)
}

fn main() -> Result<(), String> {
    let path = std::env::args().nth(1).ok_or("usage: mesh_bench DIR/scene.bin")?;
    let bytes = std::fs::read(&path).map_err(|e| format!("{path}: {e}"))?;
    if !bytes.starts_with(b"GLBENCH1") {
        return Err(format!("{path}: not a GLBENCH1 file"));
    }
    let mut at = 8;
    let [v, t, c, i] = <[u32; 4]>::try_from(words(&bytes, &mut at, 4)).map_err(|_| "short header")?.map(|x| x as usize);
    let positions = floats(&bytes, &mut at, 3 * v).chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    let indices = words(&bytes, &mut at, 3 * t);
    let coherent = rays(&floats(&bytes, &mut at, 6 * c));
    let incoherent = rays(&floats(&bytes, &mut at, 6 * i));
    let embree_t = [floats(&bytes, &mut at, c), floats(&bytes, &mut at, i)];
    let desc = MeshDesc { positions, indices, ..Default::default() };

    // Memory first, before the timed builds have grown the heap: the compiled mesh's
    // exact array bytes, and as a cross-check the resident-set growth around one build
    // with the mesh still alive, both as it stands (build scratch the allocator kept
    // counts) and after handing freed heap back to the OS.
    release_free_heap();
    let before = resident_bytes();
    let mesh = Mesh::compile(&desc).map_err(|e| e.to_string())?;
    let rss_growth = resident_bytes().saturating_sub(before);
    release_free_heap();
    let rss_growth_trimmed = resident_bytes().saturating_sub(before);
    let memory = mesh.memory_bytes();
    drop(mesh);
    let (build_s, mesh) = best_of_3_by(process_cpu, || Mesh::compile(&desc));
    let (build_wall_s, _) = best_of_3_by(|wall| wall.elapsed().as_secs_f64(), || Mesh::compile(&desc));
    let mesh = mesh.map_err(|e| e.to_string())?;
    let mut report = vec![
        format!("\"triangles\": {}", mesh.triangles.len()),
        format!("\"bvh_nodes\": {}", mesh.bvh.nodes.len()),
        format!("\"triangle_packets\": {}", mesh.packets.len()),
        format!("\"memory_bytes\": {memory}"),
        format!("\"rss_growth_bytes\": {rss_growth}"),
        format!("\"rss_growth_trimmed_bytes\": {rss_growth_trimmed}"),
        format!("\"build_s\": {build_s}"),
        format!("\"build_wall_s\": {build_wall_s}"),
        format!("\"threads\": {}", rayon::current_num_threads()),
    ];
    for (name, rays, reference) in [("coherent", &coherent, &embree_t[0]), ("incoherent", &incoherent, &embree_t[1])] {
        let (secs, hits) = best_of_3(|| rays.iter().map(|r| mesh.intersect(r, f32::INFINITY)).collect::<Vec<_>>());
        report.push(format!("\"{name}_closest_rays_per_s\": {}", rays.len() as f64 / secs));
        let (secs, blocked) = best_of_3(|| rays.iter().filter(|r| mesh.occluded(r, f32::INFINITY)).count());
        report.push(format!("\"{name}_any_rays_per_s\": {}", rays.len() as f64 / secs));
        // Agreement with Embree: same hit/miss, and the same distance up to rounding.
        let mut disagree = 0;
        for (hit, &te) in hits.iter().zip(reference.iter()) {
            match hit {
                Some(h) if te.is_finite() => disagree += usize::from((h.t - te).abs() > 1e-4 * te.max(1.0)),
                None if !te.is_finite() => {}
                _ => disagree += 1,
            }
        }
        let hit_count = hits.iter().filter(|h| h.is_some()).count();
        report.push(format!("\"{name}_hit_fraction\": {}", hit_count as f64 / rays.len() as f64));
        report.push(format!("\"{name}_disagree_with_embree\": {disagree}"));
        report.push(format!("\"{name}_any_equals_closest\": {}", blocked == hit_count));
    }
    report.extend(obvhs_report(&mesh, &coherent, &incoherent));
    println!("{{{}}}", report.join(", "));
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
    let (build_s, bvh) = best_of_3_by(process_cpu, || {
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
        let (secs, hits) = best_of_3(|| {
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
        let (secs, _) = best_of_3(|| {
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
