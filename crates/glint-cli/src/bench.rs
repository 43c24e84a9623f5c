//! `glint bench`: how fast glint's mesh BVH builds and traces, on a ~1M-triangle mesh
//! and the rays of `bench/embree_compare.sh` (a `GLBENCH1` file, which Embree is timed
//! on in the same run) or on the same kind of mesh and rays generated here.
//!
//! Timings are CPU seconds, best of three, so other work on a busy machine skews them
//! less: the build's over the whole process (it runs on the `--threads` that trace, as
//! Embree's build in `bench/embree_native.sh` runs on its device's), the rays' over the
//! one thread that traces them.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use glint_core::accel::PACKET;
use glint_core::desc::MeshDesc;
use glint_core::math::{Ray, Vec3};
use glint_core::mesh::Mesh;

/// A mesh and the rays to trace through it.
#[derive(Debug)]
pub struct BenchInput {
    pub mesh: MeshDesc,
    /// Camera rays of a square image, row by row.
    pub coherent: Vec<Ray>,
    /// Random origins and directions.
    pub incoherent: Vec<Ray>,
    /// Another library's closest-hit distances for each ray (∞ for a miss), to check
    /// that glint finds the same hits; empty when none came with the input.
    pub reference: [Vec<f32>; 2],
}

/// Reads a `GLBENCH1` file (layout in `bench/embree_compare.py`).
pub fn read_input(path: &Path) -> Result<BenchInput, String> {
    let bytes = glint_scene::input::read_bytes(path, glint_scene::input::InputKind::Mesh).map_err(|e| e.to_string())?;
    let fail = |what: &str| format!("{}: {what}", path.display());
    if !bytes.starts_with(b"GLBENCH1") {
        return Err(fail("not a GLBENCH1 file (bench/embree_compare.py writes them)"));
    }
    let mut words = bytes[8..].chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
    let mut take = |n: usize| -> Result<Vec<u32>, String> {
        let out: Vec<u32> = words.by_ref().take(n).collect();
        (out.len() == n).then_some(out).ok_or_else(|| fail("file ends early"))
    };
    let header = take(4)?;
    let [v, t, c, i] = [0, 1, 2, 3].map(|k| header[k] as usize);
    if v.max(t).max(c).max(i) > 1 << 28 {
        return Err(fail("counts in the header are absurd"));
    }
    let floats = |w: Vec<u32>| w.into_iter().map(f32::from_bits).collect::<Vec<_>>();
    let rays = |f: Vec<f32>| {
        f.chunks_exact(6).map(|r| Ray::new(Vec3::new(r[0], r[1], r[2]), Vec3::new(r[3], r[4], r[5]))).collect()
    };
    let positions = floats(take(3 * v)?).chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    let indices = take(3 * t)?;
    let coherent = rays(floats(take(6 * c)?));
    let incoherent = rays(floats(take(6 * i)?));
    let reference = [floats(take(c)?), floats(take(i)?)];
    Ok(BenchInput { mesh: MeshDesc { positions, indices, ..Default::default() }, coherent, incoherent, reference })
}

