#!/usr/bin/env bash
# make report: every part of docs/lab/tradeoffs.md — CSVs from glint-report (and Blender's Cycles for
# the peer comparison), then the PNG plots — into docs/tradeoffs/. About 3-4 minutes on a quiet
# 2-core machine (docs/lab/tradeoffs.md has the measured time); each part's line can be run alone.
#   lab/bench/report/run.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/../../.."
BUILD=${1:-build}
OUT=docs/tradeoffs
R="$BUILD/bin/glint-report"
mkdir -p "$OUT"
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
SECONDS=0

echo "== 1. convergence (half resolution, 1 ... 1024 spp; PT power / balance / none, MLT)"
for s in cornell glossy door pool dof; do
  "$R" convergence "scenes/$s" --scale 2 --max-spp 1024 --out "$OUT/convergence_$s.csv"
done

echo "   (${SECONDS} s)"
echo "== 2. against Cycles at equal time (cornell, full resolution)"
"$R" convergence scenes/cornell --scale 1 --max-spp 512 --methods power,mlt --out "$OUT/peer_glint.csv"
echo "spp,seconds,relmse" > "$TMP/peer_cycles.csv"
if command -v blender >/dev/null; then
  for spp in 1 2 4 8 16 32 64 128 256; do
    line=$(blender -b -P lab/bench/cycles/cornell_cycles.py -- --spp $spp --threads 2 --max-depth 8 \
      --out "$TMP/cycles.exr" 2>/dev/null | grep '^{"renderer": "cycles"')
    seconds=$(/usr/bin/python3 -c 'import json,sys; print(json.loads(sys.argv[1])["seconds"])' "$line")
    err=$("$BUILD/bin/glint-image" diff "$TMP/cycles.exr" --reference scenes/cornell/reference.exr \
      --metric relmse --json | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["value"])')
    echo "$spp,$seconds,$err" >> "$TMP/peer_cycles.csv"
  done
else
  echo "report: blender not found (make bench-deps): part 2 has no Cycles curve" >&2
fi
mv "$TMP/peer_cycles.csv" "$OUT/peer_cycles.csv"

echo "   (${SECONDS} s)"
echo "== 3 and 4. denoising and the render + denoise frontier (cornell, 1 ... 1024 spp)"
"$R" denoise scenes/cornell --max-spp 1024 --bank 16 --out "$OUT/denoise.csv"

echo "   (${SECONDS} s)"
echo "== 5. bilateral-mc against the exact bilateral (cornell, 64 spp, half resolution)"
"$R" bilateral-mc scenes/cornell --scale 2 --spp 64 --out "$OUT/bilateral_mc.csv"

echo "   (${SECONDS} s)"
echo "== 6. threads and peak memory"
"$R" threads scenes/cornell --out "$OUT/threads.csv"

echo "   (${SECONDS} s)"
echo "== 7. the equal-time race against Cycles + OIDN (docs/lab/race.md; RACE=1 reruns it: ~20 min on a quiet machine, ~20 more for the references the first time)"
if [ "${RACE:-0}" = 1 ]; then
  lab/bench/race.sh "$BUILD" "$OUT"
elif [ -f "$OUT/race.csv" ]; then
  /usr/bin/python3 lab/bench/report/plot_race.py "$OUT" >/dev/null  # race.png from race.csv
fi

echo "   (${SECONDS} s)"
echo "== plots"
/usr/bin/python3 lab/bench/report/plot_tradeoffs.py "$OUT"
echo "report: done in ${SECONDS} s; CSVs and PNGs in $OUT/"
