#!/usr/bin/env python3
"""Render Bitterli's scenes (pbrt-v4 form, ../shared/bitterli/) with pbrt-v4 and rayforge.

    python3 tools/fidelity/pbrt_bitterli.py pbrt SCENE --spp N --batches B [--seed0 S]
    python3 tools/fidelity/pbrt_bitterli.py rayforge SCENE --spp N --batches B [--seed0 S] [--bin PATH]

Both write linear PFM batches into DATA/SCENE/ (DATA is /work/fidelity-data/bitterli by
default, --data): `SCENE.pbrt.bK.pfm` and `SCENE.rayforge.bK.pfm`, batch K rendered with
seed S + K, each an independent estimate (pbrt-v4's `--seed` rescrambles its samplers;
rayforge's `--seed` likewise), at a quarter of the file's resolution (--divide) and the
file's own settings otherwise (integrator, maxdepth, filter). Each prints its wall time.

pbrt-v4 has no flag for the resolution, so `pbrt` writes a copy of the scene file into
DATA/SCENE/ with the Film's resolution divided, and links the scene's `models/` and
`textures/` beside it (pbrt-v4 resolves a scene's file names in the top-level file's folder,
`SetSearchDirectory`). rayforge reads the original with --width/--height (the same field of
view). `--grey` renders a copy in which every rgb of the scene is replaced by its luminance
(with pbrt only: rayforge reads the same copy via `rayforge SCENE --grey`), to tell RGB
rendering's differences from spectral rendering's: pbrt-v4 renders spectra, rayforge RGB,
and the two agree exactly for grey.

Compare the batches with compare_pbrt.py. Nothing here is a build or test dependency of
rayforge.
"""

import argparse
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
# ../shared beside the checkout (a worktree's checkout may lie deeper: then /work/shared).
SHARED = next(
    (p for p in (os.path.join(os.path.dirname(REPO), "shared", "bitterli"), "/work/shared/bitterli")
     if os.path.isdir(p)),
    "/work/shared/bitterli",
)
PBRT = "/work/peers/pbrt-v4/build/pbrt"

RES = re.compile(r'"integer\s+([xy])resolution"\s*(\[\s*)?(\d+)(\s*\])?')
# One parameter with its values: `"type name" [ values ]` or `"type name" value`.
PARAM = re.compile(r'"\w+\s+(\w+)"\s*(?:\[[^\]]*\]|"[^"]*"|[-+0-9.eE]+)')
# The parameters pbrt-v4's `path` and `volpath` integrators take.
KEPT_BY_PATH = {"maxdepth", "regularize", "lightsampler"}
RGB = re.compile(r'"(rgb|color)\s+([A-Za-z_.]+)"\s*\[\s*([-+0-9.eE]+)\s+([-+0-9.eE]+)\s+([-+0-9.eE]+)\s*\]')


def original(scene):
    path = os.path.join(SHARED, scene, "pbrt", "scene-v4.pbrt")
    if not os.path.isfile(path):
        raise SystemExit(f"{path}: no such scene")
    return path


def resolution(text):
    """The Film's (x, y) resolution: the first uncommented x and y lines."""
    found = {}
    for line in text.splitlines():
        if line.lstrip().startswith("#"):
            continue
        for m in RES.finditer(line.split("#")[0]):
            found.setdefault(m.group(1), int(m.group(3)))
    return found.get("x", 1280), found.get("y", 720)


def grey_text(text):
    """Every rgb of the scene replaced by its luminance (Rec. 709 weights)."""

    def grey(m):
        r, g, b = (float(m.group(i)) for i in (3, 4, 5))
        y = 0.2126 * r + 0.7152 * g + 0.0722 * b
        return f'"{m.group(1)} {m.group(2)}" [ {y:.9g} {y:.9g} {y:.9g} ]'

    return RGB.sub(grey, text)


