#!/usr/bin/env python3
"""Image metrics and Markdown tables for bench/mitsuba_compare.sh and bench/mitsuba_speed.sh.

    compare.py rmse TEST.exr REF.exr                  # one number
    compare.py table --out DIR MANIFEST.tsv     # scene, glint, Mitsuba A, B, ref, glint s, A json
    compare.py speed --gt GT.exr --mitsuba LABEL:EXR:SECONDS:SPP [...] --glint EXR:SECONDS:SPP [...] [--glint-label L]

The error measure is the relative mean squared error

    rMSE(test, ref) = mean over pixels and RGB channels of (test - ref)^2 / (ref^2 + eps),  eps = 1e-2

computed on both images clamped to [0, 50] first (CLAMP). The relative form weighs dark and
bright regions alike (a plain MSE is dominated by the light source and by highlights); eps
keeps near-black pixels from blowing up; the clamp keeps rare fireflies - single samples of
huge value that both renderers produce on caustic paths - from dominating a mean of a few
hundred thousand terms (the Cornell light is 17 and nothing in the scenes should legitimately
exceed 50 in a converged image; where it does - the sun reflected in the smooth copper
sphere of envmap.xml - both images are clipped alike). The reference is always the second argument: the noise floor is
rMSE(Mitsuba B, Mitsuba A), the test rMSE(glint, Mitsuba A), both with Mitsuba A in the
denominator.

When two Mitsuba renders A and B and the glint render are independent and unbiased with the
same number of samples per pixel, E[rMSE(glint, A)] ~ var_glint + var_A and E[rMSE(B, A)] ~
2 var_A: a ratio near 1 says glint agrees with Mitsuba and is about as noisy per sample; a
ratio well above 1 is either bias (look at the mean ratio and the difference image) or more
noise per sample (look at rMSE of glint against a converged reference, when there is one).
"""

import argparse
import math
import os
import sys

import numpy as np

EPS = 1e-2
CLAMP = 50.0

_mi = None


def _mitsuba():
    global _mi
    if _mi is None:
        import mitsuba as mi

        mi.set_variant("scalar_rgb")
        _mi = mi
    return _mi


def load(path):
    """An EXR (or anything Mitsuba's Bitmap reads) as float64 HxWx3 linear RGB."""
    if not os.path.exists(path):
        sys.exit(f"compare.py: {path} does not exist")
    try:
        mi = _mitsuba()
        bmp = mi.Bitmap(path)
        if bmp.pixel_format() not in (mi.Bitmap.PixelFormat.RGB, mi.Bitmap.PixelFormat.RGBA):
            bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
        arr = np.array(bmp, dtype=np.float64)
    except ImportError:
        import OpenEXR

        with OpenEXR.File(path) as f:
            ch = f.channels()
            if "RGB" in ch:
                arr = np.asarray(ch["RGB"].pixels, dtype=np.float64)
            elif "RGBA" in ch:
                arr = np.asarray(ch["RGBA"].pixels, dtype=np.float64)
            else:
                arr = np.stack([np.asarray(ch[c].pixels, dtype=np.float64) for c in "RGB"], axis=-1)
    if arr.ndim == 2:
        arr = np.repeat(arr[..., None], 3, axis=-1)
    arr = arr[..., :3]
    if not np.all(np.isfinite(arr)):
        bad = int(np.count_nonzero(~np.isfinite(arr)))
        print(f"compare.py: warning: {path} has {bad} NaN/inf values, counted as 0", file=sys.stderr)
        arr = np.nan_to_num(arr, nan=0.0, posinf=0.0, neginf=0.0)
    return arr


def rmse(test, ref):
    if test.shape != ref.shape:
        sys.exit(f"compare.py: image sizes differ: {test.shape[1]}x{test.shape[0]} vs {ref.shape[1]}x{ref.shape[0]}")
    t = np.clip(test, 0.0, CLAMP)
    r = np.clip(ref, 0.0, CLAMP)
    return float(np.mean((t - r) ** 2 / (r * r + EPS)))


def write_png(path, img):
    """Tone mapped (clamped, sRGB) PNG."""
    mi = _mitsuba()
    mi.util.write_bitmap(path, np.clip(img, 0.0, 1.0).astype(np.float32))


