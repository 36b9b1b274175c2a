#!/usr/bin/env bash
# Where does the error per sample come from? Glint and Cycles at equal spp on scenes/cornell,
# bounce depth by bounce depth (docs/lab/renderer.md, "Where the error per sample came from"):
# for Glint maxDepth D (Cycles max bounces D - 1), a Glint reference at 1024 spp (seed 99), then
# relMSE at SPP spp of Cycles and of Glint's stratified and sobol samplers against it.
#   lab/bench/cycles/depth_compare.sh [BUILD_DIR] [SPP] [DEPTHS...]
# Needs Debian's `blender` (make bench-deps). About 2 minutes on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/../../.."
BUILD_DIR=${1:-build}
SPP=${2:-64}
shift $(( $# > 2 ? 2 : $# ))
DEPTHS=${*:-1 2 3}
G="$BUILD_DIR/bin/glint-render"
OUT=${TMPDIR:-/tmp}/glint-depth-compare.$$
mkdir -p "$OUT"
source "$(dirname "$0")/with_sampler.sh"
trap 'rm -rf "$OUT"; remove_sampler_copies' EXIT
command -v blender >/dev/null || { echo "depth_compare.sh: blender not found (make bench-deps)" >&2; exit 2; }
relmse() { "$BUILD_DIR/bin/glint-image" diff "$1" --reference "$2" --metric relmse --json |
  python3 -c 'import json,sys; print("%.3g" % json.load(sys.stdin)["value"])'; }
echo "depth cycles glint_stratified glint_sobol"
for D in $DEPTHS; do
  "$G" scenes/cornell/scene.json --spp 1024 --set maxDepth="$D" --seed 99 --threads 2 \
    --out "$OUT/ref.exr" >/dev/null 2>&1
  blender -b -P lab/bench/cycles/cornell_cycles.py -- --spp "$SPP" --threads 2 \
    --max-depth $((D - 1)) --out "$OUT/cycles.exr" >/dev/null 2>&1
  line="$D $(relmse "$OUT/cycles.exr" "$OUT/ref.exr")"
  for S in stratified sobol; do
    "$G" "$(with_sampler scenes/cornell/scene.json $S)" --spp "$SPP" --set maxDepth="$D" --threads 2 \
      --out "$OUT/g.exr" >/dev/null 2>&1
    line="$line $(relmse "$OUT/g.exr" "$OUT/ref.exr")"
  done
  echo "$line"
done
