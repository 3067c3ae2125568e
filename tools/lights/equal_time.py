#!/usr/bin/env python3
"""The light samplers of the path tracer at equal time: RMSE against a reference.

    # a reference: the mean of BATCHES renders of SPP samples, each its own seed
    python3 tools/lights/equal_time.py reference scenes/bench/many-lights.yml \\
        --rayforge target/release/rayforge --sampler bvh --spp 4096 --batches 4 \\
        -o /tmp/many-lights.ref.pfm
    # without a reference: each sampler's error from the spread of its ROUNDS renders
    python3 tools/lights/equal_time.py spread /tmp/grid-16.yml --samplers power,bvh --rounds 6
    # the samplers in turns, ROUNDS rounds, each render its own seed
    python3 tools/lights/equal_time.py compare scenes/bench/many-lights.yml \\
        --rayforge target/release/rayforge --reference /tmp/many-lights.ref.pfm \\
        --samplers uniform,power,bvh --spp 64 --rounds 5 --threads 2

`compare` renders every sampler once a round, the samplers taking turns, each render a
process of its own timed by its CPU time (user + system, from the operating system's
accounting of the finished process: a shared machine's other work moves it less than the
wall clock). Each render's RMSE over every pixel and channel is scaled to the budget, the
CPU time of the `--budget` sampler's render in the same round, by sqrt(time / budget)
(error falls as one over the square root of the samples); the table gives each sampler's
median over the rounds and its ratio to the budget sampler's error (above 1: the budget
sampler is closer to the reference in the same time).

`spread` needs no reference: both samplers are unbiased, so a render's mean squared error
is its variance, estimated per pixel and channel from the spread of the ROUNDS renders (each
its own seed) and averaged over the image; the ratio is of the RMSE at equal time,
sqrt(variance x median CPU time), the budget sampler's over each one's inverted as above.

Only the Python standard library is needed.
"""

import argparse
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time


def read_pfm(path):
    """(width, height, values) of a colour PFM, values a flat list of floats."""
    with open(path, "rb") as f:
        data = f.read()
    tokens, pos = [], 0
    while len(tokens) < 4:
        while data[pos : pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos : pos + 1].isspace():
            pos += 1
        tokens.append(data[start:pos].decode("ascii"))
    pos += 1
    if tokens[0] != "PF":
        raise SystemExit(f"{path}: not a colour PFM")
    w, h, scale = int(tokens[1]), int(tokens[2]), float(tokens[3])
    n = w * h * 3
    order = "<" if scale < 0 else ">"
    return w, h, list(struct.unpack_from(f"{order}{n}f", data, pos))


def write_pfm(path, w, h, values):
    with open(path, "wb") as f:
        f.write(f"PF\n{w} {h}\n-1.0\n".encode("ascii"))
        f.write(struct.pack(f"<{len(values)}f", *values))


def rmse(image, reference):
    if image[:2] != reference[:2]:
        raise SystemExit("the image and the reference differ in size")
    total, n = 0.0, 0
    for a, b in zip(image[2], reference[2]):
        if a == a and b == b and abs(a) != float("inf") and abs(b) != float("inf"):
            total += (a - b) ** 2
            n += 1
    return (total / n) ** 0.5


def render(args, sampler, spp, seed, out):
    """Renders once; the CPU seconds (user + system) and wall seconds it took."""
    command = [
        args.rayforge, "render", args.scene, "-o", out, "--quiet",
        "--light-sampler", sampler, "--spp", str(spp), "--seed", str(seed),
        "--threads", str(args.threads),
    ] + args.extra
    start = time.monotonic()
    child = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.monotonic() - start
    err = child.stderr.read().decode()
    child.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        raise SystemExit(f"{' '.join(command)} failed:\n{err}")
    return usage.ru_utime + usage.ru_stime, wall


