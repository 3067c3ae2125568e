"""The five reference scenes of /work/shared/pbr/README.md as Mitsuba 3 scene dicts.

Development and benchmarking aid only: rayforge never depends on Mitsuba.

Usage (after ``mi.set_variant(...)``)::

    import mitsuba_scenes
    scene = mi.load_dict(mitsuba_scenes.scene_dict("cornell"))

Conventions checked against Mitsuba 3.9.1 (see README.md next to this file and
``check_conventions.py``):

* ``perspective`` with ``fov_axis: x`` and ``look_at``: image right is forward x up.
* ``rectangle`` is [-1,1]^2 in the z = 0 plane with normal +Z; every rectangle here is
  placed by a matrix whose columns are (half-extent u, half-extent v, normal, centre)
  with u x v along the normal, so the one-sided emitter/BSDF faces the stated side.
* ``envmap``: checked numerically (``check_conventions.py`` evaluates the emitter at the
  README's texel-centre directions): Mitsuba 3.9.1's default frame already is the
  README's convention -- u = atan2(x, -z) / 2pi, v = acos(y) / pi, texel centre i at
  phi = 2pi(i + 0.5)/W, row j at theta = pi j/(H - 1), bilinear between texel centres.
  So no rotation is needed (``ENVMAP_ROT_DEG`` = 0; the hook stays for other versions).
"""

import math
import os

import mitsuba as mi

PBR_DIR = os.environ.get("PBR_DIR", "/work/shared/pbr")
ENVMAP_FILE = os.path.join(PBR_DIR, "envmap-sky.pfm")  # PFM: EXR reading can hang on 1 thread
ENVMAP_WIDTH = 64
# Rotation of the envmap about +Y in degrees; 0 = Mitsuba 3.9.1 matches the README.
ENVMAP_ROT_DEG = 0.0

SCENES = ["furnace", "furnace-closed", "cornell", "spheres-materials", "envmap"]

ALU_ETA = [1.6575, 0.880405, 0.521244]
ALU_K = [9.22381, 6.2695, 4.837]

CORNELL_WHITE = [0.885809, 0.698859, 0.666422]
CORNELL_RED = [0.570068, 0.0430135, 0.0443706]
CORNELL_GREEN = [0.105421, 0.37798, 0.076425]


def rgb(v):
    if isinstance(v, (int, float)):
        v = [v, v, v]
    return {"type": "rgb", "value": list(v)}


def diffuse(albedo):
    return {"type": "diffuse", "reflectance": rgb(albedo)}


def area(radiance):
    return {"type": "area", "radiance": rgb(radiance)}


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _unit(a):
    n = math.sqrt(sum(x * x for x in a))
    return [x / n for x in a]


def rect_transform(center, normal, size_u, size_v, u_dir):
    """to_world of a Mitsuba rectangle: centre, unit normal, full side lengths along
    u_dir and along normal x u_dir (u_dir must be perpendicular to the normal)."""
    n = _unit(normal)
    u = _unit(u_dir)
    v = _cross(n, u)  # u x v = u x (n x u) = n  (right-handed)
    hu, hv = size_u / 2.0, size_v / 2.0
    m = [
        [u[0] * hu, v[0] * hv, n[0], center[0]],
        [u[1] * hu, v[1] * hv, n[1], center[1]],
        [u[2] * hu, v[2] * hv, n[2], center[2]],
        [0.0, 0.0, 0.0, 1.0],
    ]
    return mi.ScalarTransform4f(m)


def rectangle(center, normal, size_u, size_v, u_dir, bsdf, emitter=None):
    d = {
        "type": "rectangle",
        "to_world": rect_transform(center, normal, size_u, size_v, u_dir),
        "bsdf": bsdf,
    }
    if emitter is not None:
        d["emitter"] = emitter
    return d


def sphere(center, radius, bsdf):
    return {"type": "sphere", "center": list(center), "radius": float(radius), "bsdf": bsdf}


def sensor(origin, target, up, fov, size, spp=16):
    return {
        "type": "perspective",
        "fov_axis": "x",
        "fov": float(fov),
        "to_world": mi.ScalarTransform4f().look_at(origin=origin, target=target, up=up),
        "near_clip": 1e-3,
        "far_clip": 1e4,
        "sampler": {"type": "independent", "sample_count": spp},
        "film": {
            "type": "hdrfilm",
            "width": size,
            "height": size,
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
            "component_format": "float32",
        },
    }


def base(sensor_dict):
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": -1},
        "sensor": sensor_dict,
    }


