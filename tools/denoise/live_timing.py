"""What denoising beside the render costs (docs/performance.md, "Denoising beside the render").

tev: `rayforge render SCENE --renderer path --width W --spp N --display-server` to a viewer that
reads and discards (a TCP sink standing in for tev), ROUNDS times each without and with
--denoise, in turns; the render's time is the summary line's (the passes, up to the last pass's
film: the final image's denoise and the file's writing come after it), and with --denoise the
line after it gives the passes denoised beside the render, their time each, and those skipped.

The page: `rayforge serve SCENE --threads T`, a WebSocket client sending path-traced requests
(`samples` N at width W, and 1-sample previews) without and with `"denoise": true`, in turns;
the time is the `done` message's `millis` (the job from its start to its last PNG sent).

Usage: python3 tools/denoise/live_timing.py RAYFORGE [--scene S] [--width W] [--spp N]
           [--rounds R] [--threads T]
Needs the `websockets` package for the page's part.
"""
import argparse
import json
import re
import socket
import statistics
import subprocess
import tempfile
import threading


def sink():
    """A viewer that accepts connections and reads them to their end; its port."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()

    def serve():
        while True:
            connection, _ = server.accept()
            threading.Thread(target=drain, args=(connection,), daemon=True).start()

    def drain(connection):
        while connection.recv(1 << 16):
            pass

    threading.Thread(target=serve, daemon=True).start()
    return server.getsockname()[1]


def tev(args, port, out):
    rows = {False: [], True: []}
    live = []
    for _ in range(args.rounds):
        for denoise in (False, True):
            command = [
                args.rayforge, "render", args.scene, "-o", f"{out}/t.exr", "--renderer", "path",
                "--width", str(args.width), "--spp", str(args.spp), "--threads", str(args.threads),
                "--display-server", f"127.0.0.1:{port}",
            ] + (["--denoise"] if denoise else [])
            result = subprocess.run(command, capture_output=True, text=True, check=True)
            seconds = float(re.search(r" in ([0-9.]+) s,", result.stderr).group(1))
            rows[denoise].append(seconds)
            found = re.search(
                r"denoised beside the render: (\d+) pass\w* \((\d+) ms each\), (\d+) skipped",
                result.stderr,
            )
            if denoise and found:
                live.append(tuple(int(g) for g in found.groups()))
    print(f"tev, {args.scene} at {args.width} px wide, {args.spp} spp, {args.threads} threads:")
    for denoise in (False, True):
        times = rows[denoise]
        print(
            f"  {'--denoise' if denoise else 'without'}: render {statistics.median(times):.2f} s "
            f"median ({min(times):.2f}-{max(times):.2f}) of {len(times)}"
        )
    for denoised, each, skipped in live:
        print(f"  beside it: {denoised} passes denoised, {each} ms each, {skipped} skipped")


def page(args):
    from websockets.sync.client import connect

    server = subprocess.Popen(
        [args.rayforge, "serve", args.scene, "--port", "0", "--threads", str(args.threads)],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )
    try:
        address = server.stdout.readline().strip()
        port = int(address.rsplit(":", 1)[1].strip("/"))
        with connect(f"ws://127.0.0.1:{port}/ws", max_size=None) as ws:
            def job(request):
                ws.send(json.dumps(request))
                frames = denoised = 0
                while True:
                    message = ws.recv()
                    if isinstance(message, bytes):
                        continue
                    m = json.loads(message)
                    if m["type"] == "frame":
                        frames += 1
                        denoised += bool(m.get("denoised"))
                    elif m["type"] == "error":
                        raise SystemExit(m["message"])
                    elif m["type"] == "done":
                        return m["millis"], frames, denoised

            kinds = {
                "full": {"type": "render", "renderer": "path", "samples": args.spp,
                         "width": args.width},
                "preview": {"type": "render", "renderer": "path", "preview": True,
                            "width": args.width},
            }
            job(kinds["full"])  # reads the scene
            for kind, request in kinds.items():
                times = {False: [], True: []}
                counts = []
                for r in range(args.rounds):
                    for denoise in (False, True):
                        request["yaw"] = r  # a new camera each time, as a drag sends
                        millis, frames, denoised = job(dict(request, denoise=denoise))
                        times[denoise].append(millis)
                        if denoise:
                            counts.append((frames, denoised))
                print(f"page, {kind} ({request}):")
                for denoise in (False, True):
                    t = times[denoise]
                    print(
                        f"  {'denoise' if denoise else 'without'}: {statistics.median(t)} ms "
                        f"median ({min(t)}-{max(t)}) of {len(t)}"
                    )
                print(f"  frames (all, denoised) with denoise: {sorted(set(counts))}")
    finally:
        server.kill()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("rayforge")
    parser.add_argument("--scene", default="scenes/pbr/cornell.yml")
    parser.add_argument("--width", type=int, default=256)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as out:
        tev(args, sink(), out)
    page(args)


if __name__ == "__main__":
    main()
