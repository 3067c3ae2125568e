#!/usr/bin/env python3
"""rayforge against pbrt-v4 and Blender's Cycles at equal time on Bitterli's pbrt-v4 scenes
(docs/performance.md, "The path tracer against pbrt-v4 and Cycles").

    python3 bench/bitterli/equal_time.py --rayforge target/release/rayforge \\
        [--pbrt /path/to/pbrt-v4/build/pbrt] [--bpy /path/to/venv-with-bpy/bin/python] \\
        [--scenes cornell-box veach-mis] [--divide 4] [--spp 64] [--threads 2] [--rounds 2]

Each scene is the pbrt-v4 file in ../shared/bitterli at the file's depth and a fraction of
its resolution (`--divide`): rayforge reads it with `--width`, pbrt-v4 a copy with the Film's
resolution divided (tools/fidelity/pbrt_bitterli.py writes it), Cycles a rebuild by
cycles_pbrt.py beside this file (which says how the two are matched). Each round renders the
scene with every renderer in turn, two seeds each, at the same samples per pixel on
`--threads` threads, no denoiser.

A renderer's noise is measured from its own two seeds, needing no reference: for independent
renders a and b, E[(a − b)²] ∕ 2 is each one's variance, so one render's relative mean
squared error is the mean over pixels and channels of (a − b)² ∕ 2 ∕ (m² + 0.01), m the
pixel's mean over every render of every renderer. The error at equal time is that error
times the render's time (a Monte Carlo render's squared error falls as 1 ∕ time); each ratio
printed is the peer's over rayforge's, above 1 where rayforge reaches the lower error in the
same time. Times: pbrt-v4's and rayforge's whole processes (reading included: pbrt-v4 has no
render-only figure), Cycles' render alone against rayforge's summary time (Blender's own
start takes seconds). Each figure is the median over the rounds. The ratio of the image means
shows whether the scenes match (a bias does not show in the noise).
"""

import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "fidelity"))
import pbrt_bitterli  # noqa: E402
import pfm  # noqa: E402

import numpy as np  # noqa: E402

RAYFORGE_TIME = re.compile(r"path traced \d+×\d+ at \d+ spp in ([0-9.]+) s")
CYCLES_TIME = re.compile(r"cycles render_s=([0-9.]+)")


def timed(cmd):
    """Runs `cmd`; its output and wall time."""
    start = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True)
    took = time.perf_counter() - start
    if run.returncode != 0:
        raise SystemExit(f"failed: {' '.join(cmd)}\n{run.stdout}{run.stderr}")
    return run.stdout + run.stderr, took


def rayforge(a, scene, seed, out):
    """(render time, process time) of one rayforge render."""
    text, wall = timed([a.rayforge, "render", pbrt_bitterli.original(scene), "-o", out,
                        "--width", str(a.size[0]), "--height", str(a.size[1]), "--spp",
                        str(a.spp), "--threads", str(a.threads), "--seed", str(seed)])
    return float(RAYFORGE_TIME.search(text).group(1)), wall


def pbrt(a, scene, seed, out):
    _, wall = timed([a.pbrt, "--seed", str(seed), "--spp", str(a.spp), "--nthreads",
                     str(a.threads), "--outfile", out, "--quiet", a.copy])
    return wall, wall


def cycles(a, scene, seed, out):
    text, wall = timed([a.bpy, os.path.join(HERE, "cycles_pbrt.py"),
                        pbrt_bitterli.original(scene), "-o", out, "--divide", str(a.divide),
                        "--spp", str(a.spp), "--threads", str(a.threads), "--seed", str(seed)])
    return float(CYCLES_TIME.search(text).group(1)), wall


def rel_mse(pair, mean):
    a, b = pair
    return float(np.mean((a - b) ** 2 / 2 / (mean ** 2 + 0.01)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rayforge", required=True)
    ap.add_argument("--pbrt", help="pbrt-v4's binary (left out when not given)")
    ap.add_argument("--bpy", help="a Python with PyPI's bpy (Cycles left out when not given)")
    ap.add_argument("--scenes", nargs="+", default=["cornell-box", "veach-mis"])
    ap.add_argument("--divide", type=int, default=4)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=2)
    a = ap.parse_args()
    peers = [(n, f) for n, f, given in (("pbrt-v4", pbrt, a.pbrt), ("Cycles", cycles, a.bpy)) if given]
    if not peers:
        raise SystemExit("give --pbrt, --bpy or both")
    print("| scene | size | spp | peer | rayforge s | peer s | rayforge rel. MSE | peer rel. MSE "
          "| peer ÷ rayforge, time per sample | peer ÷ rayforge, error at equal time "
          "| image mean rayforge ÷ peer |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for scene in a.scenes:
            a.copy, a.size = pbrt_bitterli.prepared(scene, tmp, a.divide, False)
            rows = {name: [] for name, _ in peers}
            for r in range(a.rounds):
                images, took = {}, {}
                for seed in (2 * r + 1, 2 * r + 2):
                    for name, render in [("rayforge", rayforge)] + peers:
                        out = os.path.join(tmp, f"{name}-{seed}.pfm")
                        render_s, wall_s = render(a, scene, seed, out)
                        images.setdefault(name, []).append(pfm.read_pfm(out))
                        t = took.setdefault(name, [0.0, 0.0])
                        t[0] += render_s / 2
                        t[1] += wall_s / 2
                mean = np.mean([im for ims in images.values() for im in ims], axis=0)
                err = {name: rel_mse(ims, mean) for name, ims in images.items()}
                for name, _ in peers:
                    # pbrt-v4 against rayforge's whole process, Cycles against its render.
                    ours = took["rayforge"][1 if name == "pbrt-v4" else 0]
                    theirs = took[name][0]
                    rows[name].append((ours, theirs, err["rayforge"], err[name], theirs / ours,
                                       err[name] * theirs / (err["rayforge"] * ours),
                                       float(np.mean(images["rayforge"]) / np.mean(images[name]))))
            h, w, _ = images["rayforge"][0].shape
            for name, _ in peers:
                m = [statistics.median(col) for col in zip(*rows[name])]
                print(f"| {scene} | {w}×{h} | {a.spp} | {name} | {m[0]:.2f} | {m[1]:.2f} "
                      f"| {m[2]:.4g} | {m[3]:.4g} | {m[4]:.2f} | {m[5]:.2f} | {m[6]:.4f} |",
                      flush=True)


if __name__ == "__main__":
    main()