def write_diff(path, test, ref):
    """Side by side: test | ref | signed relative difference (red: test brighter, blue: darker),
    the difference smoothed over 5x5 pixels so noise averages out and bias shows."""
    t = np.clip(test, 0.0, CLAMP).mean(axis=-1)
    r = np.clip(ref, 0.0, CLAMP).mean(axis=-1)
    d = t - r
    k = 2
    pad = np.pad(d, k, mode="edge")
    padr = np.pad(r, k, mode="edge")
    ds = np.zeros_like(d)
    rs = np.zeros_like(r)
    for dy in range(2 * k + 1):
        for dx in range(2 * k + 1):
            ds += pad[dy : dy + d.shape[0], dx : dx + d.shape[1]]
            rs += padr[dy : dy + d.shape[0], dx : dx + d.shape[1]]
    rel = np.clip(ds / (np.abs(rs) + 1e-2 * (2 * k + 1) ** 2) * 4.0, -1.0, 1.0)  # +-25% = full colour
    diff = np.stack([np.clip(rel, 0, 1), np.zeros_like(rel), np.clip(-rel, 0, 1)], axis=-1)
    sheet = np.concatenate([np.clip(test, 0, 1), np.clip(ref, 0, 1), diff], axis=1)
    write_png(path, sheet)


def fmt(x):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "n/a"
    return f"{x:.3g}" if abs(x) < 1e4 else f"{x:.3e}"


def cmd_rmse(args):
    print(f"{rmse(load(args.test), load(args.ref)):.6g}")


def _json_seconds(path):
    import json

    try:
        with open(path) as f:
            return float(json.load(f)["total_s"])
    except (OSError, ValueError, KeyError):
        return None


def cmd_table(args):
    """Reads a tab-separated manifest, one scene a line:
    scene, glint exr, Mitsuba A exr, Mitsuba B exr, converged reference exr, glint seconds,
    Mitsuba A summary json ('-' where absent; a glint exr of '-' means glint was not run or failed)."""
    rows = []
    with open(args.manifest) as f:
        for line in f:
            if line.strip():
                cols = line.rstrip("\n").split("\t")
                if len(cols) != 7:
                    sys.exit(f"compare.py: manifest line needs 7 tab-separated fields: {line!r}")
                rows.append([None if c == "-" else c for c in cols])
    has_ref = any(r[4] for r in rows)
    head = "| scene | rMSE glint vs Mitsuba | noise floor (Mitsuba vs Mitsuba) | ratio | mean glint / Mitsuba |"
    sep = "| --- | ---: | ---: | ---: | ---: |"
    if has_ref:
        head += " rMSE vs converged ref: glint | Mitsuba |"
        sep += " ---: | ---: |"
    head += " time glint (s) | time Mitsuba (s) |"
    sep += " ---: | ---: |"
    print(head)
    print(sep)
    for scene, g, a, b, ref, g_secs, m_json in rows:
        ma, mb = load(a), load(b)
        e_floor = rmse(mb, ma)
        ga = load(g) if g else None
        if ga is not None:
            e_glint = rmse(ga, ma)
            ratio = e_glint / e_floor if e_floor > 0 else float("inf")
            mean_ratio = float(np.clip(ga, 0, CLAMP).mean() / max(np.clip(ma, 0, CLAMP).mean(), 1e-12))
            cells = [fmt(e_glint), fmt(e_floor), fmt(ratio), f"{mean_ratio:.4f}"]
        else:
            cells = ["n/a", fmt(e_floor), "n/a", "n/a"]
        if has_ref:
            r = load(ref) if ref else None
            cells += [fmt(rmse(ga, r)) if (r is not None and ga is not None) else "n/a", fmt(rmse(ma, r)) if r is not None else "n/a"]
        cells += [fmt(float(g_secs)) if g_secs else "n/a", fmt(_json_seconds(m_json)) if m_json else "n/a"]
        print(f"| {scene} | " + " | ".join(cells) + " |")
        if args.out and ga is not None:
            write_diff(os.path.join(args.out, f"{scene}-diff.png"), ga, ma)
    if args.out and any(r[1] for r in rows):
        print(f"\nDifference images, glint | Mitsuba A | smoothed relative difference (red: glint brighter, blue: darker; full colour = 25%): {args.out}/SCENE-diff.png")


