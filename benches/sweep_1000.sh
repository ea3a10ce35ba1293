#!/usr/bin/env bash
# Issue 11's sweep target, measured (not a timed test): benches/sweep-1000.ron, 1,000 points
# of a 128x128 scene, and the same file cut to 100 points and grown to 4,000, each run once on
# THREADS threads (default 2) by the release binary BIN (default target/release/bumpsim).
# Prints the wall time and the peak RSS (/usr/bin/time -v) of each: the time should stay under
# 60 s at 2 threads for 1,000 points and the memory flat in the number of points. Every file it
# writes is under $TMPDIR (the variants' base config path made absolute).
#
#   benches/sweep_1000.sh [BIN] [THREADS] [POINTS...]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../target/release/bumpsim}"
threads="${2:-2}"
shift $(($# < 2 ? $# : 2))
counts=("${@:-100 1000 4000}")
out="$(mktemp -d "${TMPDIR:-/tmp}/bumpsim-sweep-1000.XXXXXX")"
trap 'rm -rf "$out"' EXIT
base="$(cd "$here/../configs" && pwd)/sgi-teapot.ron"
for n in ${counts[@]}; do
    f="$out/sweep-$n.ron"
    sed -e "s/Random(1000, 7)/Random($n, 7)/" -e "s|\"../configs/sgi-teapot.ron\"|\"$base\"|" \
        "$here/sweep-1000.ron" >"$f"
    /usr/bin/time -v "$bin" sweep "$f" --out "$out/out-$n" --threads "$threads" \
        >"$out/log" 2>"$out/time"
    points=$(grep -o '^[0-9]* of [0-9]* points run' "$out/log")
    wall=$(grep 'Elapsed (wall clock)' "$out/time" | awk '{print $NF}')
    rss=$(grep 'Maximum resident set size' "$out/time" | awk '{print $NF}')
    echo "$points: wall $wall, peak RSS $((rss / 1024)) MiB ($threads threads)"
done
