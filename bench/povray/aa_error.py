#!/usr/bin/env python3
"""Anti-aliasing error of an image against a converged one of the same renderer: the
root-mean-square difference of the displayed (sRGB-encoded) values, in 8-bit steps.

Usage: aa_error.py IMAGE.ppm REFERENCE.ppm
"""

import math
import sys

import ppm


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    w1, h1, a = ppm.read(sys.argv[1])
    w2, h2, b = ppm.read(sys.argv[2])
    if (w1, h1) != (w2, h2):
        sys.exit(f"sizes differ: {w1}x{h1} vs {w2}x{h2}")
    squared = sum((x - y) ** 2 for x, y in zip(a, b))
    print(f"{255 * math.sqrt(squared / len(a)):.3f}")


if __name__ == "__main__":
    main()
