#!/usr/bin/env python3
"""Compare rayforge's batches of a pbrt-v4 scene with pbrt-v4's own (pbrt_bitterli.py).

    python3 tools/fidelity/compare_pbrt.py SCENE [--data DIR] [--a TAG] [--b TAG] [--header]

Reads DATA/SCENE/SCENE.A.b*.pfm (default A = rayforge) and SCENE.B.b*.pfm (B = pbrt), each
set n >= 2 independent batches, and prints one markdown row:

* image mean per channel of each side and their ratio (the issue asks within 3 %), with the
  z of the difference from the batches' spread of image means;
* 16 x 16 blocks: each block's mean (luminance), its standard error from the batch spread on
  each side, and the Welch z of the two sides' difference; the share of blocks with |z| < 3
  (a block is also a pass when the two differ by under 1 % of the image mean: noise-free
  blocks, such as a black background, have no spread to divide by); and pbrt's own
  seed-to-seed spread, the same statistic between its first and second half of batches,
  for scale;
* the per-pixel Welch z of compare.py (pass fraction at family level 1 %).
"""

import argparse
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare import LUM, compare, load_set  # noqa: E402


def blocks(stack, size=16):
    """Per batch, the luminance mean of each size x size block (partial edge blocks dropped)."""
    n, h, w, _ = stack.shape
    lum = stack @ LUM
    h2, w2 = h // size * size, w // size * size
    lum = lum[:, :h2, :w2].reshape(n, h2 // size, size, w2 // size, size)
    return lum.mean(axis=(2, 4))


def block_z(a, b, image_mean):
    """Welch z per block between batch sets a and b (arrays n x by x bx); the pass share."""
    ma, mb = a.mean(0), b.mean(0)
    va, vb = a.var(0, ddof=1) / len(a), b.var(0, ddof=1) / len(b)
    diff = ma - mb
    se = np.sqrt(va + vb)
    with np.errstate(divide="ignore", invalid="ignore"):
        z = np.where(se > 0, diff / se, 0.0)
    tiny = np.abs(diff) < 0.01 * image_mean
    passed = (np.abs(z) < 3) | tiny
    return z, passed.mean()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("--data", default="/work/fidelity-data/bitterli")
    ap.add_argument("--a", default="rayforge")
    ap.add_argument("--b", default="pbrt")
    ap.add_argument("--header", action="store_true")
    a = ap.parse_args()
    folder = os.path.join(a.data, a.scene)
    _, A = load_set(os.path.join(folder, f"{a.scene}.{a.a}.b*.pfm"))
    _, B = load_set(os.path.join(folder, f"{a.scene}.{a.b}.b*.pfm"))
    if A.shape[1:] != B.shape[1:]:
        raise SystemExit(f"sizes differ: {A.shape[1:]} and {B.shape[1:]}")
    finite = np.isfinite(A).all() and np.isfinite(B).all()
    mean_a, mean_b = A.mean(axis=(0, 1, 2)), B.mean(axis=(0, 1, 2))
    se = np.sqrt(A.mean(axis=(1, 2)).var(0, ddof=1) / len(A) + B.mean(axis=(1, 2)).var(0, ddof=1) / len(B))
    mean_z = (mean_a - mean_b) / np.where(se > 0, se, np.inf)
    image_mean = float(B.mean(axis=(0, 1, 2)) @ LUM)
    ba, bb = blocks(A), blocks(B)
    z, share = block_z(ba, bb, image_mean)
    half = len(bb) // 2
    if half >= 2:
        _, own = block_z(bb[:half], bb[half:], image_mean)
        own = f"{100 * own:.1f} %"
    else:
        own = "n/a"
    pixel = compare(A, B)
    if a.header:
        print("| scene | size | batches × spp | image mean rayforge (R, G, B) | pbrt-v4 | ratio | image-mean z | 16×16 blocks |z| < 3 | pbrt vs itself | largest block |z| | pixels passing (Welch z) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|")
    ratio = mean_a / mean_b
    fmt = lambda v, d=4: "(" + ", ".join(f"{x:.{d}f}" for x in v) + ")"
    print(f"| {a.scene} | {A.shape[2]}×{A.shape[1]} | {len(A)} / {len(B)} | {fmt(mean_a)} | {fmt(mean_b)} | "
          f"{fmt(ratio, 3)} | {fmt(mean_z, 1)} | {100 * share:.1f} % | {own} | {np.abs(z).max():.1f} | "
          f"{100 * pixel['pass']:.2f} % (expected {100 * pixel['expected_pass'][0]:.1f}–{100 * pixel['expected_pass'][1]:.1f} %){'' if finite else ' (non-finite pixels!)'} |")


if __name__ == "__main__":
    main()
