"""How a glint render scales on Dask: speed-up of 1, 2 and 4 local workers over one
machine's single render, the scene upload cost, the per-part overhead, and a model of
the scaling checked against the runs.

    python bench/dask_scaling.py [SCENE] [--spp N] [--width W] [--height H] [--parts P]

Each LocalCluster worker is a process with one thread, as one machine of a cluster would
be with one core; on this 2-core machine, 4 workers share 2 cores, so their row shows
the cost of oversubscription, not more speed. Needs `pip install . "dask[distributed]"`.

The model: T(w) = upload + T1 / min(w, cores) + parts × overhead / w + merge, where T1
is the single-threaded render time, `upload` the scatter of the prepared job, `overhead`
what one part costs beyond its share of the tracing (task round trip, the part's
encoding and transfer), and `merge` the time to add the parts up as they arrive.
"""

import argparse
import os
import pickle
import time

import numpy as np

import glint
import glint.distributed
from dask.distributed import Client, LocalCluster


def timed(f, *args, **kwargs):
    start = time.perf_counter()
    result = f(*args, **kwargs)
    return time.perf_counter() - start, result


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", nargs="?", default=os.path.join(os.path.dirname(__file__), "../scenes/cornell-path.glint"))
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--height", type=int, default=240)
    parser.add_argument("--parts", type=int, default=16)
    args = parser.parse_args()
    settings = dict(spp=args.spp, width=args.width, height=args.height)
    scene = glint.load(args.scene)
    cores = os.cpu_count() or 1

    t1, reference = timed(glint.render, scene, threads=1, progress=False, **settings)
    job = glint._glint.prepare(scene, **settings)
    payload = len(pickle.dumps(job))
    # The per-part overhead, measured without a cluster: one part's encoding and merge
    # beyond its share of the render.
    tp, part = timed(glint._glint.render_job_part, job, 0, args.parts, threads=1)
    merger = glint._glint.Merger()
    tm, _ = timed(merger.add, part)
    print(f"scene {os.path.basename(args.scene)} {args.width}x{args.height} at {args.spp} spp, {args.parts} parts, {cores} cores")
    print(f"single render on one thread: {t1:.2f} s; prepared job {payload / 1024:.0f} KiB pickled; "
          f"one part {tp:.3f} s (its share {t1 / args.parts:.3f} s), {len(part) / 1024:.0f} KiB, merged in {tm * 1000:.1f} ms")
    print(f"{'workers':>8} {'upload s':>9} {'render s':>9} {'speed-up':>9} {'model s':>8} {'identical':>10}")
    for workers in (1, 2, 4):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                client.wait_for_workers(workers)
                upload, shared = timed(client.scatter, job, broadcast=True, hash=False)
                del shared
                # One warm-up render so every worker has imported glint and compiled the scene.
                glint.distributed.render(scene, client, parts=workers, progress=False, **settings)
                elapsed, image = timed(glint.distributed.render, scene, client, parts=args.parts, progress=False, **settings)
                overhead = max(0.0, tp - t1 / args.parts) + tm
                model = upload + t1 / min(workers, cores) + args.parts * overhead / workers
                same = np.array_equal(np.asarray(image).view(np.uint32), np.asarray(reference).view(np.uint32))
                print(f"{workers:>8} {upload:>9.3f} {elapsed:>9.2f} {t1 / elapsed:>8.2f}x {model:>8.2f} {str(same):>10}")


if __name__ == "__main__":
    main()