def _interp_time(points, target):
    """Time at which the error curve (time, err) reaches `target`, interpolating linearly in
    log(err) over log(time); outside the measured range, extrapolates along the nearest two
    points' slope. Returns (time, how) with how = 'interpolated' or 'extrapolated'."""
    pts = sorted((t, e) for t, e in points if t > 0 and e > 0)
    if len(pts) < 2:
        return None, "too few points"
    lt = [math.log(t) for t, _ in pts]
    le = [math.log(e) for _, e in pts]
    lx = math.log(target)
    for i in range(len(pts) - 1):
        lo, hi = sorted((le[i], le[i + 1]))
        if lo <= lx <= hi and le[i] != le[i + 1]:
            f = (lx - le[i]) / (le[i + 1] - le[i])
            return math.exp(lt[i] + f * (lt[i + 1] - lt[i])), "interpolated"
    i = 0 if lx > le[0] else len(pts) - 2
    if le[i + 1] == le[i]:
        return None, "flat error curve"
    slope = (lt[i + 1] - lt[i]) / (le[i + 1] - le[i])
    return math.exp(lt[i] + slope * (lx - le[i])), "extrapolated"


def cmd_speed(args):
    gt = load(args.gt)
    h, w = gt.shape[:2]
    rows = []
    for spec in args.mitsuba:
        label, exr, secs, spp = spec.rsplit(":", 3)
        rows.append((label, int(spp), float(secs), rmse(load(exr), gt)))
    glint = []
    for spec in args.glint:
        exr, secs, spp = spec.rsplit(":", 2)
        glint.append((int(spp), float(secs), rmse(load(exr), gt)))
    print(f"Ground truth: {os.path.basename(args.gt)} ({w}x{h}); rMSE with eps={EPS}, clamp [0, {CLAMP}]\n")
    print("| renderer | spp | time (s) | samples/s | rMSE vs ground truth | rMSE x time |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for label, spp, secs, err in rows:
        print(f"| {label} | {spp} | {secs:.2f} | {fmt(w * h * spp / secs)} | {fmt(err)} | {fmt(err * secs)} |")
    for spp, secs, err in glint:
        print(f"| {args.glint_label} | {spp} | {secs:.2f} | {fmt(w * h * spp / secs)} | {fmt(err)} | {fmt(err * secs)} |")
    if glint:
        print("\n| target | target rMSE | target time (s) | glint time to reach it (s) | glint / Mitsuba time |")
        print("| --- | ---: | ---: | ---: | ---: |")
        pts = [(secs, err) for _, secs, err in glint]
        for label, spp, secs, err in rows:
            t, how = _interp_time(pts, err)
            if t is None:
                print(f"| {label} {spp} spp | {fmt(err)} | {secs:.2f} | n/a ({how}) | n/a |")
            else:
                print(f"| {label} {spp} spp | {fmt(err)} | {secs:.2f} | {t:.2f} ({how}) | {t / secs:.3g} |")
    print("\nrMSE x time is constant for an unbiased renderer once the ground truth's own noise is negligible: lower is more efficient.")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("rmse", help="rMSE of TEST against REF")
    p.add_argument("test")
    p.add_argument("ref")
    p.set_defaults(fn=cmd_rmse)
    p = sub.add_parser("table", help="glint vs Mitsuba table from a manifest (see cmd_table)")
    p.add_argument("--out", help="folder for difference images")
    p.add_argument("manifest")
    p.set_defaults(fn=cmd_table)
    p = sub.add_parser("speed", help="equal-time / equal-error table against a ground truth")
    p.add_argument("--gt", required=True)
    p.add_argument("--mitsuba", action="append", default=[], metavar="LABEL:EXR:SECONDS:SPP")
    p.add_argument("--glint", action="append", default=[], metavar="EXR:SECONDS:SPP")
    p.add_argument("--glint-label", default="glint", help="what the glint rows are called (e.g. its sampler)")
    p.set_defaults(fn=cmd_speed)
    args = ap.parse_args()
    args.fn(args)


if __name__ == "__main__":
    main()
