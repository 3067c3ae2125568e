#!/usr/bin/env python3
"""Mitsuba 3 throughput on the five reference scenes: samples per second for each scene,
variant and thread count, as a markdown table.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
    python3 tools/fidelity/bench_mitsuba.py --spp 64 [--variants scalar_rgb llvm_ad_rgb] \
        [--threads 1 2] [--scenes ...] [--repeats 1]

Every (variant, thread count) pair runs in its own Python process (so thread pools and
JIT state never carry over).  The thread count is set with drjit.set_thread_count(T):
Mitsuba 3 renders on Dr.Jit's nanothread pool in every variant, scalar included, and
the Python thread counts as one of the T.  Timings exclude scene loading.  For llvm_*
variants the first render (JIT tracing + compilation, or a load from Dr.Jit's on-disk
kernel cache) is reported separately; "samples/s" is the best of --repeats later renders
with other seeds.  cpu/wall is the process CPU time over the wall time of those renders.

Single-configuration mode (what `rayforge-bench pbr` runs, one process per measurement):

    python3 tools/fidelity/bench_mitsuba.py --one SCENE VARIANT THREADS --spp N \
        [--seed S] [--sampler independent|multijitter|ldsampler] [--pfm OUT.pfm]

loads the scene, renders it once untimed first for llvm_* variants (the same spp with seed
S + 1, so the timed render finds its kernels compiled), then times one `mi.render` call
(seed S) and prints one JSON line on stdout: scene, variant, threads, sampler, spp (the
sampler's sample count after the render: ldsampler rounds up to a power of 4), width,
height, seconds (the timed render), warmup_seconds (null for scalar), load_seconds,
cpu_ratio.  Python start-up, scene loading and the warm-up are not in `seconds`.
"""

import argparse
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

# Debian's libLLVM 19, which the llvm_* variants need (see README.md).
LIBLLVM = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def worker(variant, threads, scenes, spp, repeats):
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(variant)
    mi.set_log_level(mi.LogLevel.Warn)
    dr.set_thread_count(threads)
    import mitsuba_scenes as ms

    jit = not variant.startswith("scalar")
    rows = []
    for name in scenes:
        scene = mi.load_dict(ms.scene_dict(name))
        size = ms.image_size(name)
        first = None
        if jit:
            t0 = time.perf_counter()
            np.array(mi.render(scene, spp=spp, seed=1000))
            first = time.perf_counter() - t0
        best, cpu_ratio = None, None
        for r in range(repeats):
            c0, t0 = time.process_time(), time.perf_counter()
            np.array(mi.render(scene, spp=spp, seed=r))
            dt, dc = time.perf_counter() - t0, time.process_time() - c0
            if best is None or dt < best:
                best, cpu_ratio = dt, dc / dt
        rows.append({
            "scene": name, "variant": variant, "threads": threads, "size": size, "spp": spp,
            "time": best, "rate": size * size * spp / best, "first": first, "cpu_ratio": cpu_ratio,
        })
        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    print(json.dumps(rows))


def one(scene_name, variant, threads, spp, seed, sampler, pfm_path):
    """One configuration, one timed render; a JSON line on stdout (see the module doc)."""
    if variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ \
            and os.path.exists(LIBLLVM):
        os.environ["DRJIT_LIBLLVM_PATH"] = LIBLLVM
    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(variant)
    mi.set_log_level(mi.LogLevel.Error)  # ldsampler warns when it rounds its count
    dr.set_thread_count(threads)
    import mitsuba_scenes as ms

    d = ms.scene_dict(scene_name)
    d["sensor"]["sampler"] = {"type": sampler, "sample_count": spp}
    t0 = time.perf_counter()
    scene = mi.load_dict(d)
    load = time.perf_counter() - t0
    warmup = None
    if not variant.startswith("scalar"):
        t0 = time.perf_counter()
        np.array(mi.render(scene, spp=spp, seed=seed + 1))
        warmup = time.perf_counter() - t0
    c0, t0 = time.process_time(), time.perf_counter()
    img = np.array(mi.render(scene, spp=spp, seed=seed))
    dt, dc = time.perf_counter() - t0, time.process_time() - c0
    h, w = img.shape[0], img.shape[1]
    if pfm_path:
        from pfm import write_pfm
        write_pfm(pfm_path, img[:, :, :3])
    print(json.dumps({
        "scene": scene_name, "variant": variant, "threads": threads, "sampler": sampler,
        "spp": int(scene.sensors()[0].sampler().sample_count()), "seed": seed,
        "width": w, "height": h, "seconds": dt, "warmup_seconds": warmup,
        "load_seconds": load, "cpu_ratio": dc / dt if dt > 0 else None,
        "mitsuba": mi.__version__,
    }), flush=True)


