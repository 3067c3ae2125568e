#!/usr/bin/env python3
"""Convergence of rayforge's path tracer: error against a high-sample reference vs spp.

    python3 tools/fidelity/convergence.py --scene cornell --out /work/fidelity-data/convergence \
        [--ref-spp 512 --ref-batches 8 --ref-seed0 1000] \
        [--spps 16:4,32:4,64:2,128:2,256:1,512:1,1024:1] [--samplers sobol,independent] \
        [--threads 2] [--width W] [--bin PATH] [--reuse]

1. The reference: --ref-batches independent renders of --ref-spp spp each (Sobol, seeds
   ref-seed0 ..), NAME.ref.bK.pfm; their mean is the reference image R (ref-spp x
   ref-batches samples per pixel, 4096 by default).
2. For each sampler and each entry SPP:K of --spps, K renders at SPP spp with seeds
   2000 + 10 * (index of the entry) + i (never a reference seed), NAME.SAMPLER.sSPP.kI.pfm.
3. For each render I: MSE = mean over pixels and channels of (I - R)^2 and the mean
   relative error MRE = mean |I - R| / max(R, 1e-2) (as compare.py).  MSE and MRE are
   averaged over the K renders of an entry.

The reference's own noise: I and R are independent, so E[MSE] = MSE_true + mean Var(R),
and Var(R) per pixel and channel is estimated from the spread of the reference batches
(sample variance / number of batches).  The table gives the raw RMSE, the reference's noise
floor sqrt(mean Var(R)) and the corrected RMSE sqrt(MSE - mean Var(R)); the fitted slopes
(least squares of log RMSE against log spp) use the corrected RMSE.  MRE is not corrected.

Writes DIR/NAME.convergence.csv and prints a markdown table and the slopes.  Without
matplotlib no plot is drawn.
"""

import argparse
import csv
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from pfm import read_pfm, write_pfm  # noqa: E402
from render_rayforge import ROOT, default_bin, render_one  # noqa: E402


def parse_spps(text):
    out = []
    for part in text.split(","):
        spp, _, k = part.partition(":")
        out.append((int(spp), int(k or 1)))
    return out


def render(args, scene_path, path, spp, seed, sampler):
    if args.reuse and os.path.exists(path):
        return float("nan")
    extra = ["--width", str(args.width)] if args.width else []
    wall, rt, _ = render_one(args.bin, scene_path, path, spp, seed, sampler, args.threads, extra)
    return rt if rt is not None else wall


