#!/usr/bin/env bash
# Coverage-guided fuzzing of one rayforge-fuzz target with AFL++ (through cargo-afl, on the
# stable toolchain), from the same seed corpus as the stable fuzzer.
#
#   tools/fuzz/afl.sh TARGET SECONDS        TARGET: scene, obj, image, gltf, ply, part or page
#
# Needs cargo-afl (`cargo install cargo-afl`; it builds AFL++ on first use, or run
# `cargo afl config --build`). It builds the harness in fuzz-afl/ with `cargo afl build
# --release`, writes the target's seeds with `rayforge-fuzz --write-seeds`, runs one
# `cargo afl fuzz` for SECONDS and prints a summary of its fuzzer_stats. Everything goes under
# ${CARGO_TARGET_DIR:-target}/afl/: the instrumented build in build/, each run in
# runs/TARGET-DATE/ (seeds/, and AFL's out/ with default/crashes and default/hangs). Replay a
# finding with the stable fuzzer:
#
#   cargo run --release -p rayforge-fuzz -- --target TARGET --replay FILE
#
# One fuzzer process, not bound to a core (AFL_NO_AFFINITY), rendering on one thread
# (RAYON_NUM_THREADS=1): on a shared machine run it under `nice -n 10`. AFL's timeout is 10 s
# by default (AFL_TIMEOUT_MS), the stable fuzzer's, so a hang means the same for both.
set -euo pipefail

usage() {
    sed -n '2,/^set /p' "$0" | sed '$d; s/^# \{0,1\}//' >&2
    exit 2
}
[[ $# -eq 2 ]] || usage
target=$1
seconds=$2
case $target in scene | obj | image | gltf | ply | part | page) ;; *) usage ;; esac
[[ $seconds =~ ^[1-9][0-9]*$ ]] || usage

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
base=${CARGO_TARGET_DIR:-$root/target}/afl
run=$base/runs/$target-$(date +%Y%m%d-%H%M%S)

# The instrumented build has a directory of its own: other flags than the ordinary build, which
# would otherwise be rebuilt after every switch between the two.
echo "building the harness (cargo afl build --release) in $base/build" >&2
CARGO_TARGET_DIR=$base/build cargo afl build --release --quiet \
    --manifest-path "$root/fuzz-afl/Cargo.toml" --bin "$target"

(cd "$root" && cargo run --release --quiet -p rayforge-fuzz -- \
    --target "$target" --write-seeds "$run/seeds")

echo "fuzzing $target for $seconds s; output in $run/out" >&2
export AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 AFL_NO_UI=1 AFL_NO_AFFINITY=1
export RAYON_NUM_THREADS=1
cargo afl fuzz -i "$run/seeds" -o "$run/out" -V "$seconds" -t "${AFL_TIMEOUT_MS:-10000}" \
    -- "$base/build/release/$target" > "$run/afl.log" 2>&1 || {
    tail -n 30 "$run/afl.log" >&2
    exit 1
}

stats=$run/out/default/fuzzer_stats
stat() { sed -n "s/^$1 *: //p" "$stats"; }
echo "$target: $(stat execs_done) inputs in $(stat run_time) s ($(stat execs_per_sec)/s)," \
    "edges $(stat edges_found)/$(stat total_edges) ($(stat bitmap_cvg)), corpus $(stat corpus_count)," \
    "crashes $(stat saved_crashes), hangs $(stat saved_hangs)"
echo "stats: $stats; log: $run/afl.log"
for kind in crashes hangs; do
    for f in "$run/out/default/$kind"/id:*; do
        [[ -e $f ]] && echo "$kind: $f"
    done
done
exit 0
