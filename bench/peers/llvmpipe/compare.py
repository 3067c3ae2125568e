#!/usr/bin/env python3
"""Agreement of two PPM images (P3 or P6, 8-bit): the share of pixels whose three channels
all differ by at most TOL/255 (default 2), plus a few summary numbers.

Usage: python3 compare.py raster_million.ppm llvmpipe_frame.ppm [TOL]
"""
import sys
import numpy as np


def read_ppm(path):
    data = open(path, "rb").read()
    tokens, pos = [], 0
    # Header: magic, width, height, maxval (comments allowed).
    while len(tokens) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        tokens.append(data[pos:end])
        pos = end
    magic, w, h = tokens[0], int(tokens[1]), int(tokens[2])
    if magic == b"P6":
        pixels = np.frombuffer(data[pos + 1:pos + 1 + w * h * 3], dtype=np.uint8)
    else:
        pixels = np.array(data[pos:].split(), dtype=np.uint8)
    return pixels.reshape(h, w, 3).astype(np.int16)


a, b = read_ppm(sys.argv[1]), read_ppm(sys.argv[2])
tol = int(sys.argv[3]) if len(sys.argv) > 3 else 2
diff = np.abs(a - b).max(axis=2)
print(f"size {a.shape[1]}x{a.shape[0]}")
print(f"pixels within {tol}/255: {100.0 * (diff <= tol).mean():.5f}% ({(diff > tol).sum()} of {diff.size} outside)")
print(f"identical: {100.0 * (diff == 0).mean():.3f}%  over 10/255: {100.0 * (diff > 10).mean():.3f}%")
print(f"max channel difference: {diff.max()}  mean: {np.abs(a - b).mean():.4f}")
# Orientation check: the same comparison with one image mirrored left-right.
mirrored = np.abs(a - b[:, ::-1]).max(axis=2)
print(f"(with the second mirrored in x: {100.0 * (mirrored <= tol).mean():.3f}% within {tol}/255)")
