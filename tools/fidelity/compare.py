#!/usr/bin/env python3
"""Compare two sets of independent batch renders (linear float PFMs) of one scene.

    python3 tools/fidelity/compare.py \
        --a '/work/fidelity-data/cornell.rayforge.b*.pfm' \
        --b '/work/fidelity-data/cornell.mitsuba.b*.pfm' [--header] [--test z|t]

Each set holds n >= 2 images of the same size, each the mean of its own independent
samples.  Per pixel and channel: the mean m over the batches and its standard error
se = s / sqrt(n), s the sample standard deviation across batches (ddof 1).

Printed:
* mean relative error of the means: |m_a - m_b| / max(m_b, 1e-2), averaged over all
  finite pixels and the three channels;
* per-pixel test: two-sided Welch test of m_a = m_b per channel at level alpha/3 each
  (Bonferroni over the 3 channels, so a pixel fails at family level alpha = 1 % by
  default); statistic (m_a - m_b) / sqrt(se_a^2 + se_b^2), compared with the normal
  distribution (--test z, the default) or with Student's t with the Welch-Satterthwaite
  degrees of freedom (--test t; with few batches the z-test rejects more often than
  alpha even when both renderers agree -- the "expected" figure printed for z shows
  how much).  Pixels where both sides have zero spread in a channel pass when the
  means are equal (to 1e-6 relative) and fail otherwise.  Pixels with a NaN/Inf in
  any batch of either set are counted, reported and counted as failing;
* the whole-image mean per channel of both sets, with a z-score from the batch spread
  of the image means (a sensitive test for an overall bias);
* a markdown table row (--header also prints the header).
"""

import argparse
import glob
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfm import read_pfm  # noqa: E402

LUM = np.array([0.2126, 0.7152, 0.0722])


def load_set(pattern):
    paths = sorted(glob.glob(pattern))
    paths = [p for p in paths if not p.endswith(".mean.pfm")]
    if len(paths) < 2:
        raise SystemExit(f"{pattern!r}: need at least 2 batch images, found {len(paths)}")
    imgs = [read_pfm(p).astype(np.float64) for p in paths]
    shapes = {im.shape for im in imgs}
    if len(shapes) != 1:
        raise SystemExit(f"{pattern!r}: images of different sizes {sorted(shapes)}")
    return paths, np.stack(imgs)  # (n, h, w, 3)


# --- Student's t distribution without scipy: two-sided p-value via the regularised
# incomplete beta function, p = I_{df/(df+t^2)}(df/2, 1/2), evaluated with a
# continued fraction (modified Lentz), vectorised over arrays.

def _beta_cf(a, b, x, iters=300):
    tiny = 1e-300

    def fix(v):
        return np.where(np.abs(v) < tiny, tiny, v)

    c = np.ones_like(x)
    d = 1.0 / fix(1.0 - (a + b) * x / (a + 1.0))
    h = d.copy()
    for m in range(1, iters + 1):
        m2 = 2 * m
        num = m * (b - m) * x / ((a + m2 - 1.0) * (a + m2))
        d = 1.0 / fix(1.0 + num * d)
        c = fix(1.0 + num / c)
        h *= d * c
        num = -(a + m) * (a + b + m) * x / ((a + m2) * (a + m2 + 1.0))
        d = 1.0 / fix(1.0 + num * d)
        c = fix(1.0 + num / c)
        h *= d * c
    return h


def _inc_beta(a, b, x):
    """Regularised incomplete beta I_x(a, b) for arrays a, b, x (0 <= x <= 1)."""
    a, b, x = np.broadcast_arrays(np.asarray(a, float), np.asarray(b, float), np.asarray(x, float))
    lg = np.vectorize(math.lgamma)
    out = np.empty_like(x)
    inner = (x > 0) & (x < 1)
    out[x <= 0] = 0.0
    out[x >= 1] = 1.0
    if inner.any():
        aa, bb, xx = a[inner], b[inner], x[inner]
        ln_front = lg(aa + bb) - lg(aa) - lg(bb) + aa * np.log(xx) + bb * np.log1p(-xx)
        direct = xx < (aa + 1.0) / (aa + bb + 2.0)
        res = np.empty_like(xx)
        res[direct] = np.exp(ln_front[direct]) * _beta_cf(aa[direct], bb[direct], xx[direct]) / aa[direct]
        sw = ~direct
        res[sw] = 1.0 - np.exp(ln_front[sw]) * _beta_cf(bb[sw], aa[sw], 1.0 - xx[sw]) / bb[sw]
        out[inner] = res
    return out


def t_two_sided_p(t, df):
    t = np.abs(np.asarray(t, float))
    df = np.asarray(df, float)
    return _inc_beta(df / 2.0, 0.5, df / (df + t * t))


def z_two_sided_p(z):
    z = np.abs(np.asarray(z, float))
    erfc = np.vectorize(math.erfc)
    return erfc(z / math.sqrt(2.0))


