#!/usr/bin/env bash
# Installs Debian's peers that `rayforge bench` compares against and builds our own harnesses
# of them, on Debian bookworm:
#
#   POV-Ray 3.7     Debian's `povray`, linked as bench/peers/build/povray
#   Embree 3        Debian's `libembree-dev`; our harnesses (bench/peers/embree/primary.c and
#                   instances.c) are compiled to bench/peers/build/embree_primary and
#                   embree_instances
#   llvmpipe        Mesa's software OpenGL through Debian's `libosmesa6-dev`; our harness
#                   (bench/peers/llvmpipe/frame.c) is compiled to bench/peers/build/llvmpipe_frame
#
# Usage:
#   bench/peers/setup.sh
#
# `rayforge bench` looks for every peer in bench/peers/build/ (or --peers DIR) and reports a
# peer that is missing as skipped, so any step below may be left out. Set SKIP_APT=1 to skip the
# apt-get step (the packages already installed, or no root).
#
# Nothing here fetches or builds another project's program. The bench also times peers that
# are not Debian's (raytracer_rs, Don Cross's program) when given a binary you built yourself:
#   rayforge bench scenes --peer raytracer_rs-cover=FILE --peer raytracer_rs-dragons=FILE
#   rayforge bench cross --peer cross-raytrace=FILE
# (`rayforge bench --help` says what each binary must render; docs/performance.md, "Peers").
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
        povray libembree-dev libosmesa6-dev gcc pkg-config >/dev/null
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
