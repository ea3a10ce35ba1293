#!/usr/bin/env bash
# Whole-run figures of a render (README, "Whole-run speed and memory"): not a cargo bench,
# a measurement of the release binary as a user runs it.
#
#   benches/whole_run.sh speed OLD_BIN NEW_BIN [ROUNDS] [CONFIG]   end to end (sgi-teapot)
#   benches/whole_run.sh memory BIN [CONFIG] [SIZE]       peak RSS per pixel at SIZE x SIZE
#
# speed: ROUNDS rounds (default 20) of configs/CONFIG.ron, each runs OLD then NEW, or NEW then OLD on odd rounds
# (interleaved, so both see the same machine), and prints the median wall time of each and
# the median of the per-round ratios OLD / NEW.
# memory: B/px = (peak RSS at SIZE x SIZE - peak RSS at 64x64) / SIZE^2, the peak RSS from
# /usr/bin/time -v (Maximum resident set size): what the image adds to the fixed cost.
set -euo pipefail
cfg_dir="$(cd "$(dirname "$0")/.." && pwd)/configs"
out="${TMPDIR:-/tmp}/bumpsim-whole-run.$$"
trap 'rm -rf "$out"' EXIT

wall() { # BIN ARGS... -> seconds
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
}

median() { sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2] + v[NR/2+1]) / 2}'; }

case "${1:-}" in
speed)
    old="$2" new="$3" rounds="${4:-20}" cfg="${5:-sgi-teapot}"
    args=(render "$cfg_dir/$cfg.ron" --out "$out")
    : >"$out.old"; : >"$out.new"; : >"$out.ratio"
    for ((i = 0; i < rounds; i++)); do
        if ((i % 2 == 0)); then
            a=$(wall "$old" "${args[@]}"); b=$(wall "$new" "${args[@]}")
        else
            b=$(wall "$new" "${args[@]}"); a=$(wall "$old" "${args[@]}")
        fi
        echo "$a" >>"$out.old"; echo "$b" >>"$out.new"; echo "$a / $b" | bc -l >>"$out.ratio"
    done
    printf 'old median %.1f ms\nnew median %.1f ms\nratio old/new: median %.3f (%d rounds)\n' \
        "$(median <"$out.old" | awk '{print $1 * 1000}')" \
        "$(median <"$out.new" | awk '{print $1 * 1000}')" \
        "$(median <"$out.ratio")" "$rounds"
    rm -f "$out.old" "$out.new" "$out.ratio"
    ;;
memory)
    bin="$2" cfg="${3:-sgi-teapot}" size="${4:-2048}"
    rss() { /usr/bin/time -v "$bin" render "$cfg_dir/$cfg.ron" --set "scene.width=$1" \
        --set "scene.height=$1" --out "$out" 2>&1 >/dev/null |
        awk '/Maximum resident set size/ {print $NF}'; }
    big=$(rss "$size"); small=$(rss 64)
    echo "$cfg ${size}x$size: peak RSS $big kB, at 64x64 $small kB," \
        "$(echo "($big - $small) * 1024 / ($size * $size)" | bc -l | xargs printf '%.1f') B/px"
    ;;
*)
    sed -n '2,14p' "$0"
    exit 2
    ;;
esac