def print_table(rows, scenes, spp):
    import mitsuba

    print(f"\nMitsuba {mitsuba.__version__}, {spp} spp per render, {os.cpu_count()} CPU(s) visible; "
          "Msamples/s = pixels x spp / wall time; per CPU-s = divided by the process CPU time "
          "(less sensitive to other load on the machine)\n")
    print("| scene | size | variant | threads | Msamples/s | Msamples per CPU-s | render s | cpu/wall "
          "| first render s (JIT) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: (scenes.index(r["scene"]), r["variant"], r["threads"])):
        first = f"{r['first']:.2f}" if r["first"] is not None else "-"
        print(f"| {r['scene']} | {r['size']}x{r['size']} | {r['variant']} | {r['threads']} | "
              f"{r['rate'] / 1e6:.3f} | {r['rate'] / r['cpu_ratio'] / 1e6:.3f} | {r['time']:.2f} | "
              f"{r['cpu_ratio']:.2f} | {first} |")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--variants", nargs="+", default=["scalar_rgb", "llvm_ad_rgb"])
    ap.add_argument("--threads", nargs="+", type=int, default=[1, 2])
    ap.add_argument("--scenes", nargs="+",
                    default=["furnace", "furnace-closed", "cornell", "spheres-materials", "envmap"])
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--json", help="also write all rows to this JSON file")
    ap.add_argument("--from-json", help="only print the table of an earlier --json file")
    ap.add_argument("--one", nargs=3, metavar=("SCENE", "VARIANT", "THREADS"),
                    help="time one render of one configuration; print a JSON line")
    ap.add_argument("--seed", type=int, default=0, help="--one: the timed render's seed")
    ap.add_argument("--sampler", default="independent", help="--one: Mitsuba's sampler")
    ap.add_argument("--pfm", help="--one: write the timed render here")
    ap.add_argument("--worker", nargs=2, metavar=("VARIANT", "THREADS"), help=argparse.SUPPRESS)
    args = ap.parse_args()

    if args.one:
        one(args.one[0], args.one[1], int(args.one[2]), args.spp, args.seed, args.sampler,
            args.pfm)
        sys.exit(0)

    if args.worker:
        worker(args.worker[0], int(args.worker[1]), args.scenes, args.spp, args.repeats)
        sys.exit(0)

    if args.from_json:
        with open(args.from_json) as f:
            rows = json.load(f)
        print_table(rows, args.scenes, rows[0]["spp"] if rows else args.spp)
        sys.exit(0)

    env = dict(os.environ)
    if "DRJIT_LIBLLVM_PATH" not in env and os.path.exists(LIBLLVM):
        env["DRJIT_LIBLLVM_PATH"] = LIBLLVM
    rows = []
    for variant in args.variants:
        for t in args.threads:
            cmd = [sys.executable, os.path.abspath(__file__), "--worker", variant, str(t),
                   "--spp", str(args.spp), "--repeats", str(args.repeats), "--scenes", *args.scenes]
            out = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, text=True)
            if out.returncode != 0:
                print(f"{variant} x{t}: worker failed (exit {out.returncode})", file=sys.stderr)
                continue
            rows += json.loads(out.stdout.strip().splitlines()[-1])
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)

    print_table(rows, args.scenes, args.spp)