def reference(args):
    mean = None
    with tempfile.TemporaryDirectory() as tmp:
        for batch in range(args.batches):
            out = os.path.join(tmp, "batch.pfm")
            cpu, wall = render(args, args.sampler, args.spp, 1000 + batch, out)
            w, h, values = read_pfm(out)
            mean = values if mean is None else [m + v for m, v in zip(mean, values)]
            print(f"batch {batch}: {cpu:.1f} s CPU, {wall:.1f} s wall", file=sys.stderr)
    write_pfm(args.output, w, h, [m / args.batches for m in mean])


def compare(args):
    samplers = args.samplers.split(",")
    budget = args.budget or samplers[0]
    ref = read_pfm(args.reference)
    rows = {s: [] for s in samplers}  # per round: (cpu, wall, rmse)
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            for s in samplers:
                out = os.path.join(tmp, f"{s}.pfm")
                cpu, wall = render(args, s, args.spp, r, out)
                e = rmse(read_pfm(out), ref)
                rows[s].append((cpu, wall, e))
                print(f"round {r} {s}: {cpu:.2f} s CPU, {wall:.2f} s wall, RMSE {e:.5g}",
                      file=sys.stderr)
    print(f"| sampler | CPU s ({args.spp} spp) | RMSE | RMSE at {budget}'s time "
          f"| ÷ {budget}'s | efficiency ÷ {budget}'s |")
    print("|---|---|---|---|---|---|")
    base = rows[budget]
    for s in samplers:
        scaled = [e * (cpu / b[0]) ** 0.5 for (cpu, _, e), b in zip(rows[s], base)]
        ratio = [x / b[2] for x, b in zip(scaled, base)]
        cpu = statistics.median(c for c, _, _ in rows[s])
        e = statistics.median(x for _, _, x in rows[s])
        r = statistics.median(ratio)
        print(f"| {s} | {cpu:.2f} | {e:.4g} | {statistics.median(scaled):.4g} | "
              f"{r:.2f}× | {1 / (r * r):.2f}× |")


def spread(args):
    samplers = args.samplers.split(",")
    budget = args.budget or samplers[0]
    images = {s: [] for s in samplers}
    times = {s: [] for s in samplers}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(args.rounds):
            for s in samplers:
                out = os.path.join(tmp, f"{s}.pfm")
                cpu, _ = render(args, s, args.spp, r, out)
                images[s].append(read_pfm(out)[2])
                times[s].append(cpu)
    cost = {}
    for s in samplers:
        n = len(images[s])
        total = 0.0
        for values in zip(*images[s]):
            mean = sum(values) / n
            total += sum((v - mean) ** 2 for v in values) / (n - 1)
        variance = total / len(images[s][0])
        cost[s] = (variance, statistics.median(times[s]))
    print(f"| sampler | CPU s ({args.spp} spp) | RMSE of one render | RMSE at equal time ÷ {budget}'s |")
    print("|---|---|---|---|")
    vb, tb = cost[budget]
    for s in samplers:
        v, t = cost[s]
        print(f"| {s} | {t:.2f} | {v ** 0.5:.4g} | {((v * t) / (vb * tb)) ** 0.5:.2f}× |")


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("mode", choices=["reference", "compare", "spread"])
    p.add_argument("scene")
    p.add_argument("--rayforge", default="target/release/rayforge")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--sampler", default="bvh", help="reference: the light sampler")
    p.add_argument("--batches", type=int, default=4, help="reference: renders averaged")
    p.add_argument("-o", "--output", help="reference: the PFM to write")
    p.add_argument("--reference", help="compare: the reference PFM")
    p.add_argument("--samplers", default="power,bvh,uniform")
    p.add_argument("--budget", help="compare: whose time is the budget [the first sampler]")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("extra", nargs="*", help="more render flags, after --")
    args = p.parse_args()
    {"reference": reference, "compare": compare, "spread": spread}[args.mode](args)


if __name__ == "__main__":
    main()