/// The benchmark's scene made here: a bumpy sphere of `2·n_lat·n_lon` triangles, a
/// `side`² camera looking at it from (0, 0.3, 3), and `random` rays from random points
/// of [−1.5, 1.5]³ in random directions — the scene of `bench/embree_compare.py`.
pub fn generate(n_lat: u32, n_lon: u32, side: u32, random: usize) -> BenchInput {
    use std::f64::consts::PI;
    let mut positions = Vec::new();
    for i in 0..=n_lat {
        let th = PI * i as f64 / n_lat as f64;
        for j in 0..n_lon {
            let ph = 2.0 * PI * j as f64 / n_lon as f64;
            let r = 1.0 + 0.04 * (13.0 * th).sin() * (17.0 * ph).sin() + 0.02 * (41.0 * th + 5.0 * ph).sin();
            positions.push(Vec3::new(
                (r * th.sin() * ph.cos()) as f32,
                (r * th.cos()) as f32,
                (r * th.sin() * ph.sin()) as f32,
            ));
        }
    }
    let mut indices = Vec::new();
    for i in 0..n_lat {
        for j in 0..n_lon {
            let (a, b) = (i * n_lon + j, i * n_lon + (j + 1) % n_lon);
            let (c, d) = ((i + 1) * n_lon + (j + 1) % n_lon, (i + 1) * n_lon + j);
            indices.extend([a, b, c, a, c, d]);
        }
    }
    let tan = 20f32.to_radians().tan();
    let coherent = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) as f32, (k / side) as f32);
            let (px, py) = ((x + 0.5) / side as f32 * 2.0 - 1.0, 1.0 - (y + 0.5) / side as f32 * 2.0);
            Ray::new(Vec3::new(0.0, 0.3, 3.0), Vec3::new(px * tan, py * tan - 0.1, -1.0).normalize())
        })
        .collect();
    let mut state = 0x853c_49e6_748f_ea9bu64;
    let mut uniform = move || {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let incoherent = (0..random)
        .map(|_| {
            let origin = Vec3::new(uniform(), uniform(), uniform()) * 3.0 - 1.5;
            // Uniform on the sphere: z uniform in [−1, 1], azimuth uniform.
            let (z, phi) = (uniform() * 2.0 - 1.0, uniform() * std::f32::consts::TAU);
            let s = (1.0 - z * z).max(0.0).sqrt();
            Ray::new(origin, Vec3::new(s * phi.cos(), s * phi.sin(), z))
        })
        .collect();
    BenchInput {
        mesh: MeshDesc { positions, indices, ..Default::default() },
        coherent,
        incoherent,
        reference: [vec![], vec![]],
    }
}

/// One measured quantity: a JSON key and its value.
pub type Measure = (String, f64);

/// How the rays are timed.
#[derive(Clone, Copy, Debug)]
pub struct BenchOptions {
    /// Threads tracing the rays (each takes chunks of 1024 rays in turn); 1 = one thread.
    pub threads: usize,
    /// Timed runs of each query: the median is reported, and the fastest and slowest.
    pub rounds: usize,
}

impl Default for BenchOptions {
    fn default() -> Self {
        Self { threads: 1, rounds: 5 }
    }
}

