"""The table and the crops of tools/denoise/fidelity.sh. For each scene in OUT_DIR, against
NAME.ref.pfm: the denoised image NAME.SPP.pfm and the raw one NAME.SPP.noisy.pfm at 4, 16 and
64 samples, and the raw image at 4x the samples, each scored by

- RMSE on linear radiance (ruled by the brightest pixels: a lamp far above 1);
- RMSE on the sRGB-encoded image clipped to [0, 1] (what a PNG shows);
- SSIM on the same (scikit-image's structural_similarity over the three channels, data range 1);
- FLIP on the same (NVIDIA's LDR-FLIP, the flip-evaluator package, at its default 67 pixels per
  degree; the mean of its error map, 0 identical, 1 most different).

It prints the Markdown table and writes OUT_DIR/crops.png: for each scene but the two furnaces
(flat white, nothing to see) a crop of the reference, the raw image at 16 and 64 samples, and the denoised one at 4 and 16, side by side,
each enlarged 3x by nearest neighbour so that the noise shows as pixels.
"""
import pathlib
import sys

import flip_evaluator as flip
import numpy as np
from PIL import Image, ImageDraw
from skimage.metrics import structural_similarity


def read_pfm(path):
    """A PFM's pixels, rows from the top, as float64 (height, width, 3)."""
    data = path.read_bytes()
    lines, at = [], 0
    while len(lines) < 3:
        end = data.index(b"\n", at)
        lines.append(data[at:end].decode())
        at = end + 1
    width, height = map(int, lines[1].split())
    order = "<" if float(lines[2]) < 0 else ">"
    pixels = np.frombuffer(data[at:], dtype=order + "f4", count=width * height * 3)
    return pixels.reshape(height, width, 3)[::-1].astype(np.float64)


def srgb(linear):
    """Linear radiance clipped to [0, 1] and sRGB-encoded, as rayforge writes a PNG."""
    v = np.clip(linear, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def scores(image, reference):
    """(linear RMSE, sRGB RMSE, SSIM, FLIP) of `image` against `reference`."""
    rmse = float(np.sqrt(np.mean((image - reference) ** 2)))
    shown, shown_ref = srgb(image), srgb(reference)
    srgb_rmse = float(np.sqrt(np.mean((shown - shown_ref) ** 2)))
    ssim = structural_similarity(shown, shown_ref, channel_axis=2, data_range=1.0)
    _, mean_flip, _ = flip.evaluate(
        shown_ref.astype(np.float32), shown.astype(np.float32), "LDR", applyMagma=False
    )
    return rmse, srgb_rmse, float(ssim), float(mean_flip)


def crop_box(reference):
    """A square of a third of the image's smaller side about its busiest part: the block of
    the reference with the most local contrast (edges, highlights), so that the crop shows
    what a denoiser smooths."""
    h, w, _ = reference.shape
    side = max(8, min(h, w) // 3)
    shown = srgb(reference).mean(axis=2)
    gx = np.abs(np.diff(shown, axis=1))[:-1, :]
    gy = np.abs(np.diff(shown, axis=0))[:, :-1]
    edges = gx + gy
    best, at = -1.0, (0, 0)
    step = max(1, side // 4)
    for y in range(0, h - side, step):
        for x in range(0, w - side, step):
            score = float(edges[y : y + side - 1, x : x + side - 1].sum())
            if score > best:
                best, at = score, (y, x)
    return at[0], at[1], side


def crops(out, names):
    """Writes OUT/crops.png: a row a scene, columns as the module doc says."""
    columns = [
        ("reference", "ref.pfm"),
        ("raw 16 spp", "16.noisy.pfm"),
        ("raw 64 spp", "64.noisy.pfm"),
        ("denoised 4 spp", "4.pfm"),
        ("denoised 16 spp", "16.pfm"),
    ]
    scale, label, pad = 3, 16, 4
    rows = []
    for name in names:
        reference = read_pfm(out / f"{name}.ref.pfm")
        y, x, side = crop_box(reference)
        tiles = []
        for _, suffix in columns:
            image = read_pfm(out / f"{name}.{suffix}")[y : y + side, x : x + side]
            tile = Image.fromarray((srgb(image) * 255 + 0.5).astype(np.uint8))
            tiles.append(tile.resize((side * scale, side * scale), Image.NEAREST))
        rows.append((name, tiles))
    tile = max(t[0].width for _, t in rows)
    width = len(columns) * (tile + pad) + pad
    height = label + len(rows) * (tile + label + pad) + pad
    sheet = Image.new("RGB", (width, height), (255, 255, 255))
    draw = ImageDraw.Draw(sheet)
    for c, (title, _) in enumerate(columns):
        draw.text((pad + c * (tile + pad), 1), title, fill=(0, 0, 0))
    for r, (name, tiles) in enumerate(rows):
        top = label + r * (tile + label + pad)
        draw.text((pad, top + 1), name, fill=(0, 0, 0))
        for c, t in enumerate(tiles):
            sheet.paste(t, (pad + c * (tile + pad), top + label))
    sheet.save(out / "crops.png", optimize=True)


def main():
    out = pathlib.Path(sys.argv[1])
    print(
        "| scene | spp | RMSE linear: raw / denoised / raw 4x | RMSE sRGB: raw / denoised / raw 4x "
        "| SSIM: raw / denoised / raw 4x | FLIP: raw / denoised / raw 4x |"
    )
    print("|---|---:|---|---|---|---|")
    names = []
    for ref_path in sorted(out.glob("*.ref.pfm")):
        name = ref_path.name[: -len(".ref.pfm")]
        names.append(name)
        reference = read_pfm(ref_path)
        for spp in (4, 16, 64):
            raw = scores(read_pfm(out / f"{name}.{spp}.noisy.pfm"), reference)
            denoised = scores(read_pfm(out / f"{name}.{spp}.pfm"), reference)
            more = scores(read_pfm(out / f"{name}.{spp * 4}.noisy.pfm"), reference)
            cells = []
            for i, digits in enumerate((4, 4, 3, 3)):
                triple = (raw[i], denoised[i], more[i])
                best = min(triple) if i != 2 else max(triple)
                cells.append(
                    " / ".join(
                        f"**{v:.{digits}f}**" if v == best else f"{v:.{digits}f}" for v in triple
                    )
                )
            print(f"| {name} | {spp} | " + " | ".join(cells) + " |")
    crops(out, [n for n in names if not n.startswith("furnace")])


if __name__ == "__main__":
    main()
