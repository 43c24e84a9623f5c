#!/usr/bin/env python3
"""Renders a Mitsuba 3 scene to an EXR through the Python API, timed, on a fixed thread count.

    python3 bench/mitsuba/render.py bench/mitsuba/cornell.xml -o out.exr \
        --variant llvm_ad_rgb --threads 2 --spp 256 --seed 1 -D width=256 -D height=256

Why not the `mitsuba` command: in Mitsuba 3.9.1 `mitsuba -t 2` on this 2-core machine writes
the image and then never exits (a deadlock at shutdown whenever -t is below the default thread
count); the Python API with drjit.set_thread_count(N) does not hang.

The samples are taken in passes of at most --pass-spp samples per pixel (the LLVM variant keeps
every sample of a pass in flight at once, so one 4096-spp pass at 512x512 would need a lot of
memory); the passes are averaged with weights proportional to their spp, which for the box
filter the scenes use is exactly the image one pass with all samples would give.
Seeds: the scene's `seed` default (the sampler's base seed) is set to --seed, and pass i is
rendered with mi.render(seed = seed * 65536 + i), so two renders with different --seed values
never share a random stream.

Warnings and errors that Mitsuba logs are printed, counted in the JSON summary, and with
--strict make the command fail. The last line on stdout is a JSON summary (timings in seconds).
"""

import argparse
import json
import math
import os
import sys
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("-o", "--output", required=True, help="EXR to write")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="scalar_rgb or llvm_ad_rgb (default)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--spp", type=int, help="samples per pixel (sets the scene's `spp` default)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--pass-spp", type=int, default=64, help="most samples per pixel in one pass (default 64)")
    ap.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE", help="override a scene <default>")
    ap.add_argument("--strict", action="store_true", help="fail if Mitsuba logs any warning")
    ap.add_argument("-q", "--quiet", action="store_true", help="print only the JSON summary")
    args = ap.parse_args()

    if args.variant.startswith("llvm") and not os.environ.get("DRJIT_LIBLLVM_PATH"):
        for cand in ("/usr/lib/x86_64-linux-gnu/libLLVM-19.so", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"):
            if os.path.exists(cand):
                os.environ["DRJIT_LIBLLVM_PATH"] = cand
                break

    try:
        import drjit as dr
        import mitsuba as mi
        import numpy as np
    except ImportError as e:
        sys.exit(f"render.py: {e}; install with: python3 -m pip install mitsuba numpy (see bench/mitsuba/README.md)")

    try:
        mi.set_variant(args.variant)
    except Exception as e:  # noqa: BLE001 - report any failure to load the variant plainly
        hint = ""
        if args.variant.startswith("llvm"):
            hint = " (the LLVM variants need libLLVM: apt-get install -y libllvm19 and DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so)"
        sys.exit(f"render.py: cannot use Mitsuba variant {args.variant}: {e}{hint}")
    dr.set_thread_count(args.threads)

    warnings = []

    class Recorder(mi.Appender):
        def append(self, level, text):
            if level >= mi.LogLevel.Warn:
                warnings.append(text)
                print(text, file=sys.stderr)
            elif not args.quiet and level >= mi.LogLevel.Info:
                print(text, file=sys.stderr)

        def log_progress(self, progress, name, formatted, eta, ptr=None):
            pass

    logger = mi.logger() if hasattr(mi, "logger") else mi.Thread.thread().logger()
    logger.clear_appenders()
    logger.add_appender(Recorder())
    logger.set_log_level(mi.LogLevel.Info)

    defines = {}
    for d in args.defines:
        if "=" not in d:
            sys.exit(f"render.py: -D expects NAME=VALUE, got {d!r}")
        k, v = d.split("=", 1)
        defines[k] = v
    if args.spp is not None:
        defines["spp"] = str(args.spp)
    defines["seed"] = str(args.seed)

    t0 = time.perf_counter()
    try:
        scene = mi.load_file(args.scene, **defines)
    except Exception as e:  # noqa: BLE001
        sys.exit(f"render.py: Mitsuba could not load {args.scene}: {e}")
    t_load = time.perf_counter() - t0

    sensor = scene.sensors()[0]
    spp = sensor.sampler().sample_count()
    w, h = (int(x) for x in sensor.film().crop_size())
    passes = max(1, math.ceil(spp / args.pass_spp))
    acc = None
    done = 0
    t1 = time.perf_counter()
    t_first = None
    for i in range(passes):
        n = min(args.pass_spp, spp - done)
        img = mi.render(scene, spp=n, seed=args.seed * 65536 + i)
        arr = np.array(img, dtype=np.float64)[..., :3]
        acc = arr * n if acc is None else acc + arr * n
        done += n
        if t_first is None:
            t_first = time.perf_counter() - t1
    t_render = time.perf_counter() - t1
    out = (acc / done).astype(np.float32)
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    mi.Bitmap(out, mi.Bitmap.PixelFormat.RGB).write(args.output)

    summary = {
        "scene": os.path.basename(args.scene),
        "variant": args.variant,
        "threads": args.threads,
        "width": w,
        "height": h,
        "spp": done,
        "seed": args.seed,
        "passes": passes,
        "load_s": round(t_load, 4),
        "render_s": round(t_render, 4),
        "first_pass_s": round(t_first, 4),
        "total_s": round(t_load + t_render, 4),
        "samples_per_s": round(w * h * done / t_render, 1),
        "warnings": len(warnings),
        "output": args.output,
    }
    print(json.dumps(summary))
    if args.strict and warnings:
        sys.exit(f"render.py: Mitsuba logged {len(warnings)} warning(s) on {args.scene} (--strict)")


if __name__ == "__main__":
    main()