/// Builds and traces `input`, calling `progress` with what it is about to time.
pub fn run(input: &BenchInput, options: BenchOptions, mut progress: impl FnMut(&str)) -> Result<Vec<Measure>, String> {
    let mut out: Vec<Measure> = Vec::new();
    let mut put = |key: &str, value: f64| out.push((key.to_string(), value));
    progress("building");
    // The build runs on as many threads as the tracing, as Embree's device does in
    // bench/embree_native.sh: on one thread, its CPU seconds are one core's work.
    let pool = rayon::ThreadPoolBuilder::new().num_threads(options.threads).build().map_err(|e| e.to_string())?;
    let compile = || pool.install(|| Mesh::compile(&input.mesh));
    // Memory first, before the timed builds have grown the heap: the compiled mesh's
    // exact array bytes, and the resident-set growth around one build with the mesh
    // alive, as it stands (build scratch the allocator kept counts) and after handing
    // freed heap back to the OS.
    release_free_heap();
    let before = resident_bytes();
    let mesh = compile().map_err(|e| e.to_string())?;
    let rss_growth = resident_bytes().saturating_sub(before);
    release_free_heap();
    let rss_growth_trimmed = resident_bytes().saturating_sub(before);
    put("memory_bytes", mesh.memory_bytes() as f64);
    put("rss_growth_bytes", rss_growth as f64);
    put("rss_growth_trimmed_bytes", rss_growth_trimmed as f64);
    drop(mesh);
    let (build_s, mesh) = best_of_3(process_cpu_seconds, compile);
    let (build_wall_s, _) = best_of_3(|wall| wall.elapsed().as_secs_f64(), compile);
    let mesh = mesh.map_err(|e| e.to_string())?;
    put("triangles", mesh.triangles.len() as f64);
    put("bvh_nodes", mesh.bvh.nodes.len() as f64);
    put("triangle_packets", mesh.packets.len() as f64);
    put("build_s", build_s);
    put("build_wall_s", build_wall_s);
    put("threads", pool.current_num_threads() as f64);
    put("trace_threads", options.threads as f64);
    let timer = RayTimer { pool: &pool, rounds: options.rounds.max(1) };
    for (name, rays, reference) in
        [("coherent", &input.coherent, &input.reference[0]), ("incoherent", &input.incoherent, &input.reference[1])]
    {
        progress(&format!("tracing {name} rays"));
        let (rate, hits) = timer.time(rays, |r| mesh.intersect(r, f32::INFINITY).map(|h| h.t));
        rate.put(&mut put, &format!("{name}_closest"));
        let (rate, blocked) = timer.time(rays, |r| mesh.occluded(r, f32::INFINITY));
        rate.put(&mut put, &format!("{name}_any"));
        let hit_count = hits.iter().filter(|h| h.is_some()).count();
        if blocked.iter().filter(|&&b| b).count() != hit_count {
            return Err(format!("{name} rays: blocked and hit rays differ; the queries disagree"));
        }
        put(&format!("{name}_hit_fraction"), hit_count as f64 / rays.len().max(1) as f64);
        if !reference.is_empty() {
            put(&format!("{name}_disagree_with_reference"), disagreements(&hits, reference) as f64);
        }
        // Camera rays go into packets as 4×2 pixel tiles; random rays as they come.
        let order = if name == "coherent" { tile_order(rays.len()) } else { (0..rays.len()).collect() };
        let packets: Vec<Ray> = order.iter().map(|&i| rays[i]).collect();
        let (rate, packet_hits) = timer.time_packets(&packets, |rays| {
            let mut hits = [None; PACKET];
            mesh.intersect_packet(rays, u32::MAX, &mut [f32::INFINITY; PACKET], &mut hits);
            hits
        });
        rate.put(&mut put, &format!("{name}_closest_packet"));
        let (rate, packet_blocked) = timer.time_packets(&packets, |rays| {
            let mask = mesh.occluded_packet(rays, f32::INFINITY);
            std::array::from_fn(|k| mask >> k & 1 == 1)
        });
        rate.put(&mut put, &format!("{name}_any_packet"));
        // The same distance; of surfaces hit at (nearly) the same distance the visit
        // order may pick another, so the last bits may differ.
        let close = |a: f32, b: f32| (a - b).abs() <= 1e-6 * a.abs().max(1.0);
        let same = order.iter().zip(&packet_hits).all(|(&i, h)| match (h, hits[i]) {
            (Some(h), Some(t)) => close(h.t, t),
            (h, t) => h.is_none() && t.is_none(),
        });
        let same_blocked = order.iter().zip(&packet_blocked).all(|(&i, &b)| b == blocked[i]);
        if !same || !same_blocked {
            return Err(format!("{name} rays: packets and single rays found different hits"));
        }
    }
    Ok(out)
}

/// A rate's median over the timed runs, and its fastest and slowest.
struct Rate {
    median: f64,
    min: f64,
    max: f64,
}

impl Rate {
    /// `{key}_rays_per_s` (the median) and its `_min` and `_max`.
    fn put(&self, put: &mut impl FnMut(&str, f64), key: &str) {
        put(&format!("{key}_rays_per_s"), self.median);
        put(&format!("{key}_rays_per_s_min"), self.min);
        put(&format!("{key}_rays_per_s_max"), self.max);
    }
}

/// Times a query over many rays on a pool of threads: wall-clock seconds on several
/// threads, this thread's CPU seconds on one (so other work on a busy machine counts
/// less).
struct RayTimer<'a> {
    pool: &'a rayon::ThreadPool,
    rounds: usize,
}

/// Rays a thread takes at a time.
const CHUNK: usize = 1024;

