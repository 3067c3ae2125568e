#!/usr/bin/env python3
"""Renders a pbrt-v4 scene with Blender's Cycles, for the equal-time comparison of
docs/performance.md ("The path tracer against Blender's Cycles"). A benchmarking aid outside
the renderer: rayforge never depends on Blender.

    /path/to/venv/bin/python bench/bitterli/cycles_pbrt.py SCENE.pbrt -o OUT.exr \\
        [--divide 4] [--spp 64] [--threads 2] [--seed 1]

Needs PyPI's `bpy` (Blender as a Python module; 5.3.0 on Python 3.13 when measured). It
prints one line, `cycles render_s=SECONDS spp=N size=WxH`, the time of the render alone
(Blender's start and the scene's build left out, as rayforge's summary leaves out loading).

How the scene is matched (what this reader takes from the file; anything else is refused, so
that a comparison never runs on a scene read differently):
- `Camera "perspective"` with `fov` on the image's shorter axis, placed by the `Transform`
  before it (pbrt's camera looks down +z with +y up in a left-handed frame; Blender's down −z:
  the camera's object matrix is the inverse of pbrt's camera-from-world times diag(1, 1, −1),
  which keeps every pixel's direction).
- `Film "rgb"` resolution (divided by `--divide`), written as linear OpenEXR with Blender's
  "Standard" view (no tone curve, no exposure).
- `Integrator` `maxdepth` N: pbrt-v4 adds light at N scattering events at most, Cycles'
  `max_bounces` counts the bounces after the first, so Cycles gets N − 1 (per kind too).
  Clamping, caustic blurring, adaptive sampling, light-path guiding and denoising off; the
  light tree on (Cycles' default, the counterpart of pbrt's BVH light sampler).
- `PixelFilter`: `box` as Cycles' box of width 2·radius, `gaussian` as Cycles' Gaussian of
  width 2·radius; the `triangle` filter (Cycles has none) as a Gaussian of the same support.
- Materials: `diffuse` (Lambert: Cycles' Diffuse BSDF at roughness 0) and `conductor` with
  `rgb eta`/`rgb k` (Cycles' Metallic BSDF, "physical conductor" Fresnel, single-scattering
  GGX; pbrt's `roughness` α read as Cycles' roughness √α, Cycles squaring it).
- `AreaLightSource "diffuse"` `L` (and `scale`): an Emission of that radiance on the shape's
  front only (pbrt's lamps are one-sided): Cycles' mesh lights shine from both sides, so the
  back face is masked by the geometry's `Backfacing` output.
- Shapes: `trianglemesh` (`P`, `indices`, `N`) and `sphere` (`radius`): a glowing sphere of a
  black material as Cycles' sphere light (a point light with that radius, camera-visible, no
  soft falloff: sampled by its cone as pbrt-v4 and rayforge sample it), any other sphere as a
  smooth UV sphere of 256 × 128 facets (its area within 0.02 % of the sphere's).
- `Transform`, `Translate`, `Scale`, `ConcatTransform`, `AttributeBegin`/`End`,
  `MakeNamedMaterial`, `NamedMaterial`, `Material`; `Sampler` and `Accelerator` ignored (each
  renderer uses its own).
"""

import argparse
import math
import re
import sys
import time

import bpy
from mathutils import Matrix, Vector

TOKEN = re.compile(r'\s*(?:#[^\n]*|("[^"]*")|(\[)|(\])|([A-Za-z_][A-Za-z0-9_]*)|([-+0-9.eE]+))')


def tokens(text):
    """The file's tokens: ('s', string), ('[',), (']',), ('id', name), ('n', number)."""
    at = 0
    while at < len(text):
        m = TOKEN.match(text, at)
        if not m or m.end() == at:
            if text[at:].strip() == "":
                return
            raise SystemExit(f"cannot read the scene at character {at}: {text[at:at + 20]!r}")
        at = m.end()
        if m.group(1):
            yield ("s", m.group(1)[1:-1])
        elif m.group(2):
            yield ("[",)
        elif m.group(3):
            yield ("]",)
        elif m.group(4):
            yield ("id", m.group(4))
        elif m.group(5):
            yield ("n", float(m.group(5)))


