#!/usr/bin/env python3
"""Render a reference scene with rayforge's path tracer as independent batches of PFMs.

    python3 tools/fidelity/render_rayforge.py --scene cornell --spp 256 --batches 8 \
        --seed0 0 --threads 2 --sampler sobol --out /work/fidelity-data [--bin PATH]

runs `rayforge render scenes/pbr/NAME.yml --renderer path --spp N --seed S --sampler X
--threads T -o DIR/NAME.TAG.bK.pfm` for batch K = 0..B-1 with seed S + K, then writes
DIR/NAME.TAG.mean.pfm, the mean of the batches (TAG defaults to "rayforge"; the naming
matches render_mitsuba.py, so compare.py takes both sets by glob).

Batches with different seeds are independent estimates of the image, with either sampler
(the Sobol points are Owen-scrambled per seed).  For each batch it prints the wall time
(measured here, process start to exit, scene loading included), the samples/s that
rayforge's own summary line reports (render only) and the image mean.
"""

import argparse
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
from pfm import read_pfm, write_pfm  # noqa: E402

SCENES = ["furnace", "furnace-closed", "cornell", "spheres-materials", "envmap"]
# "path traced 256×256 at 16 spp in 1.94 s, 541.5 k samples/s (6.4 M rays) → out.pfm"
SUMMARY = re.compile(r"path traced (\d+)\D(\d+) at (\d+) spp in ([\d.]+) s, ([\d.]+) ([kMG]?) ?samples/s")
UNIT = {"": 1.0, "k": 1e3, "M": 1e6, "G": 1e9}


def default_bin():
    for p in (os.environ.get("RAYFORGE_BIN"), "/work/bin/rayforge",
              os.path.join(ROOT, "target", "release", "rayforge")):
        if p and os.path.exists(p):
            return p
    return "rayforge"


def render_one(binary, scene_path, out, spp, seed, sampler, threads, extra=()):
    """Render one image; returns (wall seconds, rayforge's render seconds or None,
    rayforge's samples/s or None)."""
    cmd = [binary, "render", scene_path, "--renderer", "path", "--spp", str(spp),
           "--seed", str(seed), "--sampler", sampler, "--threads", str(threads), "-o", out, *extra]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        sys.stderr.write(proc.stdout + proc.stderr)
        raise SystemExit(f"rayforge failed (exit {proc.returncode}): {' '.join(cmd)}")
    m = SUMMARY.search(proc.stdout + proc.stderr)
    if m:
        return wall, float(m.group(4)), float(m.group(5)) * UNIT[m.group(6)]
    return wall, None, None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", required=True, help="scene name (scenes/pbr/NAME.yml), or 'all'")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel per batch")
    ap.add_argument("--batches", type=int, default=8)
    ap.add_argument("--seed0", type=int, default=0, help="batch K uses seed seed0 + K")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sampler", choices=["sobol", "independent"], default="sobol")
    ap.add_argument("--out", required=True)
    ap.add_argument("--bin", default=None, help="the rayforge binary (default: $RAYFORGE_BIN, "
                    "/work/bin/rayforge, target/release/rayforge, then rayforge on PATH)")
    ap.add_argument("--scenes-dir", default=os.path.join(ROOT, "scenes", "pbr"))
    ap.add_argument("--tag", default="rayforge", help="file name tag: NAME.TAG.bK.pfm")
    args = ap.parse_args()

    binary = args.bin or default_bin()
    os.makedirs(args.out, exist_ok=True)
    names = SCENES if args.scene == "all" else [args.scene]
    for name in names:
        scene_path = os.path.join(args.scenes_dir, f"{name}.yml")
        print(f"{name}: {args.batches} batches x {args.spp} spp, sampler {args.sampler}, "
              f"seeds {args.seed0}..{args.seed0 + args.batches - 1}, {args.threads} thread(s), {binary}",
              flush=True)
        acc = None
        tot_wall = tot_render = 0.0
        npix = 0
        for k in range(args.batches):
            path = os.path.join(args.out, f"{name}.{args.tag}.b{k}.pfm")
            wall, rt, rate = render_one(binary, scene_path, path, args.spp, args.seed0 + k,
                                        args.sampler, args.threads)
            img = read_pfm(path).astype(np.float64)
            npix = img.shape[0] * img.shape[1]
            acc = img if acc is None else acc + img
            tot_wall += wall
            tot_render += rt if rt is not None else wall
            own = npix * args.spp / wall
            rf = f"{rate / 1e6:7.3f} Msamples/s (rayforge, {rt:.2f} s render)" if rate else "(no summary line)"
            print(f"  batch {k}: {wall:7.2f} s wall  {own / 1e6:7.3f} Msamples/s (wall)  {rf}  "
                  f"mean {img.mean(axis=(0, 1)).round(4)}  -> {path}", flush=True)
        mean = acc / args.batches
        mpath = os.path.join(args.out, f"{name}.{args.tag}.mean.pfm")
        write_pfm(mpath, mean)
        total = npix * args.spp * args.batches
        print(f"  total {tot_wall:.2f} s wall ({total / tot_wall / 1e6:.3f} Msamples/s), "
              f"{tot_render:.2f} s render ({total / tot_render / 1e6:.3f} Msamples/s); "
              f"mean of batches {mean.mean(axis=(0, 1)).round(4)} -> {mpath}", flush=True)


if __name__ == "__main__":
    main()
