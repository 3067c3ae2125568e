#!/usr/bin/env python3
"""rayforge against Blender's Cycles at equal time on pbrt-v4 scenes (docs/performance.md,
"The path tracer against Blender's Cycles").

    python3 bench/cycles/equal_time.py --rayforge target/release/rayforge \\
        --bpy /path/to/venv-with-bpy/bin/python [--scenes cornell-box veach-mis] \\
        [--divide 4] [--spp 64] [--threads 2] [--rounds 2]

Each scene is Bitterli's pbrt-v4 file in ../shared/bitterli (rebuilt for Cycles by
cycles_pbrt.py beside this file, which says how the two are matched), at the file's depth, a
fraction of its resolution. Each round renders it with rayforge and with Cycles in turn, two
seeds each, the same samples per pixel, both denoiser-free on `--threads` threads. A
renderer's noise is measured from its own two seeds, needing no reference: for independent
renders a and b of one scene, E[(a − b)²] ∕ 2 is each one's variance, so the relative mean
squared error of one render is the mean over pixels and channels of (a − b)² ∕ 2 ∕ (m² +
0.01), m being the pixel's mean over every render of both. Error at equal time is that error
times the render time (the error of a Monte Carlo render falls as 1 ∕ time); the ratio
printed is Cycles' over rayforge's, above 1 where rayforge has the lower error at equal time.
Each ratio is the median over the rounds. The means of the two renderers' images are printed
beside it, to show the scenes match (a bias would not show in the noise).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "fidelity"))
import pfm  # noqa: E402

import numpy as np  # noqa: E402

SHARED = os.path.join(HERE, "..", "..", "..", "shared", "bitterli")
RAYFORGE_TIME = re.compile(r"path traced (\d+)×(\d+) at (\d+) spp in ([0-9.]+) s")
CYCLES_TIME = re.compile(r"cycles render_s=([0-9.]+)")


def scene_file(name):
    path = os.path.join(SHARED, name, "pbrt", "scene-v4.pbrt")
    if not os.path.isfile(path):
        raise SystemExit(f"{path}: not found (Bitterli's scenes are in ../shared/bitterli)")
    return path


def film_width(path):
    m = re.search(r'"integer xresolution"\s*\[?\s*(\d+)', open(path).read())
    return int(m.group(1))


def rayforge(a, scene, seed, out):
    width = film_width(scene) // a.divide
    run = subprocess.run(
        [a.rayforge, "render", scene, "-o", out, "--spp", str(a.spp), "--threads",
         str(a.threads), "--seed", str(seed), "--width", str(width)],
        capture_output=True, text=True, check=True)
    return float(RAYFORGE_TIME.search(run.stdout + run.stderr).group(4))


def cycles(a, scene, seed, out):
    run = subprocess.run(
        [a.bpy, os.path.join(HERE, "cycles_pbrt.py"), scene, "-o", out, "--divide",
         str(a.divide), "--spp", str(a.spp), "--threads", str(a.threads), "--seed", str(seed)],
        capture_output=True, text=True, check=True)
    return float(CYCLES_TIME.search(run.stdout).group(1))


def rel_mse(pair, mean):
    a, b = pair
    return float(np.mean((a - b) ** 2 / 2 / (mean ** 2 + 0.01)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rayforge", required=True)
    ap.add_argument("--bpy", required=True, help="a Python with PyPI's bpy")
    ap.add_argument("--scenes", nargs="+", default=["cornell-box", "veach-mis"])
    ap.add_argument("--divide", type=int, default=4)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=2)
    a = ap.parse_args()
    print("| scene | size | spp | rayforge s | Cycles s | rayforge samples/s ÷ Cycles' "
          "| rayforge rel. MSE | Cycles rel. MSE | Cycles ÷ rayforge at equal time "
          "| image mean rayforge ÷ Cycles |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.scenes:
            scene = scene_file(name)
            ratios, speed, times = [], [], {"rayforge": [], "cycles": []}
            errors = {"rayforge": [], "cycles": []}
            means = []
            for r in range(a.rounds):
                images = {"rayforge": [], "cycles": []}
                took = {"rayforge": 0.0, "cycles": 0.0}
                for seed in (2 * r + 1, 2 * r + 2):
                    for who, render in (("rayforge", rayforge), ("cycles", cycles)):
                        out = os.path.join(tmp, f"{who}-{seed}.pfm")
                        took[who] += render(a, scene, seed, out) / 2
                        images[who].append(pfm.read_pfm(out))
                mean = np.mean(images["rayforge"] + images["cycles"], axis=0)
                err = {who: rel_mse(images[who], mean) for who in images}
                for who in images:
                    errors[who].append(err[who])
                    times[who].append(took[who])
                ratios.append(err["cycles"] * took["cycles"] / (err["rayforge"] * took["rayforge"]))
                speed.append(took["cycles"] / took["rayforge"])
                means.append(float(np.mean(images["rayforge"]) / np.mean(images["cycles"])))
            h, w, _ = images["rayforge"][0].shape
            med = statistics.median
            print(f"| {name} | {w}×{h} | {a.spp} | {med(times['rayforge']):.2f} "
                  f"| {med(times['cycles']):.2f} | {med(speed):.2f} "
                  f"| {med(errors['rayforge']):.4g} | {med(errors['cycles']):.4g} "
                  f"| {med(ratios):.2f} | {med(means):.4f} |", flush=True)


if __name__ == "__main__":
    main()