class Directives:
    """Directives with their positional arguments and typed parameter lists."""

    def __init__(self, text):
        self.toks = list(tokens(text))
        self.i = 0

    def __iter__(self):
        while self.i < len(self.toks):
            tok = self.toks[self.i]
            if tok[0] != "id":
                raise SystemExit(f"expected a directive, found {tok}")
            self.i += 1
            args = []
            while self.i < len(self.toks) and self.toks[self.i][0] in ("n", "["):
                args.append(self.value())
            if self.i < len(self.toks) and self.toks[self.i][0] == "s" and not self.is_param(self.toks[self.i][1]):
                args.append(self.toks[self.i][1])
                self.i += 1
            params = {}
            while self.i < len(self.toks) and self.toks[self.i][0] == "s" and self.is_param(self.toks[self.i][1]):
                kind, name = self.toks[self.i][1].split()
                self.i += 1
                params[name] = (kind, self.value())
            yield tok[1], args, params

    @staticmethod
    def is_param(s):
        return len(s.split()) == 2

    def value(self):
        tok = self.toks[self.i]
        self.i += 1
        if tok[0] != "[":
            return [tok[1]]
        out = []
        while self.toks[self.i][0] != "]":
            out.append(self.toks[self.i][1])
            self.i += 1
        self.i += 1
        return out


def pbrt_matrix(values):
    """pbrt's `Transform` lists the matrix column by column."""
    m = Matrix([values[0:4], values[4:8], values[8:12], values[12:16]])
    m.transpose()
    return m


def material(params, name):
    kind = params.get("type", ("string", ["diffuse"]))[1][0]
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    if kind == "diffuse":
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        r = params.get("reflectance", ("rgb", [0.5, 0.5, 0.5]))[1]
        bsdf.inputs["Color"].default_value = (*r, 1.0)
        bsdf.inputs["Roughness"].default_value = 0.0
    elif kind == "conductor":
        bsdf = nodes.new("ShaderNodeBsdfMetallic")
        bsdf.fresnel_type = "PHYSICAL_CONDUCTOR"
        bsdf.distribution = "GGX"
        eta, k = params["eta"], params["k"]
        if eta[0] != "rgb" or k[0] != "rgb":
            raise SystemExit(f"material {name}: only rgb eta and k are read")
        bsdf.inputs["IOR"].default_value = eta[1]
        bsdf.inputs["Extinction"].default_value = k[1]
        ur = params.get("uroughness", params.get("roughness", ("float", [0.0])))[1][0]
        vr = params.get("vroughness", params.get("roughness", ("float", [0.0])))[1][0]
        if ur != vr:
            raise SystemExit(f"material {name}: anisotropic roughness is not read")
        if params.get("remaproughness", ("bool", [True]))[1][0] not in (False, "false"):
            raise SystemExit(f"material {name}: remapped roughness is not read")
        bsdf.inputs["Roughness"].default_value = math.sqrt(ur)
    else:
        raise SystemExit(f"material type {kind!r} is not read by this script")
    mat.node_tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def emissive(base, radiance):
    """`base`'s copy that also emits `radiance` from its front face only."""
    mat = base.copy()
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    out = next(n for n in nodes if n.type == "OUTPUT_MATERIAL")
    surface = out.inputs["Surface"].links[0].from_socket
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*radiance, 1.0)
    emission.inputs["Strength"].default_value = 1.0
    black = nodes.new("ShaderNodeEmission")
    black.inputs["Strength"].default_value = 0.0
    geometry = nodes.new("ShaderNodeNewGeometry")
    front_only = nodes.new("ShaderNodeMixShader")
    links.new(geometry.outputs["Backfacing"], front_only.inputs["Fac"])
    links.new(emission.outputs[0], front_only.inputs[1])
    links.new(black.outputs[0], front_only.inputs[2])
    add = nodes.new("ShaderNodeAddShader")
    links.new(surface, add.inputs[0])
    links.new(front_only.outputs[0], add.inputs[1])
    links.new(add.outputs[0], out.inputs["Surface"])
    return mat


def add_mesh(name, verts, faces, normals, mat, world_from_object):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    if normals is not None:
        for poly in mesh.polygons:
            poly.use_smooth = True
        mesh.normals_split_custom_set_from_vertices(normals)
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    obj.matrix_world = world_from_object
    bpy.context.scene.collection.objects.link(obj)


