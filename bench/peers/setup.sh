#!/usr/bin/env bash
# Installs and builds the peers that `rayforge bench` compares against, on Debian bookworm:
#
#   POV-Ray 3.7     Debian's `povray`, linked as bench/peers/build/povray
#   Embree 3        Debian's `libembree-dev`; our harnesses (bench/peers/embree/primary.c and
#                   instances.c) are compiled to bench/peers/build/embree_primary and
#                   embree_instances
#   raytracer_rs    richard-dennehy/raytracer_rs, built OUTSIDE this repository from a checkout
#                   (or a bare git directory) given as the first argument or $RAYTRACER_RS;
#                   its example binaries are copied to bench/peers/build/raytracer_rs-{cover,dragons}
#   llvmpipe        Mesa's software OpenGL through Debian's `libosmesa6-dev`; our harness
#                   (bench/peers/llvmpipe/frame.c) is compiled to bench/peers/build/llvmpipe_frame
#   Don Cross's     cosinekitty/raytrace (Fundamentals of Ray Tracing), built OUTSIDE this
#   program         repository, unmodified, from a checkout (or a bare git directory) given as
#                   $CROSS_RAYTRACE, with its own build line (g++ -O3 *.cpp ../lodepng/lodepng.cpp);
#                   the binary is copied to bench/peers/build/cross-raytrace
#
# Usage:
#   [CROSS_RAYTRACE=CHECKOUT] bench/peers/setup.sh [RAYTRACER_RS_CHECKOUT]
#
# `rayforge bench` looks for every peer in bench/peers/build/ (or --peers DIR) and reports a
# peer that is missing as skipped, so any step below may be left out. Set SKIP_APT=1 to skip the
# apt-get step (the packages already installed, or no root).
#
# raytracer_rs is never copied into this repository: it is exported (git archive) to
# ${RAYTRACER_RS_BUILD:-$HOME/.cache/rayforge-peers/raytracer_rs} and built there with its own
# Cargo.lock and release profile (LTO, as its authors set it). One change is made to that copy,
# and only to an example:
#
#   examples/dragons/main.rs renders bounding-boxes.yml at 7680×4320 with Samples::grid(4) and
#   scales the result down to 1920×1080 (the README's image). We render 1920×1080 directly: the
#   line `scene.override_resolution(7680, 4320);` becomes `scene.override_resolution(1920, 1080);`
#   and the down-scaling `image::imageops::resize(&original, 1920, 1080, FilterType::Gaussian)`
#   becomes `original` (a resize to the same size would only add time that is not rendering).
#   Samples::grid(4) is kept: 4 rays per pixel at the corners of a 4×4 grid, and the 12 others
#   where those 4 disagree; rayforge renders the same scene with --spp 16, the most it can take.
#
# The cover example already renders cover.yml at 1080×1080 with Samples::single() and is built
# unchanged.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
build="$here/build"
mkdir -p "$build"

step() { printf '\n== %s\n' "$*"; }

# --- Debian packages -------------------------------------------------------------------------
if [[ "${SKIP_APT:-0}" != 1 ]]; then
    step "installing povray, libembree-dev and a C compiler (apt-get)"
    sudo_cmd=()
    if [[ $(id -u) != 0 ]]; then sudo_cmd=(sudo); fi
    "${sudo_cmd[@]}" apt-get update -qq
    DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq \
        povray libembree-dev libosmesa6-dev gcc git pkg-config >/dev/null
fi

# --- POV-Ray ---------------------------------------------------------------------------------
if command -v povray >/dev/null; then
    step "POV-Ray: $(command -v povray)"
    ln -sf "$(command -v povray)" "$build/povray"
else
    echo "povray not found: the POV-Ray comparisons will be skipped" >&2
fi

# --- Embree harness --------------------------------------------------------------------------
step "building the Embree harness"
# -O2 as Debian builds its own packages; the kernels themselves are Embree's (its ISA dispatch
# picks the widest SIMD this CPU has at run time), so the harness's flags hardly matter.
gcc -O2 -std=c11 -Wall -Wextra -o "$build/embree_primary" "$here/embree/primary.c" \
    -lembree3 -lpthread -lm
echo "built $build/embree_primary"
# What many instances of one mesh cost Embree (docs/performance.md, "Many instances").
gcc -O2 -std=c11 -Wall -Wextra -o "$build/embree_instances" "$here/embree/instances.c" \
    -lembree3 -lm
echo "built $build/embree_instances"

