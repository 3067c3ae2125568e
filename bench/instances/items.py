#!/usr/bin/env python3
"""Writes dragons-items.yml: the 100,000 dragons of docs/performance.md ("Many instances") as
one `add: obj` item each, every one with its own transform and colour (about 19 MB): the way a
scene places many instances without `add: array`. Run it here; dragon.obj goes beside it."""
import random

random.seed(1)
n, side, spacing = 100_000, 317, 3.03
items = [
    "- add: camera\n  width: 960\n  height: 540\n  field-of-view: 0.8\n"
    "  from: [0, 120, -400]\n  to: [0, 0, 0]\n  up: [0, 1, 0]\n",
    "- add: light\n  at: [-200, 400, -300]\n  intensity: [1, 1, 1]\n",
    "- add: plane\n  material:\n    color: [0.5, 0.5, 0.5]\n",
]
for i in range(n):
    x, z = (i % side - side / 2) * spacing, (i // side - side / 2) * spacing
    r, g, b = (random.random() for _ in range(3))
    items.append(
        f"- add: obj\n  file: dragon.obj\n  transform:\n"
        f"    - [rotate-y, {random.random() * 6.28:.4f}]\n    - [scale, 0.81, 0.81, 0.81]\n"
        f"    - [translate, {x:.3f}, 0, {z:.3f}]\n"
        f"  material:\n    color: [{r:.3f}, {g:.3f}, {b:.3f}]\n"
    )
with open("dragons-items.yml", "w") as f:
    f.write("".join(items))