def prepared(scene, data, divide, grey, integrator=None):
    """The scene's copy for pbrt (resolution divided; grey, another integrator if asked) and
    its resolution."""
    src = original(scene)
    text = open(src).read()
    width, height = resolution(text)
    w, h = max(1, width // divide), max(1, height // divide)
    out_lines = []
    in_integrator = False
    for line in text.splitlines():
        code, sep, comment = line.partition("#")
        if code.strip() and integrator:
            # The replaced integrator's parameters follow on its line or the next ones; those
            # the new one does not take (sppm's `radius`, bdpt's visualisations) are dropped,
            # as pbrt-v4 refuses a parameter its integrator does not use.
            replaced = re.sub(r'^(\s*)Integrator\s+"[^"]*"', rf'\1Integrator "{integrator}"', code)
            if replaced != code:
                in_integrator, code = True, replaced
            elif not code.lstrip().startswith('"'):
                in_integrator = False
            if in_integrator:
                code = PARAM.sub(lambda m: m.group(0) if m.group(1) in KEPT_BY_PATH else "", code)
        if code.strip():
            code = RES.sub(
                lambda m: f'"integer {m.group(1)}resolution" [ {w if m.group(1) == "x" else h} ]',
                code,
            )
        out_lines.append(code + sep + comment)
    text = "\n".join(out_lines) + "\n"
    if grey:
        text = grey_text(text)
    folder = os.path.join(data, scene)
    os.makedirs(folder, exist_ok=True)
    for sub in ("models", "textures"):
        target = os.path.join(os.path.dirname(src), sub)
        link = os.path.join(folder, sub)
        if os.path.isdir(target) and not os.path.lexists(link):
            os.symlink(target, link)
    name = "scene-" + ("grey" if grey else "quarter") + (f"-{integrator}" if integrator else "") + ".pbrt"
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write(text)
    return path, (w, h)


def run(cmd, log):
    start = time.time()
    with open(log, "a") as f:
        f.write("$ " + " ".join(cmd) + "\n")
        f.flush()
        result = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    took = time.time() - start
    with open(log, "a") as f:
        f.write(f"# rc {result.returncode}, {took:.1f} s wall\n")
    if result.returncode != 0:
        raise SystemExit(f"failed ({result.returncode}): {' '.join(cmd)}; see {log}")
    return took


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("renderer", choices=["pbrt", "rayforge"])
    ap.add_argument("scene")
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--batches", type=int, default=2)
    ap.add_argument("--seed0", type=int, default=1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--divide", type=int, default=4, help="resolution divisor (4: a quarter)")
    ap.add_argument("--data", default="/work/fidelity-data/bitterli")
    ap.add_argument("--bin", default=None, help="the renderer's binary")
    ap.add_argument("--tag", default=None, help="name the batches SCENE.TAG.bK.pfm")
    ap.add_argument("--grey", action="store_true", help="render the grey copy (see above)")
    ap.add_argument("--integrator", default=None,
                    help="pbrt only: replace the file's Integrator by this one (its parameters kept)")
    ap.add_argument("--extra", default="", help="more arguments for the renderer, one string")
    a = ap.parse_args()
    copy, (w, h) = prepared(a.scene, a.data, a.divide, a.grey, a.integrator)
    folder = os.path.dirname(copy)
    tag = a.tag or (a.renderer + ("-grey" if a.grey else ""))
    log = os.path.join(folder, f"{a.scene}.{tag}.log")
    for k in range(a.batches):
        seed = a.seed0 + k
        out = os.path.join(folder, f"{a.scene}.{tag}.b{k}.pfm")
        if a.renderer == "pbrt":
            cmd = [a.bin or PBRT, "--seed", str(seed), "--spp", str(a.spp), "--nthreads",
                   str(a.threads), "--outfile", out, "--quiet", copy]
        else:
            scene = copy if a.grey else original(a.scene)
            binary = a.bin or os.path.join(REPO, "target", "release", "rayforge")
            cmd = [binary, "render", scene, "-o", out, "--width", str(w), "--height", str(h),
                   "--spp", str(a.spp), "--seed", str(seed), "--threads", str(a.threads),
                   "--quiet"]
            if a.grey:
                cmd.append("--allow-outside")
        cmd += a.extra.split()
        took = run(cmd, log)
        print(f"{a.scene} {tag} b{k} seed {seed}: {w}x{h} {a.spp} spp, {took:.1f} s, "
              f"{w * h * a.spp / took / 1e6:.3f} Msamples/s", flush=True)


if __name__ == "__main__":
    main()
