#!/usr/bin/env bash
# The denoiser's fidelity (docs/fidelity.md, "Denoising"): each of the five reference scenes
# (scenes/pbr/*.yml) path traced at SIZE pixels wide at 4, 16 and 64 samples per pixel with
# --denoise --aovs (the denoised image and the raw one beside it), and once at REF samples as the
# reference; tools/denoise/metrics.py then gives each image's RMSE against the reference (linear
# radiance) and its SSIM (sRGB-encoded, clipped to [0, 1]; scikit-image's structural_similarity),
# the raw image's at 4x the samples beside (4 -> 16, 16 -> 64, 64 -> 256), and prints the table.
#
# Usage: tools/denoise/fidelity.sh [RAYFORGE] [OUT_DIR]
#   SIZE (128), REF (4096), SEED (1) and PYTHON (python3, with numpy and scikit-image) from the
#   environment. Needs OIDN (tools/oidn/install.sh).
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
rayforge="${1:-$repo/target/release/rayforge}"
out="${2:-$repo/target/denoise-fidelity}"
size="${SIZE:-128}"
ref="${REF:-4096}"
seed="${SEED:-1}"
python="${PYTHON:-python3}"
mkdir -p "$out"
for scene in "$repo"/scenes/pbr/*.yml; do
  name="$(basename "$scene" .yml)"
  common=(--renderer path --width "$size" --seed "$seed" --quiet)
  [ -f "$out/$name.ref.pfm" ] ||
    "$rayforge" render "$scene" -o "$out/$name.ref.pfm" "${common[@]}" --spp "$ref"
  for spp in 4 16 64 256; do
    [ -f "$out/$name.$spp.pfm" ] ||
      "$rayforge" render "$scene" -o "$out/$name.$spp.pfm" "${common[@]}" --spp "$spp" --denoise --aovs
  done
done
"$python" "$repo/tools/denoise/metrics.py" "$out"
