#!/usr/bin/env python3
"""Writes the small assets the Mitsuba comparison scenes use, into bench/mitsuba/assets/.

    python3 bench/mitsuba/make_assets.py

Deterministic (no randomness): running it again rewrites identical files.

- envmap.exr     256x128 RGB float32 equirectangular map: a sky gradient, a darker ground and a
                 bright sun-like Gaussian blob, laid out the way Mitsuba's `envmap` reads it
                 (see README.md, "Environment map convention").
- ring.obj       an emissive ring of 320 separated small quads (640 triangles), flat, normals
                 (by winding) pointing down -y; no vertex normals, no uvs.
- panel.ply      an ASCII PLY grid of 8x8 small quads (128 triangles) with gaps, in the z = 0
                 plane, normals (by winding) +z; vertices only.

Needs numpy, and Mitsuba 3 (`mi.Bitmap`) or the `OpenEXR` package to write the EXR.
"""

import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "assets")

# Sun direction in world space (y up): 35 degrees above the horizon.
SUN_ELEVATION = math.radians(35.0)
SUN_AZIMUTH = math.radians(-40.0)  # measured in the x-z plane, see sun_direction()
SUN_SIGMA = math.radians(2.5)  # angular standard deviation of the Gaussian blob
SUN_PEAK = np.array([130.0, 118.0, 100.0])


def sun_direction():
    c = math.cos(SUN_ELEVATION)
    return np.array([c * math.sin(SUN_AZIMUTH), math.sin(SUN_ELEVATION), -c * math.cos(SUN_AZIMUTH)])


def envmap(width=256, height=128):
    """Pixel (row i, column j) at its centre maps to u = (j+0.5)/W, v = (i+0.5)/H and to the
    direction Mitsuba's envmap gives it: theta = v*pi from +y, phi = u*2*pi, with
    d = (sin(theta) sin(phi), cos(theta), -sin(theta) cos(phi))."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    phi = (u * 2.0 * math.pi)[None, :]
    theta = (v * math.pi)[:, None]
    d = np.stack(
        np.broadcast_arrays(np.sin(theta) * np.sin(phi), np.cos(theta), -np.sin(theta) * np.cos(phi)),
        axis=-1,
    )
    up = d[..., 1:2]
    horizon = np.array([0.6, 0.62, 0.7])
    zenith = np.array([0.12, 0.25, 0.6])
    t = np.clip(up, 0.0, 1.0) ** 0.6
    sky = (1.0 - t) * horizon + t * zenith
    ground = np.array([0.2, 0.17, 0.14]) * (0.6 + 0.4 * np.clip(-up, 0.0, 1.0))
    img = np.where(up >= 0.0, sky, ground)
    cos_angle = np.clip(d @ sun_direction(), -1.0, 1.0)
    angle = np.arccos(cos_angle)[..., None]
    img = img + SUN_PEAK * np.exp(-0.5 * (angle / SUN_SIGMA) ** 2)
    return img.astype(np.float32)


def write_exr(path, img):
    try:
        import mitsuba as mi

        mi.set_variant("scalar_rgb")
        mi.Bitmap(img, mi.Bitmap.PixelFormat.RGB).write(path)
        return
    except ImportError:
        pass
    try:
        import OpenEXR  # OpenEXR >= 3.3 Python API
    except ImportError:
        sys.exit("make_assets.py: writing the EXR needs Mitsuba 3 (pip install mitsuba) or OpenEXR (pip install OpenEXR)")
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}
    with OpenEXR.File(header, {"RGB": img}) as f:
        f.write(path)


def ring(segments=160, bands=2, r_inner=0.35, r_outer=0.75, y=0.0, gap=0.12):
    """Flat annulus of separated quads, each shrunk by `gap` around its centre; faces point -y."""
    verts, faces = [], []
    radii = np.linspace(r_inner, r_outer, bands + 1)
    for b in range(bands):
        for s in range(segments):
            a0 = 2 * math.pi * s / segments
            a1 = 2 * math.pi * (s + 1) / segments
            r0, r1 = radii[b], radii[b + 1]
            corners = [
                (r0 * math.cos(a0), r0 * math.sin(a0)),
                (r1 * math.cos(a0), r1 * math.sin(a0)),
                (r1 * math.cos(a1), r1 * math.sin(a1)),
                (r0 * math.cos(a1), r0 * math.sin(a1)),
            ]
            cx = sum(c[0] for c in corners) / 4
            cz = sum(c[1] for c in corners) / 4
            base = len(verts)
            for x, z in corners:
                verts.append((cx + (1 - gap) * (x - cx), y, cz + (1 - gap) * (z - cz)))
            # With x = r cos a, z = r sin a, the order (r0,a0) (r1,a0) (r1,a1) winds so that
            # cross(p1 - p0, p2 - p0) points along -y.
            faces.append((base, base + 1, base + 2))
            faces.append((base, base + 2, base + 3))
    return verts, faces


def check_normals(verts, faces, expected):
    v = np.array(verts)
    for f in faces:
        n = np.cross(v[f[1]] - v[f[0]], v[f[2]] - v[f[0]])
        assert np.dot(n, expected) > 0, "winding does not give the expected normal"


def write_obj(path, verts, faces, comment):
    with open(path, "w", newline="\n") as f:
        f.write(f"# {comment}\n# written by bench/mitsuba/make_assets.py\n")
        for x, y, z in verts:
            f.write(f"v {x:.6f} {y:.6f} {z:.6f}\n")
        for a, b, c in faces:
            f.write(f"f {a + 1} {b + 1} {c + 1}\n")


def panel(n=8, size=1.0, gap=0.2):
    """n x n separated squares in the z = 0 plane over [-size, size]^2, faces +z."""
    verts, faces = [], []
    cell = 2 * size / n
    half = 0.5 * cell * (1 - gap)
    for i in range(n):
        for j in range(n):
            cx = -size + (i + 0.5) * cell
            cy = -size + (j + 0.5) * cell
            base = len(verts)
            verts += [(cx - half, cy - half, 0.0), (cx + half, cy - half, 0.0), (cx + half, cy + half, 0.0), (cx - half, cy + half, 0.0)]
            faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return verts, faces


def write_ply(path, verts, faces, comment):
    with open(path, "w", newline="\n") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"comment {comment}\ncomment written by bench/mitsuba/make_assets.py\n")
        f.write(f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for x, y, z in verts:
            f.write(f"{x:.6f} {y:.6f} {z:.6f}\n")
        for a, b, c in faces:
            f.write(f"3 {a} {b} {c}\n")


def main():
    os.makedirs(OUT, exist_ok=True)
    write_exr(os.path.join(OUT, "envmap.exr"), envmap())
    verts, faces = ring()
    check_normals(verts, faces, np.array([0.0, -1.0, 0.0]))
    write_obj(os.path.join(OUT, "ring.obj"), verts, faces, f"emissive ring: {len(faces)} triangles, normals -y")
    verts, faces = panel()
    check_normals(verts, faces, np.array([0.0, 0.0, 1.0]))
    write_ply(os.path.join(OUT, "panel.ply"), verts, faces, f"emissive panel: {len(faces)} triangles, normals +z")
    total = sum(os.path.getsize(os.path.join(OUT, n)) for n in os.listdir(OUT))
    print(f"wrote {OUT}: {', '.join(sorted(os.listdir(OUT)))} ({total / 1024:.0f} KiB)")


if __name__ == "__main__":
    main()