def fit_slope(spps, rmses):
    x = np.log(np.asarray(spps, float))
    y = np.log(np.asarray(rmses, float))
    ok = np.isfinite(y)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(x[ok], y[ok], 1)[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="cornell")
    ap.add_argument("--out", required=True)
    ap.add_argument("--ref-spp", type=int, default=512)
    ap.add_argument("--ref-batches", type=int, default=8)
    ap.add_argument("--ref-seed0", type=int, default=1000)
    ap.add_argument("--ref-sampler", default="sobol", choices=["sobol", "independent"])
    ap.add_argument("--spps", default="16:4,32:4,64:2,128:2,256:1,512:1,1024:1",
                    help="SPP:RENDERS,... (renders with different seeds per sample count)")
    ap.add_argument("--samplers", default="sobol,independent")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--width", type=int, default=0, help="render at this width (the scene's camera "
                    "otherwise); a smaller image makes the study cheaper")
    ap.add_argument("--bin", default=None)
    ap.add_argument("--split", type=int, default=128, help="also fit slopes below and above this spp")
    ap.add_argument("--reuse", action="store_true", help="keep renders whose files exist")
    args = ap.parse_args()
    args.bin = args.bin or default_bin()
    os.makedirs(args.out, exist_ok=True)
    scene_path = os.path.join(ROOT, "scenes", "pbr", f"{args.scene}.yml")
    name = args.scene

    # 1. the reference
    batches = []
    for k in range(args.ref_batches):
        path = os.path.join(args.out, f"{name}.ref.b{k}.pfm")
        t = render(args, scene_path, path, args.ref_spp, args.ref_seed0 + k, args.ref_sampler)
        batches.append(read_pfm(path).astype(np.float64))
        print(f"reference batch {k}: {args.ref_spp} spp, seed {args.ref_seed0 + k}, {t:.1f} s", flush=True)
    batches = np.stack(batches)
    ref = batches.mean(axis=0)
    write_pfm(os.path.join(args.out, f"{name}.ref.mean.pfm"), ref)
    ref_var = float((batches.var(axis=0, ddof=1) / args.ref_batches).mean())
    ref_total = args.ref_spp * args.ref_batches
    print(f"reference: {ref_total} spp ({args.ref_batches} x {args.ref_spp}, {args.ref_sampler}), "
          f"image mean {ref.mean(axis=(0, 1)).round(4)}, noise floor RMSE {math.sqrt(ref_var):.5f}", flush=True)
    denom = np.maximum(ref, 1e-2)

    # 2. and 3. the renders and their errors
    rows = []
    for sampler in args.samplers.split(","):
        for idx, (spp, count) in enumerate(parse_spps(args.spps)):
            mses, mres, times = [], [], []
            for i in range(count):
                seed = 2000 + 10 * idx + i
                path = os.path.join(args.out, f"{name}.{sampler}.s{spp}.k{i}.pfm")
                t = render(args, scene_path, path, spp, seed, sampler)
                img = read_pfm(path).astype(np.float64)
                d = img - ref
                mses.append(float((d * d).mean()))
                mres.append(float((np.abs(d) / denom).mean()))
                times.append(t)
            mse = float(np.mean(mses))
            row = {
                "sampler": sampler, "spp": spp, "renders": count,
                "rmse_raw": math.sqrt(mse),
                "rmse": math.sqrt(max(mse - ref_var, 0.0)),
                "ref_noise_rmse": math.sqrt(ref_var),
                "mre": float(np.mean(mres)),
                "seconds_per_render": float(np.nanmean(times)) if not all(map(math.isnan, times)) else float("nan"),
            }
            rows.append(row)
            print(f"  {sampler:11s} {spp:5d} spp x {count}: RMSE {row['rmse']:.5f} "
                  f"(raw {row['rmse_raw']:.5f}), MRE {row['mre']:.4%}, {row['seconds_per_render']:.1f} s/render",
                  flush=True)

    csv_path = os.path.join(args.out, f"{name}.convergence.csv")
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"-> {csv_path}\n")

    samplers = args.samplers.split(",")
    spps = sorted({r["spp"] for r in rows})
    by = {(r["sampler"], r["spp"]): r for r in rows}
    print(f"Reference: {ref_total} spp; its noise floor (RMSE of the reference itself) "
          f"{math.sqrt(ref_var):.5f}, subtracted in quadrature.\n")
    head = "| spp | renders |"
    for s in samplers:
        head += f" {s} RMSE | {s} RMSE raw | {s} mean rel. err. |"
    print(head)
    print("|---|---|" + "---|---|---|" * len(samplers))
    for spp in spps:
        line = f"| {spp} | {by[(samplers[0], spp)]['renders']} |"
        for s in samplers:
            r = by[(s, spp)]
            line += f" {r['rmse']:.5f} | {r['rmse_raw']:.5f} | {r['mre']:.3%} |"
        print(line)
    print()
    lo = [p for p in spps if p <= args.split]
    hi = [p for p in spps if p >= args.split]
    for s in samplers:
        full = fit_slope(spps, [by[(s, p)]["rmse"] for p in spps])
        text = f"log-log slope of RMSE, {s}: {full:.3f} over {spps[0]}-{spps[-1]} spp"
        parts = []
        for sub in (lo, hi):
            if 2 <= len(sub) < len(spps):
                parts.append(f"{fit_slope(sub, [by[(s, p)]['rmse'] for p in sub]):.3f} over {sub[0]}-{sub[-1]}")
        print(text + (f" ({', '.join(parts)})" if parts else ""))

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not installed: no plot)")
        return
    fig, ax = plt.subplots(figsize=(5, 4))
    for s in samplers:
        ax.loglog(spps, [by[(s, p)]["rmse"] for p in spps], "o-", label=s)
    ax.loglog(spps, [by[(samplers[0], spps[0])]["rmse"] * math.sqrt(spps[0] / p) for p in spps],
              "k:", label="spp^-1/2")
    ax.set_xlabel("samples per pixel")
    ax.set_ylabel("RMSE vs reference")
    ax.set_title(name)
    ax.legend()
    fig.tight_layout()
    png = os.path.join(args.out, f"{name}.convergence.png")
    fig.savefig(png, dpi=100)
    print(f"plot -> {png}")


if __name__ == "__main__":
    main()