impl RayTimer<'_> {
    /// Runs `query` on every ray `rounds` times: the rate, and the answers in ray order.
    fn time<T: Send>(&self, rays: &[Ray], query: impl Fn(&Ray) -> T + Sync) -> (Rate, Vec<T>) {
        self.measure(rays.len(), || {
            self.pool.install(|| {
                use rayon::prelude::*;
                rays.par_chunks(CHUNK).flat_map_iter(|chunk| chunk.iter().map(&query).collect::<Vec<_>>()).collect()
            })
        })
    }

    /// Runs `query` on every packet of [`PACKET`] rays: the rate, and the answers.
    fn time_packets<T: Send + Copy>(
        &self,
        rays: &[Ray],
        query: impl Fn(&[Ray]) -> [T; PACKET] + Sync,
    ) -> (Rate, Vec<T>) {
        self.measure(rays.len(), || {
            self.pool.install(|| {
                use rayon::prelude::*;
                rays.par_chunks(CHUNK)
                    .flat_map_iter(|chunk| {
                        chunk.chunks(PACKET).flat_map(|p| query(p).into_iter().take(p.len())).collect::<Vec<_>>()
                    })
                    .collect()
            })
        })
    }

    fn measure<T>(&self, rays: usize, mut run: impl FnMut() -> T) -> (Rate, T) {
        let single = self.pool.current_num_threads() == 1;
        let mut rates = Vec::with_capacity(self.rounds);
        let mut out = None;
        for _ in 0..self.rounds {
            let wall = Instant::now();
            let start = if single { self.pool.install(|| thread_cpu_seconds(wall)) } else { 0.0 };
            out = Some(run());
            let seconds = if single {
                self.pool.install(|| thread_cpu_seconds(wall)) - start
            } else {
                wall.elapsed().as_secs_f64()
            };
            rates.push(rays as f64 / seconds);
        }
        rates.sort_by(f64::total_cmp);
        let rate = Rate { median: rates[rates.len() / 2], min: rates[0], max: rates[rates.len() - 1] };
        (rate, out.expect("at least one round"))
    }
}

/// Writes `input` as a `GLBENCH1` file with `reference` as the closest-hit distances
/// (∞ for a miss), for another library (bench/embree_native.sh) to trace the same rays.
pub fn write_input(path: &Path, input: &BenchInput, reference: [&[f32]; 2]) -> std::io::Result<()> {
    let mut bytes = b"GLBENCH1".to_vec();
    let mut words = |values: &mut dyn Iterator<Item = u32>| values.for_each(|w| bytes.extend(w.to_le_bytes()));
    let (v, t) = (input.mesh.positions.len(), input.mesh.indices.len() / 3);
    words(&mut [v, t, input.coherent.len(), input.incoherent.len()].into_iter().map(|n| n as u32));
    words(&mut input.mesh.positions.iter().flat_map(|p| p.to_array()).map(f32::to_bits));
    words(&mut input.mesh.indices.iter().copied());
    for rays in [&input.coherent, &input.incoherent] {
        words(&mut rays.iter().flat_map(|r| [r.origin.to_array(), r.dir.to_array()].concat()).map(f32::to_bits));
    }
    for distances in reference {
        words(&mut distances.iter().map(|t| t.to_bits()));
    }
    std::fs::write(path, bytes)
}

/// Every ray's closest-hit distance on `input`'s mesh (∞ for a miss).
pub fn closest_distances(input: &BenchInput) -> Result<[Vec<f32>; 2], String> {
    let mesh = Mesh::compile(&input.mesh).map_err(|e| e.to_string())?;
    let trace = |rays: &Vec<Ray>| {
        rays.iter().map(|r| mesh.intersect(r, f32::INFINITY).map_or(f32::INFINITY, |h| h.t)).collect()
    };
    Ok([trace(&input.coherent), trace(&input.incoherent)])
}

/// The order in which camera rays of a square image (row by row) go into packets: 4×2
/// pixel tiles, as a renderer traces neighbouring pixels; row order if not square.
fn tile_order(n: usize) -> Vec<usize> {
    let side = (n as f64).sqrt().round() as usize;
    if side * side != n || !side.is_multiple_of(4) {
        return (0..n).collect();
    }
    (0..side / 2)
        .flat_map(|ty| (0..side / 4).flat_map(move |tx| (0..8).map(move |k| (2 * ty + k / 4) * side + 4 * tx + k % 4)))
        .collect()
}

