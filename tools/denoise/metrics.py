"""The table of tools/denoise/fidelity.sh: for each scene in OUT_DIR, RMSE (linear radiance) and
SSIM (sRGB-encoded, clipped to [0, 1], scikit-image's structural_similarity over the three
channels) against NAME.ref.pfm of the denoised image NAME.SPP.pfm and the raw one
NAME.SPP.noisy.pfm at 4, 16 and 64 samples, and of the raw image at 4x the samples."""
import pathlib
import sys

import numpy as np
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
    v = np.clip(linear, 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


def scores(image, reference):
    rmse = float(np.sqrt(np.mean((image - reference) ** 2)))
    ssim = structural_similarity(
        srgb(image), srgb(reference), channel_axis=2, data_range=1.0
    )
    return rmse, float(ssim)


def main():
    out = pathlib.Path(sys.argv[1])
    print("| scene | spp | raw RMSE | denoised RMSE | raw at 4x spp RMSE | raw SSIM | denoised SSIM | raw at 4x spp SSIM |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    for ref_path in sorted(out.glob("*.ref.pfm")):
        name = ref_path.name[: -len(".ref.pfm")]
        reference = read_pfm(ref_path)
        for spp in (4, 16, 64):
            raw = scores(read_pfm(out / f"{name}.{spp}.noisy.pfm"), reference)
            denoised = scores(read_pfm(out / f"{name}.{spp}.pfm"), reference)
            more = scores(read_pfm(out / f"{name}.{spp * 4}.noisy.pfm"), reference)
            print(
                f"| {name} | {spp} | {raw[0]:.4f} | {denoised[0]:.4f} | {more[0]:.4f} "
                f"| {raw[1]:.3f} | {denoised[1]:.3f} | {more[1]:.3f} |"
            )


if __name__ == "__main__":
    main()
