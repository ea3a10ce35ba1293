#!/usr/bin/env bash
# Issue 11's sweep target, measured (not a timed test): benches/sweep-1000.ron, 1,000 points
# of a 128x128 scene, and the same file cut to 100 points, each run once on THREADS threads
# (default 2) by the release binary BIN (default target/release/bumpsim). Prints the wall time
# and the peak RSS (/usr/bin/time -v) of each: the time should stay under 60 s at 2 threads
# and the memory flat in the number of points.
#
#   benches/sweep_1000.sh [BIN] [THREADS]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../target/release/bumpsim}"
threads="${2:-2}"
out="${TMPDIR:-/tmp}/bumpsim-sweep-1000.$$"
trap 'rm -rf "$out"' EXIT
mkdir -p "$out"
sed 's/Random(1000, 7)/Random(100, 7)/' "$here/sweep-1000.ron" >"$here/.sweep-100.ron"
trap 'rm -rf "$out" "$here/.sweep-100.ron"' EXIT
for f in "$here/.sweep-100.ron" "$here/sweep-1000.ron"; do
    /usr/bin/time -v "$bin" sweep "$f" --out "$out/$(basename "$f" .ron)" --threads "$threads" \
        >"$out/log" 2>"$out/time"
    points=$(grep -o '^[0-9]* of [0-9]* points run' "$out/log")
    wall=$(grep 'Elapsed (wall clock)' "$out/time" | awk '{print $NF}')
    rss=$(grep 'Maximum resident set size' "$out/time" | awk '{print $NF}')
    echo "$points: wall $wall, peak RSS $((rss / 1024)) MiB ($threads threads)"
done
