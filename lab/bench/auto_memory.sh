#!/usr/bin/env bash
# The memory figure of the automatic selection (docs/auto-memory.md): renders scenes/cornell
# with half buffers at 4 spp at each SIZE (WIDTHxHEIGHT; default 1920x1080 and 3840x2160), then
# runs bench_auto_memory in its own process per figure — the pipeline applying the members tile
# by tile (what `glint-denoise auto IN --out OUT` runs) and, unless the size is in NO_WHOLE, the
# same pipeline over a materialised bank — under /usr/bin/time -v, and prints one JSON line per
# run with the time, the tiles' height, the peak resident memory and the largest difference from
# the run before it. MODES lists the runs in order: whole, streamed (with its spill file, the
# default) and recompute (with the spill off, which must equal streamed bit for bit).
# Not part of `make test`: it takes minutes and most of the machine's memory.
#   lab/bench/auto_memory.sh [BUILD_DIR] [WORK_DIR]
#   SIZES="1920x1080 3840x2160" NO_WHOLE="3840x2160" MODES="whole streamed recompute" \
#     MEMBERS=64 THREADS=2 lab/bench/auto_memory.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
work=${2:-/tmp/glint-auto-memory}
sizes=${SIZES:-1920x1080 3840x2160}
noWhole=${NO_WHOLE:-3840x2160}
modes=${MODES:-whole streamed}
members=${MEMBERS:-64}
threads=${THREADS:-2}
mkdir -p "$work"
ln -sf "$root/scenes/cornell/cornell_box.obj" "$root/scenes/cornell/cornell_box.mtl" "$work/"
for size in $sizes; do
    w=${size%x*} h=${size#*x}
    input="$work/cornell-$size.exr"
    if [ ! -f "$input" ]; then
        /usr/bin/python3 - "$root/scenes/cornell/scene.json" "$work/cornell-$size.json" "$w" "$h" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["film"] = {"width": int(sys.argv[3]), "height": int(sys.argv[4])}
json.dump(scene, open(sys.argv[2], "w"))
PY
        "$build/bin/glint-render" "$work/cornell-$size.json" --spp 4 --set halfBuffers=true \
            --threads "$threads" --out "$input" > /dev/null
    fi
    against=()
    for mode in $modes; do
        if [ "$mode" = whole ] && [[ " $noWhole " == *" $size "* ]]; then continue; fi
        out="$work/$mode-$size.exr"
        spill=auto run=$mode
        if [ "$mode" = recompute ]; then spill=off run=streamed; fi
        /usr/bin/time -v -o "$work/$mode-$size.time" "$build/bin/bench_auto_memory" \
            --in "$input" --mode "$run" --spill "$spill" --members "$members" \
            --threads "$threads" --out "$out" "${against[@]}"
        grep -E "User time|System time|Elapsed|Maximum resident" "$work/$mode-$size.time" |
            sed 's/^\s*/  /'
        against=(--against "$out")
    done
done
