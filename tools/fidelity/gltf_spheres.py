#!/usr/bin/env python3
"""Three glTF metallic-roughness spheres, rendered by rayforge from a glTF file and by
Mitsuba 3 from the same spheres described in its own format (Mitsuba reads no glTF).

    python3 tools/fidelity/gltf_spheres.py --out /work/fidelity-data/gltf-spheres \
        --spp 256 --batches 8 [--bin target/release/rayforge]

Writes OUT/gltf-spheres.gltf (one UV-sphere mesh shared by three nodes, three materials, a
perspective camera and a directional KHR_lights_punctual light) and OUT/sphere.obj (the same
mesh for Mitsuba), renders B batches on each side (rayforge with seeds 0..B-1, Mitsuba with
seeds 0..B-1), and prints compare.py's verdict for the whole image and the mean radiance of
each sphere on both sides with its standard error.

The Mitsuba description of glTF's material (as docs/scene-format.md gives rayforge's meaning
of it): `blendbsdf` with weight `metallic` between `plastic` (int_ior = ior,
diffuse_reflectance = base colour, nonlinear false; `roughplastic` with GGX alpha roughness^2
when rough) and `conductor` (material `none` -- Fresnel 1 -- with specular_reflectance = base
colour; `roughconductor`, GGX, the same alpha, when rough). The sky is rayforge's default for a model rendered directly (a constant 0.5); the
light's intensity in lux is Mitsuba's irradiance.
"""

import argparse
import base64
import json
import math
import os
import struct
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from pfm import read_pfm, write_pfm  # noqa: E402

WIDTH, HEIGHT = 192, 128
YFOV = 0.6
EYE = (0.0, 0.8, 7.0)
SUN_DIRECTION = (0.45, -0.8, -0.4)  # where the light travels
SUN_LUX = 2.0
SKY = 0.5
CENTRES = [(-2.2, 0.0, 0.0), (0.0, 0.0, 0.0), (2.2, 0.0, 0.0)]
# (name, base colour, metallic, roughness)
MATERIALS = [
    ("smooth red dielectric", (0.8, 0.25, 0.2), 0.0, 0.0),
    ("rough gold", (0.95, 0.75, 0.35), 1.0, 0.35),
    ("rough blue metal", (0.3, 0.55, 0.85), 1.0, 0.7),
]
# A half metal is left out too: Mitsuba's `blendbsdf` of `plastic` and `conductor` (both with
# delta lobes) renders 0.7 % brighter than the mean of its own renders of the two (blue:
# 0.5842 against 0.5799), where rayforge's blend is the mean of its pure materials to 0.03 %.
# A rough dielectric is left out on purpose: Mitsuba 3's `roughplastic` scales its diffuse
# base by tabulated rough transmittances that lose energy (mitsuba3 issue #1155: its albedo
# at normal incidence is 0.60 for a 0.8 base at alpha 0.25, against 0.81 for `plastic`),
# where glTF's model and rayforge keep the smooth coat's base term.
IOR = 1.5


def uv_sphere(segments=64, rings=32):
    pos, nrm, idx = [], [], []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            p = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            pos.append(p)
            nrm.append(p)
    for j in range(rings):
        for i in range(segments):
            a = j * (segments + 1) + i
            b = a + segments + 1
            # Counter-clockwise seen from outside (glTF's front).
            if j != 0:
                idx += [a, b, a + 1]
            if j != rings - 1:
                idx += [a + 1, b, b + 1]
    return pos, nrm, idx


def quat_between(a, b):
    a = np.array(a, float) / np.linalg.norm(a)
    b = np.array(b, float) / np.linalg.norm(b)
    axis = np.cross(a, b)
    w = 1.0 + float(np.dot(a, b))
    q = np.array([axis[0], axis[1], axis[2], w])
    return list(q / np.linalg.norm(q))


def write_gltf(out):
    pos, nrm, idx = uv_sphere()
    pos_b = b"".join(struct.pack("<3f", *p) for p in pos)
    nrm_b = b"".join(struct.pack("<3f", *n) for n in nrm)
    idx_b = b"".join(struct.pack("<I", i) for i in idx)
    blob = pos_b + nrm_b + idx_b
    pitch = -math.atan2(EYE[1], EYE[2])
    doc = {
        "asset": {"version": "2.0", "generator": "rayforge tools/fidelity/gltf_spheres.py"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "color": [1, 1, 1], "intensity": SUN_LUX}]}},
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": len(pos_b)},
            {"buffer": 0, "byteOffset": len(pos_b), "byteLength": len(nrm_b)},
            {"buffer": 0, "byteOffset": len(pos_b) + len(nrm_b), "byteLength": len(idx_b)},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
             "min": [-1, -1, -1], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": len(nrm), "type": "VEC3"},
            {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"},
        ],
        "materials": [
            {"name": n, "pbrMetallicRoughness": {"baseColorFactor": [*c, 1.0],
                                                 "metallicFactor": m, "roughnessFactor": r}}
            for (n, c, m, r) in MATERIALS
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                    "material": k}]} for k in range(3)],
        "cameras": [{"type": "perspective", "perspective": {
            "yfov": YFOV, "aspectRatio": WIDTH / HEIGHT, "znear": 0.01}}],
        "nodes": [{"mesh": k, "translation": list(c)} for k, c in enumerate(CENTRES)] + [
            {"camera": 0, "translation": list(EYE),
             "rotation": [math.sin(pitch / 2), 0, 0, math.cos(pitch / 2)]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}},
             "rotation": quat_between((0, 0, -1), SUN_DIRECTION)},
        ],
        "scenes": [{"nodes": [0, 1, 2, 3, 4]}],
        "scene": 0,
    }
    path = os.path.join(out, "gltf-spheres.gltf")
    with open(path, "w") as f:
        json.dump(doc, f)
    with open(os.path.join(out, "sphere.obj"), "w") as f:
        for p in pos:
            f.write("v %r %r %r\n" % p)
        for n in nrm:
            f.write("vn %r %r %r\n" % n)
        for t in range(0, len(idx), 3):
            a, b, c = (i + 1 for i in idx[t:t + 3])
            f.write(f"f {a}//{a} {b}//{b} {c}//{c}\n")
    return path


