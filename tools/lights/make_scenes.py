#!/usr/bin/env python3
"""Writes the many-light scenes the light samplers are measured on (docs/performance.md).

    python3 tools/lights/make_scenes.py grid 400 -o scenes/bench/many-lights.yml
    python3 tools/lights/make_scenes.py rooms -o scenes/bench/many-lights-rooms.yml
    python3 tools/lights/make_scenes.py grid 16 -o /tmp/grid-16.yml   # any count

`grid N`: N small square lamps facing down, on a grid of spacing 1 over a grey floor, at
heights and colours that vary over the grid, the camera looking down over them (it sees the
lamps' black backs, so that every pixel's noise is the light sampling's, not the lamps'
edges). `rooms`: a 4 x 4 block of open-topped rooms with doorways, eight lamps hung in each
at random places, their brightness spread over a factor of 1,000 (log-uniform): the
brightest lamps are mostly in other rooms, behind walls.
"""

import argparse
import math

HUES = [(1.0, 0.35, 0.2), (1.0, 0.9, 0.3), (0.3, 1.0, 0.4), (0.25, 0.6, 1.0),
        (0.8, 0.3, 1.0), (1.0, 1.0, 1.0)]


class Random:
    """A small linear congruential generator: the same scene on every machine."""

    def __init__(self, seed):
        self.state = seed

    def next(self):
        self.state = (self.state * 6364136223846793005 + 1442695040888963407) % 2**64
        return (self.state >> 11) / 2**53


def lamp(x, y, z, color, half=0.1):
    r, g, b = color
    return (f"- add: rectangle\n"
            f"  material: {{ type: diffuse, color: [0, 0, 0], "
            f"emission: [{r:.3f}, {g:.3f}, {b:.3f}] }}\n"
            f"  transform: [[scale, {half}, 1, {half}], [rotate-x, 3.1415926536], "
            f"[translate, {x:.3f}, {y:.3f}, {z:.3f}]]\n\n")


def block(x, y, z, sx, sy, sz, grey):
    """A box of half-sizes sx, sy, sz centred at (x, y, z)."""
    return (f"- add: cube\n"
            f"  material: {{ type: diffuse, color: [{grey}, {grey}, {grey}] }}\n"
            f"  transform: [[scale, {sx:.3f}, {sy:.3f}, {sz:.3f}], "
            f"[translate, {x:.3f}, {y:.3f}, {z:.3f}]]\n\n")


def header(title, lines, camera_from, camera_to, fov):
    text = "# " + "=" * 86 + "\n"
    for line in [title] + lines:
        text += f"# {line}\n".replace("# \n", "#\n")
    text += "# " + "=" * 86 + "\n\n"
    text += ("- world:\n    renderer: path\n    background: [0, 0, 0]\n\n"
             "- add: camera\n  width: 160\n  height: 120\n"
             f"  field-of-view-degrees: {fov}\n  handedness: right\n"
             f"  from: {camera_from}\n  to: {camera_to}\n  up: [0, 1, 0]\n\n")
    return text


def grid(n, command, output, spacing=1.0):
    columns = math.ceil(math.sqrt(n))
    rows = math.ceil(n / columns)
    span = max(columns, rows)
    title = (f"{n} small coloured lamps over a floor, each a 0.2 x 0.2 square facing down on a "
             f"{columns} x {rows} grid")
    if spacing != 1.0:
        title += f" (spacing {spacing}: the lamps close together, every point lit by all alike)"
    text = header(title, [
        f"of spacing {spacing:g}, at heights and in colours that vary over the grid: a point on the floor",
        "is lit mostly by the few lamps near it, which the light tree (`light-sampler: bvh`)",
        "finds and picking by power does not. The camera sees the lamps' black backs.",
        f"Written by `{command}`.",
        f"  rayforge render {output} --light-sampler bvh -o bvh.pfm",
    ], f"[0, {0.45 * span + 1:.2f}, {0.7 * span:.2f}]", "[0, 0, 0]", 60)
    text += ("# the floor, facing +y\n- add: rectangle\n"
             "  material: { type: diffuse, color: [0.6, 0.6, 0.6] }\n"
             f"  transform: [[scale, {span / 2 + 1}, 1, {span / 2 + 1}]]\n\n")
    for i in range(n):
        c, r = i % columns, i // columns
        x = (c - (columns - 1) / 2) * spacing
        z = (r - (rows - 1) / 2) * spacing
        height = 0.6 + 0.1 * ((3 * c + 7 * r) % 5)
        hue = HUES[(c + 2 * r) % len(HUES)]
        bright = 8.0 * (1 + (c * 5 + r * 3) % 4)
        text += lamp(x, height, z, tuple(bright * h for h in hue))
    return text


def rooms(command, output):
    random = Random(43)
    size, count, height, wall = 5.0, 4, 3.0, 0.05
    half = size * count / 2
    text = header("Sixteen open-topped rooms (a 4 x 4 block of 5 x 5, walls 3 high, a doorway in "
                  "every inner wall)", [
        "with eight lamps hung in each at random places, facing down, their brightness spread",
        "log-uniformly over a factor of 1,000: picking by power spends most samples on the",
        "bright lamps, mostly behind walls in other rooms; the light tree weighs nearness and",
        "brightness together (it does not know the walls either).",
        f"Written by `{command}`.",
        f"  rayforge render {output} --light-sampler bvh -o bvh.pfm",
    ], "[0, 26, 17]", "[0, 0, 1.5]", 50)
    text += ("# the floor, facing +y\n- add: rectangle\n"
             "  material: { type: diffuse, color: [0.6, 0.6, 0.6] }\n"
             f"  transform: [[scale, {half}, 1, {half}]]\n\n")
    door = 0.6  # half the doorway's width
    for k in range(count + 1):
        at = -half + k * size
        for cell in range(count):
            middle = -half + (cell + 0.5) * size
            inner = 0 < k < count
            pieces = ([(middle - size / 2, middle - door), (middle + door, middle + size / 2)]
                      if inner else [(middle - size / 2, middle + size / 2)])
            for a, b in pieces:
                length = (b - a) / 2 + (wall if not inner else 0)
                centre = (a + b) / 2
                # A wall along x at z = at, and one along z at x = at.
                text += block(centre, height / 2, at, length, height / 2, wall, 0.7)
                text += block(at, height / 2, centre, wall, height / 2, length, 0.7)
    for rx in range(count):
        for rz in range(count):
            for _ in range(8):
                x = -half + rx * size + 0.4 + random.next() * (size - 0.8)
                z = -half + rz * size + 0.4 + random.next() * (size - 0.8)
                y = 1.2 + random.next() * 1.6
                bright = 2.0 * 1000.0 ** random.next()
                hue = HUES[int(random.next() * len(HUES))]
                text += lamp(x, y, z, tuple(bright * h for h in hue))
    return text


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("kind", choices=["grid", "rooms"])
    p.add_argument("count", nargs="?", type=int, default=400, help="grid: how many lamps")
    p.add_argument("--spacing", type=float, default=1.0, help="grid: between lamps")
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args()
    command = f"python3 tools/lights/make_scenes.py {args.kind}"
    command += f" {args.count}" if args.kind == "grid" else ""
    command += f" --spacing {args.spacing}" if args.spacing != 1.0 else ""
    command += f" -o {args.output}"
    if args.kind == "grid":
        text = grid(args.count, command, args.output, args.spacing)
    else:
        text = rooms(command, args.output)
    with open(args.output, "w") as f:
        f.write(text)


if __name__ == "__main__":
    main()