def add_sphere_lamp(name, radius, radiance, mat, world_from_object):
    """A glowing sphere as Cycles' own sphere light (a point light of that radius, seen by the
    camera, without the soft falloff), sampled as pbrt-v4 samples a sphere (by its visible
    cone), which a tessellated emitter would not be. A point light of power P and radius r
    shows a radiance of P ∕ (4π² r²) (measured with Blender 5.3: exact to 1e-7)."""
    loc, _, scale = world_from_object.decompose()
    if max(scale) - min(scale) > 1e-6 * max(scale):
        raise SystemExit("a glowing sphere scaled unevenly is not read by this script")
    bsdf = next(n for n in mat.node_tree.nodes if n.type == "BSDF_DIFFUSE")
    if any(bsdf.inputs["Color"].default_value[:3]):
        raise SystemExit("a glowing sphere that also reflects is not read by this script")
    r = radius * scale[0]
    peak = max(radiance)
    light = bpy.data.lights.new(name, "POINT")
    light.color = [c / peak for c in radiance]
    light.energy = 4 * math.pi ** 2 * r * r * peak
    light.shadow_soft_size = r
    light.use_soft_falloff = False
    obj = bpy.data.objects.new(name, light)
    obj.location = loc
    obj.visible_camera = True
    bpy.context.scene.collection.objects.link(obj)


def uv_sphere(radius, segments=256, rings=128):
    verts, faces = [], []
    for j in range(1, rings):
        theta = math.pi * j / rings
        for i in range(segments):
            phi = 2 * math.pi * i / segments
            verts.append((radius * math.sin(theta) * math.cos(phi),
                          radius * math.sin(theta) * math.sin(phi), radius * math.cos(theta)))
    top, bottom = len(verts), len(verts) + 1
    verts += [(0, 0, radius), (0, 0, -radius)]
    normals = [Vector(v).normalized() for v in verts]
    for j in range(rings - 2):
        for i in range(segments):
            a, b = j * segments + i, j * segments + (i + 1) % segments
            faces.append((a, b, b + segments, a + segments))
    for i in range(segments):
        faces.append((top, (i + 1) % segments, i))
        last = (rings - 2) * segments
        faces.append((bottom, last + i, last + (i + 1) % segments))
    # Each face turned to front outwards (pbrt's sphere shines outwards).
    def outwards(face):
        a, b, c = (Vector(verts[i]) for i in face[:3])
        return face if (b - a).cross(c - a).dot(a + b + c) > 0 else tuple(reversed(face))
    return verts, [outwards(f) for f in faces], normals