def mitsuba_scene(out, spp, seed):
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    shapes = {}
    for k, ((_, colour, metallic, roughness), centre) in enumerate(zip(MATERIALS, CENTRES)):
        alpha = roughness * roughness
        tint = {"type": "rgb", "value": list(colour)}
        plastic = {"type": "plastic", "int_ior": IOR, "ext_ior": 1.0, "nonlinear": False,
                   "diffuse_reflectance": tint}
        metal = {"type": "conductor", "material": "none", "specular_reflectance": tint}
        if alpha > 0:
            plastic.update(type="roughplastic", distribution="ggx", alpha=alpha)
            metal.update(type="roughconductor", distribution="ggx", alpha=alpha)
        bsdf = {"type": "blendbsdf", "weight": metallic, "bsdf_0": plastic, "bsdf_1": metal}
        shapes[f"sphere{k}"] = {"type": "obj", "filename": os.path.join(out, "sphere.obj"),
                                "face_normals": False, "bsdf": bsdf,
                                "to_world": mi.ScalarTransform4f().translate(list(centre))}
    return mi.load_dict({
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": {
            "type": "perspective", "fov_axis": "y", "fov": math.degrees(YFOV),
            "to_world": mi.ScalarTransform4f().look_at(origin=list(EYE), target=[0, 0, 0], up=[0, 1, 0]),
            "sampler": {"type": "independent", "sample_count": spp, "seed": seed},
            "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT, "rfilter": {"type": "box"},
                     "pixel_format": "rgb", "component_format": "float32"},
        },
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": [SKY] * 3}},
        "sun": {"type": "directional", "direction": list(SUN_DIRECTION),
                "irradiance": {"type": "rgb", "value": [SUN_LUX] * 3}},
        **shapes,
    })


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--batches", type=int, default=8)
    ap.add_argument("--bin", default=os.path.join(HERE, "..", "..", "target", "release", "rayforge"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    model = write_gltf(args.out)
    for b in range(args.batches):
        target = os.path.join(args.out, f"gltf-spheres.rayforge.b{b}.pfm")
        subprocess.run([args.bin, "render", model, "-o", target, "--renderer", "path", "--spp",
                        str(args.spp), "--seed", str(b), "--width", str(WIDTH), "--height",
                        str(HEIGHT), "-q"], check=True)
    import mitsuba as mi
    for b in range(args.batches):
        scene = mitsuba_scene(args.out, args.spp, b)
        image = np.array(mi.render(scene, spp=args.spp, seed=b), dtype=np.float32)[:, :, :3]
        write_pfm(os.path.join(args.out, f"gltf-spheres.mitsuba.b{b}.pfm"), image)
    subprocess.run([sys.executable, os.path.join(HERE, "compare.py"), "--header", "--a",
                    os.path.join(args.out, "gltf-spheres.rayforge.b*.pfm"), "--b",
                    os.path.join(args.out, "gltf-spheres.mitsuba.b*.pfm")], check=True)
    # Each sphere's mean over the pixels that see it in every batch of both sides.
    sides = {}
    for side in ("rayforge", "mitsuba"):
        batches = [read_pfm(os.path.join(args.out, f"gltf-spheres.{side}.b{b}.pfm"))
                   for b in range(args.batches)]
        sides[side] = np.stack(batches)
    print("\n| sphere | rayforge (R, G, B) | Mitsuba 3 (R, G, B) | difference / standard error |")
    print("|---|---|---|---|")
    for k, (name, _, metallic, roughness) in enumerate(MATERIALS):
        x0 = int(WIDTH * (0.5 + (k - 1) * 0.345)) - 8
        y0 = HEIGHT // 2 - 8
        row = []
        stats = {}
        for side, data in sides.items():
            patch = data[:, y0:y0 + 16, x0:x0 + 16, :3].mean(axis=(1, 2))
            stats[side] = (patch.mean(axis=0), patch.std(axis=0, ddof=1) / math.sqrt(len(patch)))
        (ma, sa), (mb, sb) = stats["rayforge"], stats["mitsuba"]
        z = (ma - mb) / np.sqrt(sa ** 2 + sb ** 2 + 1e-30)
        fmt = lambda v: ", ".join(f"{x:.4f}" for x in v)  # noqa: E731
        print(f"| {name} (metallic {metallic}, roughness {roughness}) | {fmt(ma)} | {fmt(mb)} | "
              f"{', '.join(f'{x:+.1f}' for x in z)} |")


if __name__ == "__main__":
    main()
