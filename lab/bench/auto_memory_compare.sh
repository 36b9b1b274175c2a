#!/usr/bin/env bash
# The figures of docs/lab/auto-memory.md: the peak resident memory and the CPU time (user + sys)
# of the one auto pipeline (what `glint-denoise auto IN --out OUT` runs with no flag:
# bench_auto_memory --mode streamed) against another build's bench_auto_memory — the in-memory
# path of 1b719f6^ (--mode whole, OLD_MODE) — alternating, ROUNDS times per size, each run in
# its own process under /usr/bin/time -v, with the composite's values compared (--against).
# Renders scenes/cornell with half buffers at 4 spp at each size first (as auto_memory.sh).
# NEW_ONLY lists the sizes run with the new build alone (the in-memory path at 4K needs ~20 GB).
# OLD_MODE=streamed compares two builds of the one pipeline (before and after a change).
# Not part of `make test`: minutes per run.
#   OLD=/path/to/old/bin/bench_auto_memory lab/bench/auto_memory_compare.sh [BUILD_DIR] [WORK_DIR]
#   SIZES="1920x1080 1024x1024 3840x2160" NEW_ONLY="3840x2160" ROUNDS=2 ...
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build}
work=${2:-/tmp/glint-auto-memory}
old=${OLD:?OLD must name another build of bench_auto_memory}
oldMode=${OLD_MODE:-whole}
sizes=${SIZES:-1920x1080 1024x1024}
newOnly=${NEW_ONLY-3840x2160}
rounds=${ROUNDS:-2}
mkdir -p "$work"
ln -sf "$root/scenes/cornell/cornell_box.obj" "$root/scenes/cornell/cornell_box.mtl" "$work/"
# One run: NAME BIN ARGS…, its JSON line and the times; its resident memory every 2 s (VmRSS,
# KiB, against the seconds since the start) in WORK/NAME.rss, to find the phase of the peak.
run() {
    local name=$1
    shift
    /usr/bin/time -v -o "$work/$name.time" "$@" > "$work/$name.json" &
    local timePid=$! start=$SECONDS
    sleep 1
    local benchPid
    benchPid=$(pgrep -P "$timePid" || true)
    : > "$work/$name.rss"
    while kill -0 "$timePid" 2> /dev/null; do
        if [ -n "$benchPid" ]; then
            awk -v t=$((SECONDS - start)) '/VmRSS/ {print t, $2}' "/proc/$benchPid/status" \
                >> "$work/$name.rss" 2> /dev/null || true
        fi
        sleep 2
    done
    wait "$timePid"
    echo "$name $(cat "$work/$name.json")"
    grep -E "User time|System time|Maximum resident" "$work/$name.time" | tr -s ' \t' ' ' |
        tr '\n' ';'
    echo
}
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
        "$build/bin/glint-render" "$work/cornell-$size.json" --spp 4 --set halfBuffers=true --threads 2 \
            --out "$input" > /dev/null
    fi
    for r in $(seq 1 "$rounds"); do
        against=()
        if [[ " $newOnly " != *" $size "* ]]; then
            run "old-$size-$r" "$old" --in "$input" --mode "$oldMode" --threads 2 \
                --out "$work/old-$size.exr"
            against=(--against "$work/old-$size.exr")
        fi
        run "new-$size-$r" "$build/bin/bench_auto_memory" --in "$input" --mode streamed \
            --threads 2 --out "$work/new-$size.exr" "${against[@]}"
    done
done