def rough_aluminium():
    return {
        "type": "roughconductor",
        "distribution": "ggx",
        "alpha": 0.2,
        "sample_visible": True,
        "eta": rgb(ALU_ETA),
        "k": rgb(ALU_K),
    }


def smooth_aluminium():
    return {"type": "conductor", "eta": rgb(ALU_ETA), "k": rgb(ALU_K)}


def glass():
    return {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}


def furnace():
    s = base(sensor([0, 0, 4], [0, 0, 0], [0, 1, 0], 40, 128))
    s["sphere"] = sphere([0, 0, 0], 1.0, diffuse(0.8))
    s["env"] = {"type": "constant", "radiance": rgb(1.0)}
    return s


def furnace_closed():
    s = base(sensor([0, 0, 0], [0, 0, 1], [0, 1, 0], 90, 128))
    # The solid [-1,1]^3 with its normals turned inwards: the inside faces are the
    # front faces of both the (one-sided) diffuse BSDF and the area emitter.
    s["box"] = {
        "type": "cube",
        "flip_normals": True,
        "bsdf": diffuse(0.8),
        "emitter": area(0.2),
    }
    return s


def cornell():
    s = base(sensor([0, 0, 3.9], [0, 0, 0], [0, 1, 0], 39.3077, 256))
    white, red, green = diffuse(CORNELL_WHITE), diffuse(CORNELL_RED), diffuse(CORNELL_GREEN)
    s["floor"] = rectangle([0, -1, 0], [0, 1, 0], 2, 2, [1, 0, 0], white)
    s["ceiling"] = rectangle([0, 1, 0], [0, -1, 0], 2, 2, [1, 0, 0], white)
    s["back"] = rectangle([0, 0, -1], [0, 0, 1], 2, 2, [1, 0, 0], white)
    s["red"] = rectangle([-1, 0, 0], [1, 0, 0], 2, 2, [0, 0, 1], red)
    s["green"] = rectangle([1, 0, 0], [-1, 0, 0], 2, 2, [0, 0, 1], green)
    s["light"] = rectangle(
        [0, 0.99, 0.01], [0, -1, 0], 0.46, 0.38, [1, 0, 0], white,
        area([18.387, 13.9873, 6.75357]),
    )
    T = mi.ScalarTransform4f
    s["small_box"] = {
        "type": "cube",
        "to_world": T().translate([0.335, -0.7, 0.38]) @ T().rotate([0, 1, 0], -17) @ T().scale(0.3),
        "bsdf": white,
    }
    s["tall_box"] = {
        "type": "cube",
        "to_world": T().translate([-0.33, -0.4, -0.28])
        @ T().rotate([0, 1, 0], 18.25)
        @ T().scale([0.3, 0.61, 0.3]),
        "bsdf": white,
    }
    return s


def spheres_materials():
    s = base(sensor([0, 1.5, 5], [0, 0.5, 0], [0, 1, 0], 45, 128))
    s["floor"] = rectangle([0, 0, 0], [0, 1, 0], 20, 20, [1, 0, 0], diffuse(0.5))
    s["light"] = rectangle([0, 3, 0.5], [0, -1, 0], 2, 2, [1, 0, 0], diffuse(0.0), area(15.0))
    s["diffuse"] = sphere([-1.2, 0.5, 0], 0.5, diffuse([0.8, 0.3, 0.2]))
    s["metal"] = sphere([0, 0.5, 0], 0.5, rough_aluminium())
    s["glass"] = sphere([1.2, 0.5, 0], 0.5, glass())
    return s


def envmap():
    s = base(sensor([0, 0.5, 6], [0, 0, 0], [0, 1, 0], 45, 128))
    s["diffuse"] = sphere([-1.1, 0, 0], 1.0, diffuse(0.7))
    s["metal"] = sphere([1.1, 0, 0], 1.0, smooth_aluminium())
    s["env"] = envmap_emitter()
    return s


def envmap_emitter(filename=ENVMAP_FILE, rot_deg=ENVMAP_ROT_DEG):
    return {
        "type": "envmap",
        "filename": filename,
        "scale": 1.0,
        "to_world": mi.ScalarTransform4f().rotate([0, 1, 0], rot_deg),
    }


BUILDERS = {
    "furnace": furnace,
    "furnace-closed": furnace_closed,
    "cornell": cornell,
    "spheres-materials": spheres_materials,
    "envmap": envmap,
}


def scene_dict(name):
    """The Mitsuba scene dict of one reference scene (requires a variant to be set)."""
    try:
        return BUILDERS[name]()
    except KeyError:
        raise SystemExit(f"unknown scene {name!r}; known: {', '.join(SCENES)}") from None


def image_size(name):
    return 256 if name == "cornell" else 128
