#!/usr/bin/env bash
# The figures of docs/distributed.md ("Measured"): one render done by one process and by N
# slices run at once on this machine, and what a slice costs besides its rendering.
#
# Usage: tools/slurm/measure.sh RAYFORGE [SCENE] [RENDER FLAGS…]
#   default: scenes/pbr/cornell.yml --renderer path --width 320 --height 320 --spp 32
# RAYFORGE should be a release build. Every run's wall time is the best of 3 (the machine may
# be shared); CPU is user + system time of all its processes. Needs GNU time (/usr/bin/time).
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
rayforge=$(readlink -f "${1:?usage: measure.sh RAYFORGE [SCENE] [FLAGS…]}")
shift
scene=${1:-$repo/scenes/pbr/cornell.yml}
[ $# -gt 0 ] && shift
flags=("$@")
[ ${#flags[@]} -gt 0 ] || flags=(--renderer path --width 320 --height 320 --spp 32)
work=$(mktemp -d /tmp/rayforge-measure.XXXXXX)
trap 'rm -rf "$work"' EXIT
now() { date +%s%N; }
secs() { printf '%d.%02d' $(($1 / 1000000000)) $(($1 % 1000000000 / 10000000)); }
# GNU time's user + system seconds, summed over the files given.
cpu() { awk '{ s += $1 + $2 } END { printf "%.2f", s }' "$@"; }

echo "rayforge: $rayforge; scene: $scene ${flags[*]}"
echo "machine: $(nproc) cores; load average before: $(cut -d' ' -f1-3 /proc/loadavg)"

best=
one() { # THREADS
  local t0 t
  best=
  for _ in 1 2 3; do
    t0=$(now)
    /usr/bin/time -f '%U %S' -o "$work/time-one" \
      "$rayforge" render "$scene" -o "$work/one.png" "${flags[@]}" --threads "$1" -q
    t=$(($(now) - t0))
    if [ -z "$best" ] || [ "$t" -lt "$best" ]; then best=$t; cp "$work/time-one" "$work/best-one"; fi
  done
  printf '%-34s wall %6s s   cpu %6s s\n' "1 process, $1 thread(s)" "$(secs "$best")" \
    "$(cpu "$work/best-one")"
}

sliced() { # N CUT
  local n=$1 cut=$2 t0 t j
  best=
  for _ in 1 2 3; do
    rm -f "$work"/part-* "$work"/time-*
    t0=$(now)
    for ((j = 0; j < n; j++)); do
      /usr/bin/time -f '%U %S' -o "$work/time-$j" "$rayforge" render "$scene" \
        -o "$work/part-$j.part" --slice "$j/$n" --slice-by "$cut" "${flags[@]}" --threads 1 \
        2>"$work/log-$j" &
    done
    wait
    local t1
    t1=$(now)
    /usr/bin/time -f '%U %S' -o "$work/time-merge" \
      "$rayforge" merge "$work"/part-*.part -o "$work/sliced.png" -q
    t=$(($(now) - t0))
    if [ -z "$best" ] || [ "$t" -lt "$best" ]; then
      best=$t
      merge_ns=$(($(now) - t1))
      rm -rf "$work/tmp-keep"
      mkdir -p "$work/tmp-keep"
      cp "$work"/time-* "$work/tmp-keep/"
    fi
  done
  cmp -s "$work/sliced.png" "$work/one.png" && same="same bytes" || same="differs"
  printf '%-34s wall %6s s   cpu %6s s   (merge %s s; image: %s)\n' \
    "$n slices by $cut, at once, 1 thread" "$(secs "$best")" "$(cpu "$work"/tmp-keep/time-*)" \
    "$(secs "$merge_ns")" "$same"
  rm -rf "$work/tmp-keep"
}

one 1
one 2
sliced 2 rows
sliced 4 rows
sliced 4 samples

# A slice's overhead: its process's wall time against the render time it reports, and a
# re-run over its complete part (the scene read, the index built, the part read: what a
# requeued task costs).
rm -f "$work"/part-*
t0=$(now)
"$rayforge" render "$scene" -o "$work/part-0.part" --slice 0/4 "${flags[@]}" --threads 1 \
  2>"$work/slice.log"
t=$(($(now) - t0))
rendered=$(grep -o 'rendered in [0-9.]* s' "$work/slice.log" | grep -o '[0-9.]*')
t0=$(now)
"$rayforge" render "$scene" -o "$work/part-0.part" --slice 0/4 "${flags[@]}" --threads 1 -q
again=$(($(now) - t0))
echo "slice 0/4 alone, 1 thread: process $(secs "$t") s, of which rendering $rendered s;" \
  "re-run over its complete part: $(secs "$again") s; part: $(stat -c %s "$work/part-0.part") bytes"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
