#!/usr/bin/env python3
"""Render a reference scene in Mitsuba 3 as independent batches of linear float PFMs.

    python3 tools/fidelity/render_mitsuba.py --scene cornell --spp 128 --batches 8 \
        --seed0 0 --threads 2 --variant llvm_ad_rgb --out /work/fidelity-data

writes DIR/NAME.mitsuba.b0.pfm ... DIR/NAME.mitsuba.b{B-1}.pfm (each the plain mean of
its N samples per pixel) and DIR/NAME.mitsuba.mean.pfm (the mean of the batches).

Seeds: pass p of batch k uses seed  seed0 + k * passes + p,  passes = ceil(spp / pass_spp),
so batches never share a seed; use seed0 values further apart than batches * passes for
independent runs.  Timings exclude scene loading; for llvm_* variants a warm-up render
(not written) runs first so that JIT compilation is not counted.
"""

import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", required=True, help="scene name, or 'all'")
    ap.add_argument("--spp", type=int, default=64, help="samples per pixel per batch")
    ap.add_argument("--batches", type=int, default=8)
    ap.add_argument("--seed0", type=int, default=0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variant", default="scalar_rgb")
    ap.add_argument("--out", required=True)
    ap.add_argument("--pass-spp", type=int, default=0,
                    help="split each batch into mi.render calls of at most this many spp "
                         "(default: 64 for llvm/cuda variants, one call for scalar)")
    ap.add_argument("--tag", default="mitsuba", help="file name tag: NAME.TAG.bK.pfm")
    ap.add_argument("--no-warmup", action="store_true", help="llvm: skip the warm-up render")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    mi.set_log_level(mi.LogLevel.Warn)
    dr.set_thread_count(args.threads)

    import mitsuba_scenes as ms
    from pfm import write_pfm

    os.makedirs(args.out, exist_ok=True)
    names = ms.SCENES if args.scene == "all" else [args.scene]
    jit = not args.variant.startswith("scalar")
    pass_spp = args.pass_spp or (64 if jit else args.spp)
    passes = max(1, math.ceil(args.spp / pass_spp))
    # Split spp into `passes` nearly equal parts; each batch is their sample-weighted mean.
    parts = [args.spp // passes + (1 if p < args.spp % passes else 0) for p in range(passes)]

    for name in names:
        t0 = time.perf_counter()
        scene = mi.load_dict(ms.scene_dict(name))
        t_load = time.perf_counter() - t0
        size = ms.image_size(name)
        print(f"{name}: {size}x{size}, {args.batches} batches x {args.spp} spp "
              f"({passes} mi.render call(s) of {max(parts)} spp or fewer), variant {args.variant}, {args.threads} thread(s), "
              f"scene load {t_load:.2f} s", flush=True)

        if jit and not args.no_warmup:
            t0 = time.perf_counter()
            np.array(mi.render(scene, spp=parts[0], seed=2**31 - 1))
            print(f"  warm-up render ({parts[0]} spp, incl. JIT compilation): "
                  f"{time.perf_counter() - t0:.2f} s", flush=True)

        acc = np.zeros((size, size, 3), np.float64)
        total_t = 0.0
        for k in range(args.batches):
            img = np.zeros((size, size, 3), np.float64)
            t0 = time.perf_counter()
            for p, n in enumerate(parts):
                seed = args.seed0 + k * passes + p
                out = np.array(mi.render(scene, spp=n, seed=seed), dtype=np.float64)
                img += out[:, :, :3] * n
            dt = time.perf_counter() - t0
            total_t += dt
            img /= args.spp
            path = os.path.join(args.out, f"{name}.{args.tag}.b{k}.pfm")
            write_pfm(path, img)
            acc += img
            rate = size * size * args.spp / dt
            print(f"  batch {k}: {dt:7.2f} s  {rate / 1e6:7.3f} Msamples/s  "
                  f"mean {img.mean(axis=(0, 1)).round(4)}  -> {path}", flush=True)
        mean = acc / args.batches
        mpath = os.path.join(args.out, f"{name}.{args.tag}.mean.pfm")
        write_pfm(mpath, mean)
        rate = size * size * args.spp * args.batches / total_t
        print(f"  total {total_t:.2f} s, {rate / 1e6:.3f} Msamples/s; "
              f"mean of batches {mean.mean(axis=(0, 1)).round(4)} -> {mpath}", flush=True)


if __name__ == "__main__":
    main()