def build(path, divide):
    text = open(path).read()
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    settings = {"maxdepth": 5, "fov": 90.0, "res": (1280, 720), "filter": ("gaussian", 1.5)}
    ctm = Matrix.Identity(4)
    camera_from_world = None
    stack = []
    materials = {}
    current = material({}, "default")
    area = None
    count = 0
    for name, args, params in Directives(text):
        if name == "Integrator":
            settings["maxdepth"] = int(params.get("maxdepth", ("integer", [5]))[1][0])
        elif name in ("Transform", "ConcatTransform"):
            m = pbrt_matrix(args[0])
            ctm = m if name == "Transform" else ctm @ m
        elif name == "Translate":
            ctm = ctm @ Matrix.Translation(Vector(args[:3] if len(args) >= 3 else args[0]))
        elif name == "Scale":
            s = args[:3] if len(args) >= 3 else args[0]
            ctm = ctm @ Matrix.Diagonal((*s, 1.0))
        elif name in ("Sampler", "Accelerator", "WorldBegin"):
            if name == "WorldBegin":
                ctm = Matrix.Identity(4)
        elif name == "PixelFilter":
            r = params.get("xradius", ("float", [0.5 if args[0] == "box" else 1.5]))[1][0]
            settings["filter"] = (args[0], r)
        elif name == "Film":
            settings["res"] = (int(params["xresolution"][1][0]), int(params["yresolution"][1][0]))
        elif name == "Camera":
            if args[0] != "perspective":
                raise SystemExit(f"camera {args[0]!r} is not read")
            settings["fov"] = params.get("fov", ("float", [90.0]))[1][0]
            camera_from_world = ctm.copy()
        elif name == "MakeNamedMaterial":
            materials[args[0]] = material(params, args[0])
        elif name == "NamedMaterial":
            current = materials[args[0]]
        elif name == "Material":
            current = material({"type": ("string", [args[0]]), **params}, f"m{count}")
        elif name == "AttributeBegin":
            stack.append((ctm.copy(), current, area))
        elif name == "AttributeEnd":
            ctm, current, area = stack.pop()
        elif name == "AreaLightSource":
            L = params.get("L", ("rgb", [1, 1, 1]))
            if L[0] != "rgb":
                raise SystemExit("only rgb L is read")
            scale = params.get("scale", ("float", [1.0]))[1][0]
            if "twosided" in params:
                raise SystemExit("two-sided lamps are not read")
            area = [c * scale for c in L[1]]
        elif name == "Shape":
            count += 1
            if ctm.to_3x3().determinant() < 0:
                raise SystemExit("a shape under a mirroring transform is not read by this script")
            mat = emissive(current, area) if area else current
            if args[0] == "trianglemesh":
                P = params["P"][1]
                idx = [int(i) for i in params["indices"][1]]
                verts = [tuple(P[i:i + 3]) for i in range(0, len(P), 3)]
                faces = [tuple(idx[i:i + 3]) for i in range(0, len(idx), 3)]
                N = params.get("N")
                normals = None if N is None else [tuple(N[1][i:i + 3]) for i in range(0, len(N[1]), 3)]
                add_mesh(f"shape{count}", verts, faces, normals, mat, ctm)
            elif args[0] == "sphere":
                for cut in ("zmin", "zmax", "phimax"):
                    if cut in params:
                        raise SystemExit(f"a cut sphere ({cut}) is not read")
                radius = params.get("radius", ("float", [1.0]))[1][0]
                if area:
                    add_sphere_lamp(f"shape{count}", radius, area, current, ctm)
                else:
                    verts, faces, normals = uv_sphere(radius)
                    add_mesh(f"shape{count}", verts, faces, normals, mat, ctm)
            else:
                raise SystemExit(f"shape {args[0]!r} is not read by this script")
        else:
            raise SystemExit(f"directive {name} is not read by this script")
    if camera_from_world is None:
        raise SystemExit("no camera")

    cam_data = bpy.data.cameras.new("camera")
    width, height = (max(1, r // divide) for r in settings["res"])
    cam_data.sensor_fit = "HORIZONTAL" if width <= height else "VERTICAL"
    cam_data.angle = math.radians(settings["fov"])
    cam = bpy.data.objects.new("camera", cam_data)
    cam.matrix_world = camera_from_world.inverted() @ Matrix.Diagonal((1.0, 1.0, -1.0, 1.0))
    scene.collection.objects.link(cam)
    scene.camera = cam
    if scene.world is None:
        scene.world = bpy.data.worlds.new("world")
    scene.world.use_nodes = True
    background = scene.world.node_tree.nodes.get("Background")
    if background is not None:
        background.inputs["Strength"].default_value = 0.0

    render = scene.render
    render.engine = "CYCLES"
    render.resolution_x, render.resolution_y = width, height
    render.resolution_percentage = 100
    render.image_settings.file_format = "OPEN_EXR"
    render.image_settings.color_depth = "32"
    render.image_settings.exr_codec = "NONE"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    cycles = scene.cycles
    cycles.device = "CPU"
    bounces = max(0, settings["maxdepth"] - 1)
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = cycles.glossy_bounces = cycles.transmission_bounces = bounces
    cycles.min_light_bounces = 0
    cycles.sample_clamp_direct = cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.caustics_reflective = cycles.caustics_refractive = True
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.use_light_tree = True
    kind, radius = settings["filter"]
    cycles.pixel_filter_type = "BOX" if kind == "box" else "GAUSSIAN"
    cycles.filter_width = 2 * radius
    return width, height


def write_pfm(exr, out, width, height):
    """The EXR Blender wrote as a little-endian colour PFM (both list rows bottom first), the
    format the comparison tools read."""
    import array
    import os

    image = bpy.data.images.load(exr)
    rgba = array.array("f", image.pixels[:])
    rgb = array.array("f", (rgba[i] for i in range(len(rgba)) if i % 4 != 3))
    if sys.byteorder != "little":
        rgb.byteswap()
    with open(out, "wb") as f:
        f.write(f"PF\n{width} {height}\n-1.0\n".encode())
        rgb.tofile(f)
    os.remove(exr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--divide", type=int, default=1)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else None)
    width, height = build(a.scene, a.divide)
    scene = bpy.context.scene
    scene.cycles.samples = a.spp
    scene.cycles.seed = a.seed
    scene.render.threads_mode = "FIXED"
    scene.render.threads = a.threads
    pfm = a.output.endswith(".pfm")
    scene.render.filepath = a.output + ".exr" if pfm else a.output
    start = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - start
    if pfm:
        write_pfm(scene.render.filepath, a.output, width, height)
    print(f"cycles render_s={seconds:.3f} spp={a.spp} size={width}x{height}")


if __name__ == "__main__":
    main()