# --- llvmpipe harness ------------------------------------------------------------------------
# Mesa's llvmpipe through OSMesa (Debian's libosmesa6-dev), for `rayforge bench raster`.
if [[ -f /usr/include/GL/osmesa.h ]]; then
    step "building the llvmpipe harness"
    gcc -O2 -o "$build/llvmpipe_frame" "$here/llvmpipe/frame.c" -lOSMesa -lm
    echo "built $build/llvmpipe_frame"
else
    echo "GL/osmesa.h not found (libosmesa6-dev): the llvmpipe comparison will be skipped" >&2
fi

# --- Don Cross's program --------------------------------------------------------------------
if [[ -n "${CROSS_RAYTRACE:-}" ]]; then
    cross_dest="${CROSS_RAYTRACE_BUILD:-$HOME/.cache/rayforge-peers/cross-raytrace}"
    step "exporting Don Cross's program from $CROSS_RAYTRACE to $cross_dest"
    cross_gitdir="$(git -C "$CROSS_RAYTRACE" rev-parse --absolute-git-dir)"
    rm -rf "$cross_dest"
    mkdir -p "$cross_dest"
    git --git-dir="$cross_gitdir" archive HEAD | tar -x -C "$cross_dest"
    echo "cosinekitty/raytrace at commit $(git --git-dir="$cross_gitdir" rev-parse HEAD)"
    step "building it with its own build line (raytrace/build: g++ -O3)"
    (cd "$cross_dest/raytrace" && g++ -o raytrace -O3 ./*.cpp ../lodepng/lodepng.cpp)
    cp "$cross_dest/raytrace/raytrace" "$build/cross-raytrace"
    echo "built $build/cross-raytrace"
else
    echo "no CROSS_RAYTRACE checkout given: the comparison with Don Cross's program will be skipped" >&2
fi

# --- raytracer_rs ----------------------------------------------------------------------------
source_dir="${1:-${RAYTRACER_RS:-}}"
if [[ -z "$source_dir" ]]; then
    echo "no raytracer_rs checkout given (argument or \$RAYTRACER_RS): its comparisons will be skipped" >&2
    exit 0
fi
dest="${RAYTRACER_RS_BUILD:-$HOME/.cache/rayforge-peers/raytracer_rs}"
step "exporting raytracer_rs from $source_dir to $dest"
# A work tree or a bare repository both work: git finds the repository either way.
if git -C "$source_dir" rev-parse --is-bare-repository >/dev/null 2>&1; then
    gitdir="$(git -C "$source_dir" rev-parse --absolute-git-dir)"
else
    echo "not a git repository: $source_dir" >&2
    exit 1
fi
rm -rf "$dest"
mkdir -p "$dest"
# File by file rather than `git archive`: a mirror may lack its largest blobs (the orrery
# example's 8k image), which neither example built here needs; those are named and skipped.
git --git-dir="$gitdir" ls-tree -r -z HEAD | while IFS= read -r -d '' entry; do
    meta="${entry%%$'\t'*}"
    path="${entry#*$'\t'}"
    read -r mode kind object <<<"$meta"
    [[ "$kind" == blob ]] || continue
    if ! git --git-dir="$gitdir" cat-file -e "$object" 2>/dev/null; then
        echo "  skipped (not in this copy of the repository): $path"
        continue
    fi
    mkdir -p "$dest/$(dirname "$path")"
    git --git-dir="$gitdir" cat-file blob "$object" >"$dest/$path"
    if [[ "$mode" == 100755 ]]; then chmod +x "$dest/$path"; fi
done
echo "raytracer_rs at commit $(git --git-dir="$gitdir" rev-parse HEAD)"

step "patching examples/dragons/main.rs: render 1920×1080 directly (see the header of this script)"
dragons="$dest/examples/dragons/main.rs"
grep -q 'scene.override_resolution(7680, 4320);' "$dragons" || {
    echo "unexpected examples/dragons/main.rs (the patch no longer applies)" >&2
    exit 1
}
sed -i \
    -e 's/scene.override_resolution(7680, 4320);/scene.override_resolution(1920, 1080);/' \
    -e 's/image::imageops::resize(&original, 1920, 1080, FilterType::Gaussian)/original/' \
    "$dragons"

step "building raytracer_rs (cargo build --release --example cover --example dragons)"
(cd "$dest" && cargo build --release --example cover --example dragons)
cp "$dest/target/release/examples/cover" "$build/raytracer_rs-cover"
cp "$dest/target/release/examples/dragons" "$build/raytracer_rs-dragons"
echo "built $build/raytracer_rs-cover and $build/raytracer_rs-dragons"