def compare(A, B, alpha=0.01, test="z", luminance=False):
    na, nb = A.shape[0], B.shape[0]
    bad = ~(np.isfinite(A).all(axis=(0, 3)) & np.isfinite(B).all(axis=(0, 3)))  # (h, w)
    A = np.where(np.isfinite(A), A, 0.0)
    B = np.where(np.isfinite(B), B, 0.0)
    if luminance:
        A = (A @ LUM)[..., None]
        B = (B @ LUM)[..., None]
    ma, mb = A.mean(axis=0), B.mean(axis=0)
    va, vb = A.var(axis=0, ddof=1) / na, B.var(axis=0, ddof=1) / nb  # squared standard errors
    nch = ma.shape[-1]
    level = alpha / nch  # Bonferroni over the channels tested
    se = np.sqrt(va + vb)
    both_zero = se == 0
    equal = np.abs(ma - mb) <= 1e-6 * np.maximum(np.abs(mb), 1e-6)
    with np.errstate(divide="ignore", invalid="ignore"):
        stat = np.where(both_zero, 0.0, (ma - mb) / np.where(both_zero, 1.0, se))
    if test == "t":
        with np.errstate(divide="ignore", invalid="ignore"):
            df = (va + vb) ** 2 / (va**2 / (na - 1) + vb**2 / (nb - 1))
        df = np.where(np.isfinite(df) & (df > 0), df, float(na + nb - 2))
        p = t_two_sided_p(stat, df)
    else:
        p = z_two_sided_p(stat)
    ch_pass = np.where(both_zero, equal, p >= level)
    pix_pass = ch_pass.all(axis=-1) & ~bad
    good = ~bad
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = np.abs(ma - mb) / np.maximum(mb, 1e-2)
    mre = float(rel[good].mean()) if good.any() else float("nan")

    # Whole-image means per channel (finite pixels only) and their batch-spread z-score.
    ia = A[:, good].mean(axis=1)  # (n, c)
    ib = B[:, good].mean(axis=1)
    sea = ia.std(axis=0, ddof=1) / math.sqrt(na)
    seb = ib.std(axis=0, ddof=1) / math.sqrt(nb)
    with np.errstate(divide="ignore", invalid="ignore"):
        img_z = (ia.mean(axis=0) - ib.mean(axis=0)) / np.sqrt(sea**2 + seb**2)
    # Per-channel rejection rate of the test when A and B agree exactly, for these batch
    # counts (for z: t with the pooled df na + nb - 2 as a stand-in for Welch's).  The pixel
    # pass rate then lies between (1 - q)^c (independent channels) and 1 - q (identical
    # channels, e.g. grey scenes); pixels of zero spread (plain background) pass always.
    if test == "z":
        zc = _z_crit(level)
        q = float(t_two_sided_p(np.array([zc]), np.array([float(na + nb - 2)]))[0])
    else:
        q = level
    expected = ((1.0 - q) ** nch, 1.0 - q)
    return {
        "na": na, "nb": nb, "shape": A.shape[1:3], "nan_pixels": int(bad.sum()),
        "mre": mre, "pass": float(pix_pass.mean()), "expected_pass": expected,
        "img_a": ia.mean(axis=0), "img_b": ib.mean(axis=0), "img_z": img_z,
        "stat": stat, "pix_pass": pix_pass,
    }


def _z_crit(level):
    # Two-sided normal critical value by bisection on erfc.
    lo, hi = 0.0, 40.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if math.erfc(mid / math.sqrt(2.0)) > level:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def fmt_vec(v, digits=4):
    return "(" + ", ".join(f"{x:.{digits}f}" for x in np.atleast_1d(v)) + ")"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--a", required=True, help="glob of set A's batch PFMs (e.g. rayforge)")
    ap.add_argument("--b", required=True, help="glob of set B's batch PFMs (the reference)")
    ap.add_argument("--name", help="scene name for the table row (default: from --b's file name)")
    ap.add_argument("--alpha", type=float, default=0.01, help="family level per pixel (default 0.01)")
    ap.add_argument("--test", choices=["z", "t"], default="z")
    ap.add_argument("--luminance", action="store_true", help="test luminance instead of R, G, B")
    ap.add_argument("--header", action="store_true", help="print the markdown table header too")
    ap.add_argument("--fail-map", help="write a PFM: 1 where a pixel fails, 0 where it passes")
    args = ap.parse_args()

    pa, A = load_set(args.a)
    pb, B = load_set(args.b)
    if A.shape[1:] != B.shape[1:]:
        raise SystemExit(f"size mismatch: A {A.shape[2]}x{A.shape[1]}, B {B.shape[2]}x{B.shape[1]}")
    name = args.name or os.path.basename(pb[0]).split(".")[0]
    r = compare(A, B, alpha=args.alpha, test=args.test, luminance=args.luminance)
    what = "luminance" if args.luminance else "per channel, Bonferroni over R,G,B"
    h, w = r["shape"]
    print(f"scene {name}: {w}x{h}, A {r['na']} batches ({args.a}), B {r['nb']} batches ({args.b})")
    print(f"  NaN/Inf pixels: {r['nan_pixels']}" + ("  <-- WARNING" if r["nan_pixels"] else ""))
    print(f"  mean relative error of the means: {r['mre']:.4%}")
    print(f"  pixels passing two-sided Welch {args.test}-test at {args.alpha:g} ({what}): "
          f"{r['pass']:.2%} (expected if A and B agree: {r['expected_pass'][0]:.1%} to {r['expected_pass'][1]:.1%})")
    print(f"  image mean A {fmt_vec(r['img_a'])}  B {fmt_vec(r['img_b'])}  z {fmt_vec(r['img_z'], 2)}")
    if args.fail_map:
        from pfm import write_pfm
        write_pfm(args.fail_map, (~r["pix_pass"]).astype(np.float32))
        print(f"  fail map -> {args.fail_map}")
    if args.header:
        print("| scene | size | batches A/B | mean rel. err. | pass (Welch "
              f"{args.test}, {args.alpha:g}) | expected pass | NaN px | image mean A | image mean B | image z |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    print(f"| {name} | {w}x{h} | {r['na']}/{r['nb']} | {r['mre']:.3%} | {r['pass']:.2%} | "
          f"{r['expected_pass'][0]:.1%}-{r['expected_pass'][1]:.1%} | {r['nan_pixels']} | {fmt_vec(r['img_a'])} | "
          f"{fmt_vec(r['img_b'])} | {fmt_vec(r['img_z'], 2)} |")


if __name__ == "__main__":
    main()
