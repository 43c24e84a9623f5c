"""Generates the shared mesh and rays for bench/embree_compare.sh and times Embree on them.

Writes DIR/scene.bin (read by `glint bench --input` and the obvhs_bench example too) and prints one JSON line of
Embree's timings. Layout of scene.bin, little-endian:
  b"GLBENCH1", u32 vertex count V, u32 triangle count T, u32 coherent rays C, u32 incoherent rays I,
  f32[V*3] positions, u32[T*3] indices, f32[C*6] coherent rays (origin, direction),
  f32[I*6] incoherent rays, then f32[C] and f32[I]: Embree's closest t (inf = miss).
"""
import ctypes
import json
import os
import sys
import time

import numpy as np
from embreex import rtcore as rtc
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh


def displaced_sphere(n_lat, n_lon):
    """A UV sphere with a bumpy radius: 2·n_lat·n_lon triangles, watertight at the seam."""
    theta = np.linspace(0.0, np.pi, n_lat + 1, dtype=np.float64)
    phi = np.linspace(0.0, 2.0 * np.pi, n_lon, endpoint=False, dtype=np.float64)
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    r = 1.0 + 0.04 * np.sin(13.0 * th) * np.sin(17.0 * ph) + 0.02 * np.sin(41.0 * th + 5.0 * ph)
    pos = np.stack([r * np.sin(th) * np.cos(ph), r * np.cos(th), r * np.sin(th) * np.sin(ph)], axis=-1)
    pos = pos.reshape(-1, 3).astype(np.float32)
    i = np.arange(n_lat)[:, None]
    j = np.arange(n_lon)[None, :]
    a = i * n_lon + j
    b = i * n_lon + (j + 1) % n_lon
    c = (i + 1) * n_lon + (j + 1) % n_lon
    d = (i + 1) * n_lon + j
    tris = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return pos, tris.astype(np.uint32)


def coherent_rays(side):
    """A pinhole camera at (0, 0.3, 3) looking at the origin, one ray per pixel, row by row."""
    y, x = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    px = (x + 0.5) / side * 2.0 - 1.0
    py = 1.0 - (y + 0.5) / side * 2.0
    tan = np.tan(np.radians(20.0))
    d = np.stack([px * tan, py * tan - 0.1, -np.ones_like(px)], -1).reshape(-1, 3)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    o = np.broadcast_to(np.array([0.0, 0.3, 3.0]), d.shape)
    return o.astype(np.float32), d.astype(np.float32)


def incoherent_rays(n, rng):
    """Random origins in [-1.5, 1.5]³ and directions uniform on the sphere."""
    o = rng.uniform(-1.5, 1.5, size=(n, 3))
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return o.astype(np.float32), d.astype(np.float32)


def timed(f, repeats=3):
    """Best of `repeats` in CPU seconds of the whole process (every Embree thread counts),
    so other work on a busy machine skews the numbers less."""
    best, out = float("inf"), None
    for _ in range(repeats):
        start = time.process_time()
        out = f()
        best = min(best, time.process_time() - start)
    return best, out


def resident_bytes():
    """The process's resident set now: /proc/self/statm's second field, in pages."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def release_free_heap():
    """Returns the heap's free pages to the OS (glibc's malloc_trim), so that the resident
    set counts what is in use rather than what the allocator kept; a no-op elsewhere."""
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def embree_memory(pos, tris32):
    """Resident-set growth, in bytes, from before an Embree scene over the mesh is made
    to after it is committed, with the scene still alive (as it stands, after freed heap
    is given back to the OS). It counts Embree's own copy of the vertex and index buffers
    (embreex fills buffers that Embree allocates with rtcSetNewGeometryBuffer; it does not
    share numpy's memory) plus the BVH and its triangle leaves. A one-triangle scene is
    committed first on the same device, so Embree's threads and fixed allocations are
    not counted."""
    device = rtc.EmbreeDevice()
    probe_o = np.array([[0.2, 0.2, 1.0]], dtype=np.float32)
    probe_d = np.array([[0.0, 0.0, -1.0]], dtype=np.float32)
    warm = rtcs.EmbreeScene(device)
    one = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    TriangleMesh(warm, one, np.array([[0, 1, 2]], dtype=np.int32))
    warm.run(probe_o, probe_d)
    release_free_heap()
    before = resident_bytes()
    scene = rtcs.EmbreeScene(device)
    TriangleMesh(scene, pos, tris32)
    scene.run(probe_o, probe_d)
    grown = resident_bytes() - before
    release_free_heap()
    grown_trimmed = resident_bytes() - before
    del scene, warm
    return grown, grown_trimmed


def main():
    out_dir = sys.argv[1]
    n_lat, n_lon, side, n_random = 500, 1000, 1024, 1 << 20
    pos, tris = displaced_sphere(n_lat, n_lon)
    tris32 = tris.astype(np.int32)
    # Memory is measured first, before the rays and timed builds have grown the heap.
    rss_growth, rss_growth_trimmed = embree_memory(pos, tris32)
    co, cd = coherent_rays(side)
    io, idir = incoherent_rays(n_random, np.random.default_rng(7))

    # Build: geometry upload plus the commit, which embreex does on the first query.
    def build_scene():
        scene = rtcs.EmbreeScene()
        TriangleMesh(scene, pos, tris32)
        scene.run(co[:1], cd[:1])
        return scene

    build, scene = timed(build_scene)

    results = {"triangles": int(len(tris)), "build_s": build, "rss_growth_bytes": rss_growth,
               "rss_growth_trimmed_bytes": rss_growth_trimmed}
    t_hits = {}
    for name, (o, d) in {"coherent": (co, cd), "incoherent": (io, idir)}.items():
        secs, hit = timed(lambda: scene.run(o, d, output=1))
        results[f"{name}_closest_rays_per_s"] = len(o) / secs
        tfar = np.where(hit["geomID"] >= 0, hit["tfar"], np.inf).astype(np.float32)
        t_hits[name] = tfar
        secs, _ = timed(lambda: scene.run(o, d, query="OCCLUDED"))
        results[f"{name}_any_rays_per_s"] = len(o) / secs
        results[f"{name}_hit_fraction"] = float(np.isfinite(tfar).mean())

    with open(f"{out_dir}/scene.bin", "wb") as f:
        f.write(b"GLBENCH1")
        f.write(np.array([len(pos), len(tris), len(co), len(io)], dtype="<u4").tobytes())
        for a in [pos, tris, np.concatenate([co, cd], 1), np.concatenate([io, idir], 1)]:
            f.write(np.ascontiguousarray(a).astype(a.dtype.newbyteorder("<")).tobytes())
        f.write(t_hits["coherent"].astype("<f4").tobytes())
        f.write(t_hits["incoherent"].astype("<f4").tobytes())
    print(json.dumps(results))


if __name__ == "__main__":
    main()
