"""Reads binary PPM (P6) images, 8 or 16 bits per channel, as floats in [0, 1].

Shared by the POV-Ray comparisons; pure Python, no dependencies.
"""

import sys


def read(path):
    """Returns (width, height, values): values row by row, r g b per pixel."""
    with open(path, "rb") as f:
        data = f.read()
    fields = []
    i = 0
    while len(fields) < 4:
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            while data[i:i + 1] not in (b"\n", b""):
                i += 1
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    if fields[0] != b"P6":
        sys.exit(f"{path}: not a binary PPM (P6)")
    width, height, maxval = int(fields[1]), int(fields[2]), int(fields[3])
    i += 1  # the single whitespace after maxval
    raw = data[i:]
    if maxval > 255:
        values = [int.from_bytes(raw[k:k + 2], "big") / maxval for k in range(0, 6 * width * height, 2)]
    else:
        values = [b / maxval for b in raw[:3 * width * height]]
    return width, height, values
