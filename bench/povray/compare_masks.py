#!/usr/bin/env python3
"""Compares two coverage masks (binary PPM, P6): which pixels see an object.

Prints the share of pixels on which both renderers agree, and splits the disagreeing
pixels into silhouette pixels (within one pixel of an edge in either mask, where the
two renderers' sub-pixel sample positions and root tolerances decide) and interior
pixels (real disagreements about the shape). Optionally writes a difference image:
red = only the first renderer sees an object, green = only the second.
Pure Python, no dependencies.
"""

import argparse
import sys

import ppm


def read_ppm(path):
    width, height, values = ppm.read(path)
    mask = [max(values[3 * p:3 * p + 3]) >= 0.5 for p in range(width * height)]
    return width, height, mask


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("first")
    parser.add_argument("second")
    parser.add_argument("--name", default="scene")
    parser.add_argument("--diff", help="write a difference image (PPM) here")
    args = parser.parse_args()
    w1, h1, a = read_ppm(args.first)
    w2, h2, b = read_ppm(args.second)
    if (w1, h1) != (w2, h2):
        sys.exit(f"sizes differ: {w1}x{h1} vs {w2}x{h2}")
    w, h = w1, h1

    def on_edge(mask, x, y):
        v = mask[y * w + x]
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                xx, yy = x + dx, y + dy
                if 0 <= xx < w and 0 <= yy < h and mask[yy * w + xx] != v:
                    return True
        return False

    differ = edge = 0
    covered_a = sum(a)
    covered_b = sum(b)
    both = sum(1 for p, q in zip(a, b) if p and q)
    out = bytearray()
    for y in range(h):
        for x in range(w):
            p, q = a[y * w + x], b[y * w + x]
            if p != q:
                differ += 1
                if on_edge(a, x, y) or on_edge(b, x, y):
                    edge += 1
            out += bytes((255 if p and not q else 0, 255 if q and not p else 0, 96 if p and q else 0))
    total = w * h
    union = covered_a + covered_b - both
    print(
        f"{args.name}: {100.0 * (total - differ) / total:.3f}% of {total} pixels agree; "
        f"{differ} differ ({edge} on a silhouette, {differ - edge} inside); "
        f"coverage {covered_a} vs {covered_b} pixels, IoU {both / union if union else 1.0:.4f}"
    )
    if args.diff:
        with open(args.diff, "wb") as f:
            f.write(f"P6\n{w} {h}\n255\n".encode() + bytes(out))


if __name__ == "__main__":
    main()
