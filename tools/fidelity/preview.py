#!/usr/bin/env python3
"""Linear PFM -> 8-bit sRGB PNG for a quick look (exposure scale, clamp, sRGB curve).

    python3 tools/fidelity/preview.py IN.pfm [IN2.pfm ...] [--exposure 1.0] [--out-dir DIR]

Writes IN.png next to each input (or into --out-dir).  Only numpy and zlib.
"""

import argparse
import os
import struct
import sys
import zlib

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfm import read_pfm  # noqa: E402


def write_png(path, rgb8):
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].tobytes() for y in range(h))

    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def to_srgb8(img, exposure=1.0):
    x = np.nan_to_num(img * exposure, nan=0.0, posinf=1.0, neginf=0.0).clip(0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return (s * 255.0 + 0.5).astype(np.uint8)


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("inputs", nargs="+")
    ap.add_argument("--exposure", type=float, default=1.0)
    ap.add_argument("--out-dir")
    a = ap.parse_args()
    for p in a.inputs:
        out = os.path.splitext(p)[0] + ".png"
        if a.out_dir:
            out = os.path.join(a.out_dir, os.path.basename(out))
        write_png(out, to_srgb8(read_pfm(p), a.exposure))
        print(out)
