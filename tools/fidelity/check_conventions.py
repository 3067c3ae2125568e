"""Numerical checks of the Mitsuba conventions that mitsuba_scenes.py relies on.

    python3 tools/fidelity/check_conventions.py

1. envmap: Mitsuba's envmap `eval` at the README's texel-centre directions
   d = (sin phi sin theta, cos theta, -cos phi sin theta), phi = 2 pi (i + 0.5)/64,
   theta = pi j/31, compared with the texels, without and with the rotation that
   mitsuba_scenes applies.
2. camera: the direction of the ray through the right edge of the image is forward x up.
3. rectangles: each Cornell wall's geometric normal, seen by a ray from the room centre.
"""

import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mitsuba as mi  # noqa: E402

mi.set_variant("scalar_rgb")
import mitsuba_scenes as ms  # noqa: E402
from pfm import read_pfm  # noqa: E402


def readme_dir(i, j, w=64, h=32):
    phi = 2 * math.pi * (i + 0.5) / w
    th = math.pi * j / (h - 1)
    return [math.sin(phi) * math.sin(th), math.cos(th), -math.cos(phi) * math.sin(th)]


def env_eval(emitter, d):
    si = mi.SurfaceInteraction3f()
    si.wi = mi.Vector3f(-d[0], -d[1], -d[2])  # eval looks up -wi
    return np.array(emitter.eval(si))


def check_envmap():
    tex = read_pfm(ms.ENVMAP_FILE)
    h, w, _ = tex.shape
    em = mi.load_dict(ms.envmap_emitter())
    errs = []
    for j in range(h):
        for i in range(w):
            v = env_eval(em, readme_dir(i, j, w, h))
            errs.append(np.abs(v - tex[j, i]).max() / max(tex[j, i].max(), 1e-3))
    print(f"envmap (rotation {ms.ENVMAP_ROT_DEG} deg about +Y): max rel. error at the README's "
          f"texel centres = {max(errs):.3e}")
    ok = max(errs) < 1e-3
    # Bilinear interpolation between texel centres, along phi and along theta.
    j, i = 9, 39  # the sun texel
    for label, (x, y), want in (
        ("phi half-way (9,39)-(9,40)", (i + 1.0, j), 0.5 * (tex[j, i] + tex[j, i + 1])),
        ("theta half-way (9,39)-(10,39)", (i + 0.5, j + 0.5), 0.5 * (tex[j, i] + tex[j + 1, i])),
        ("phi quarter (9,39)-(9,40)", (i + 0.75, j), 0.75 * tex[j, i] + 0.25 * tex[j, i + 1]),
    ):
        phi = 2 * math.pi * x / w
        th = math.pi * y / (h - 1)
        d = [math.sin(phi) * math.sin(th), math.cos(th), -math.cos(phi) * math.sin(th)]
        got = env_eval(em, d)
        err = np.abs(got - want).max() / want.max()
        print(f"  {label}: mitsuba {np.round(got, 4)}, bilinear {np.round(want, 4)}, rel. err {err:.1e}")
        ok &= err < 1e-3
    return ok


def check_camera():
    scene = mi.load_dict(ms.scene_dict("cornell"))
    cam = scene.sensors()[0]
    ok = True
    for x, y, label in ((0.999, 0.5, "right"), (0.001, 0.5, "left"), (0.5, 0.001, "top")):
        ray, _ = cam.sample_ray(0.0, 0.5, mi.Point2f(x, y), mi.Point2f(0.5, 0.5))
        d = np.array(ray.d)
        print(f"camera: image {label:5s} edge ray direction {np.round(d, 3)}")
    ray, _ = cam.sample_ray(0.0, 0.5, mi.Point2f(0.999, 0.5), mi.Point2f(0.5, 0.5))
    ok &= float(ray.d[0]) > 0  # forward (0,0,-1) x up (0,1,0) = +X
    # Horizontal fov: the edge ray makes half the fov with the forward axis.
    ray, _ = cam.sample_ray(0.0, 0.5, mi.Point2f(1.0, 0.5), mi.Point2f(0.5, 0.5))
    half = math.degrees(math.atan2(abs(float(ray.d[0])), abs(float(ray.d[2]))))
    print(f"camera: half horizontal fov {half:.4f} (want {39.3077 / 2:.4f})")
    ok &= abs(half - 39.3077 / 2) < 1e-3
    return ok


def check_rectangles():
    scene = mi.load_dict(ms.scene_dict("cornell"))
    ok = True
    probes = {
        "floor": ([0, -1, 0.9], [0, 1, 0]),
        "ceiling (or light)": ([0.7, 1, 0.7], [0, -1, 0]),
        "light": ([0, 1, 0], [0, -1, 0]),
        "back": ([0, 0.5, -1], [0, 0, 1]),
        "red (x=-1)": ([-1, 0.5, 0.5], [1, 0, 0]),
        "green (x=+1)": ([1, 0.5, 0.5], [-1, 0, 0]),
    }
    for label, (target, want_n) in probes.items():
        # From the open front of the room, above both boxes.
        o = np.array([0.0, 0.5, 0.9]) if label != "light" else np.array([0.0, 0.0, 0.0])
        d = np.array(target, float) - o
        d /= np.linalg.norm(d)
        si = scene.ray_intersect(mi.Ray3f(mi.Point3f(*o), mi.Vector3f(*d)))
        n = np.array(si.n)
        emits = si.shape.emitter() is not None
        print(f"rect {label:18s}: hit t={float(si.t):.3f} normal {np.round(n, 3)} emitter={emits}")
        ok &= np.allclose(n, want_n, atol=1e-5)
        if label == "light":
            ok &= emits and abs(float(si.t) - 0.99) < 1e-5
    return ok


if __name__ == "__main__":
    results = {"envmap": check_envmap(), "camera": check_camera(), "rectangles": check_rectangles()}
    for k, v in results.items():
        print(f"{k}: {'OK' if v else 'FAILED'}")
    sys.exit(0 if all(results.values()) else 1)