/// Rays whose hit or miss, or hit distance beyond rounding, differs from `reference`.
fn disagreements(hits: &[Option<f32>], reference: &[f32]) -> usize {
    hits.iter()
        .zip(reference)
        .filter(|&(hit, &te)| match hit {
            Some(t) if te.is_finite() => (t - te).abs() > 1e-4 * te.max(1.0),
            None => te.is_finite(),
            Some(_) => true,
        })
        .count()
}

/// One JSON object of the measures; a value that is not a finite number (a rate over
/// no rays, or over a time too short to measure) is `null`.
pub fn to_json(measures: &[Measure]) -> String {
    let value = |v: f64| if v.is_finite() { v.to_string() } else { "null".into() };
    let fields: Vec<String> = measures.iter().map(|(k, v)| format!("\"{k}\": {}", value(*v))).collect();
    format!("{{{}}}", fields.join(", "))
}

/// A table for people.
pub fn to_table(measures: &[Measure]) -> String {
    let get = |k: &str| measures.iter().find(|(key, _)| key == k).map_or(f64::NAN, |m| m.1);
    let mut s = String::new();
    let tris = get("triangles");
    let _ =
        writeln!(s, "{tris} triangles, {} BVH nodes, {} triangle packets", get("bvh_nodes"), get("triangle_packets"));
    let _ = writeln!(
        s,
        "build: {:.3} s CPU, {:.3} s wall on {} threads",
        get("build_s"),
        get("build_wall_s"),
        get("threads")
    );
    let threads = get("trace_threads");
    let clock = if threads == 1.0 { "Mrays per CPU second on one thread" } else { "Mrays per second" };
    let _ = writeln!(s, "rays on {threads} thread(s), {clock}: median (slowest – fastest run)");
    for kind in ["coherent", "incoherent"] {
        for (query, packet) in [("closest", ""), ("any", ""), ("closest", "_packet"), ("any", "_packet")] {
            let key = format!("{kind}_{query}{packet}_rays_per_s");
            let [median, min, max] = ["", "_min", "_max"].map(|end| get(&format!("{key}{end}")) / 1e6);
            let how = if packet.is_empty() { String::new() } else { format!("  in packets of {PACKET}") };
            let _ = writeln!(s, "  {kind:10} {query:7} {median:8.3} ({min:.3} – {max:.3}){how}");
        }
    }
    let _ = writeln!(s, "memory: {:.1} bytes per triangle", get("memory_bytes") / tris);
    s
}

/// Best of three runs of `f`, timed by `clock` (seconds since the instant it is given,
/// from any zero point).
pub fn best_of_3<T>(clock: impl Fn(Instant) -> f64, mut f: impl FnMut() -> T) -> (f64, T) {
    let (mut best, mut out) = (f64::INFINITY, None);
    let origin = Instant::now();
    for _ in 0..3 {
        // The last run's result is freed before the clock starts, as Embree's scene is
        // released before its timed build in bench/embree_native.cpp.
        drop(out.take());
        let start = clock(origin);
        let value = f();
        best = best.min(clock(origin) - start);
        out = Some(value);
    }
    (best, out.expect("ran three times"))
}

/// CPU time of this thread; wall time since `wall` where unknown.
pub fn thread_cpu_seconds(wall: Instant) -> f64 {
    #[cfg(target_os = "linux")]
    let clock = cpu_clock(libc::CLOCK_THREAD_CPUTIME_ID);
    #[cfg(not(target_os = "linux"))]
    let clock = None;
    clock.unwrap_or_else(|| wall.elapsed().as_secs_f64())
}

/// CPU time of the whole process, every thread; wall time since `wall` where unknown.
pub fn process_cpu_seconds(wall: Instant) -> f64 {
    #[cfg(target_os = "linux")]
    let clock = cpu_clock(libc::CLOCK_PROCESS_CPUTIME_ID);
    #[cfg(not(target_os = "linux"))]
    let clock = None;
    clock.unwrap_or_else(|| wall.elapsed().as_secs_f64())
}

