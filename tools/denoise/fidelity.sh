#!/usr/bin/env bash
# The denoiser's fidelity (docs/fidelity.md, "Denoising"): each of the five reference scenes
# (scenes/pbr/*.yml) and of Bitterli's scenes named in BITTERLI (read from
# ../shared/bitterli/NAME/pbrt/scene-v4.pbrt by the pbrt-v4 reader) path traced at SIZE pixels
# wide at 4, 16 and 64 samples per pixel with --denoise --aovs (the denoised image and the raw
# one beside it), at 256 for the raw image of 4x the samples, and once at REF samples as the
# reference; tools/denoise/metrics.py then prints each image's errors against the reference
# (RMSE on linear radiance and on the sRGB-encoded image clipped to [0, 1], SSIM and FLIP on the
# latter) and draws the crops side by side.
#
# Usage: tools/denoise/fidelity.sh [RAYFORGE] [OUT_DIR]
#   SIZE (128), REF (4096), SEED (1), BITTERLI ("cornell-box veach-mis"; empty for none),
#   SHARED (../shared beside the checkout) and PYTHON (python3, with numpy, scikit-image,
#   pillow and flip-evaluator) from the environment. Needs OIDN (tools/oidn/install.sh).
set -euo pipefail
repo="$(cd "$(dirname "$0")/../.." && pwd)"
rayforge="${1:-$repo/target/release/rayforge}"
out="${2:-$repo/target/denoise-fidelity}"
size="${SIZE:-128}"
ref="${REF:-4096}"
seed="${SEED:-1}"
bitterli="${BITTERLI-cornell-box veach-mis}"
shared="${SHARED:-$repo/../shared}"
python="${PYTHON:-python3}"
mkdir -p "$out"
scenes=("$repo"/scenes/pbr/*.yml)
for name in $bitterli; do
  scenes+=("$shared/bitterli/$name/pbrt/scene-v4.pbrt")
done
for scene in "${scenes[@]}"; do
  case "$scene" in
    *.pbrt) name="$(basename "$(dirname "$(dirname "$scene")")")" ;;
    *) name="$(basename "$scene" .yml)" ;;
  esac
  common=(--renderer path --width "$size" --seed "$seed" --quiet)
  [ -f "$out/$name.ref.pfm" ] ||
    "$rayforge" render "$scene" -o "$out/$name.ref.pfm" "${common[@]}" --spp "$ref"
  for spp in 4 16 64 256; do
    [ -f "$out/$name.$spp.pfm" ] ||
      "$rayforge" render "$scene" -o "$out/$name.$spp.pfm" "${common[@]}" --spp "$spp" --denoise --aovs
  done
done
"$python" "$repo/tools/denoise/metrics.py" "$out"