/// Linux's `clock_gettime` on a CPU-time clock, in seconds: exact to the nanosecond,
/// where `/proc`'s counters advance only at scheduler ticks.
#[cfg(target_os = "linux")]
fn cpu_clock(clock: libc::clockid_t) -> Option<f64> {
    // SAFETY: a timespec is plain integers (and, on some targets, padding), so all
    // zeros is a valid one.
    let mut t: libc::timespec = unsafe { std::mem::zeroed() };
    // SAFETY: clock_gettime writes one timespec to `t`, which outlives the call.
    let ok = unsafe { libc::clock_gettime(clock, &mut t) } == 0;
    ok.then_some(t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9)
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
        // SAFETY: glibc's malloc_trim takes a byte count and only touches the allocator's own state.
        unsafe { libc::malloc_trim(0) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closest hit of `ray` among all triangles, tried one by one (Möller–Trumbore
    /// in f64), or ∞ for a miss: a reference that shares no code with the BVH.
    fn brute_force_t(mesh: &MeshDesc, ray: &Ray) -> f32 {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let mut closest = f64::INFINITY;
        for tri in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize].as_dvec3());
            let (e1, e2) = (b - a, c - a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-12 {
                continue;
            }
            let s = o - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = d.dot(q) / det;
            let t = e2.dot(q) / det;
            if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0 {
                closest = closest.min(t);
            }
        }
        closest as f32
    }

    /// A small generated scene runs end to end: packets and single rays agree (`run`
    /// checks), every ray finds the hit a brute-force search over all triangles finds,
    /// and the GLBENCH1 reader reads what the layout says.
    #[test]
    fn small_benchmark_runs_and_round_trips() {
        let mut input = generate(20, 40, 16, 500);
        assert_eq!(input.mesh.indices.len(), 3 * 2 * 20 * 40);
        input.reference = [&input.coherent, &input.incoherent]
            .map(|rays| rays.iter().map(|r| brute_force_t(&input.mesh, r)).collect());
        let measures = run(&input, BenchOptions { threads: 2, rounds: 1 }, |_| {}).unwrap();
        let get = |k: &str| measures.iter().find(|(key, _)| key == k).unwrap().1;
        assert_eq!(get("triangles"), (2 * 20 * 40) as f64);
        for (name, rays, reference) in
            [("coherent", &input.coherent, &input.reference[0]), ("incoherent", &input.incoherent, &input.reference[1])]
        {
            assert_eq!(get(&format!("{name}_disagree_with_reference")), 0.0, "{name} rays");
            let hits = reference.iter().filter(|t| t.is_finite()).count();
            assert_eq!(get(&format!("{name}_hit_fraction")), hits as f64 / rays.len() as f64, "{name} rays");
        }
        assert!(get("coherent_hit_fraction") > 0.3 && get("incoherent_hit_fraction") > 0.05);
        assert!(to_table(&measures).contains("bytes per triangle"));

        let mut bytes = b"GLBENCH1".to_vec();
        let words = |v: &[u32], out: &mut Vec<u8>| v.iter().for_each(|w| out.extend(w.to_le_bytes()));
        words(&[3, 1, 1, 0], &mut bytes);
        let floats = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0].map(f32::to_bits);
        words(&floats, &mut bytes);
        words(&[0, 1, 2], &mut bytes);
        words(&[0.2f32, 0.2, 1.0, 0.0, 0.0, -1.0].map(f32::to_bits), &mut bytes);
        words(&[1.0f32.to_bits()], &mut bytes);
        let path = std::env::temp_dir().join(format!("glint-bench-{}.bin", std::process::id()));
        std::fs::write(&path, &bytes).unwrap();
        let read = read_input(&path).unwrap();
        assert_eq!(read.mesh.positions.len(), 3);
        assert_eq!(read.coherent.len(), 1);
        assert_eq!(read.reference[0], vec![1.0]);
        std::fs::write(&path, &bytes[..bytes.len() - 2]).unwrap();
        assert!(read_input(&path).unwrap_err().contains("ends early"));
        let _ = std::fs::remove_file(&path);
    }
}
