#!/usr/bin/env bash
# Error per sample and per second against Blender's Cycles (issue: accuracy per sample):
# scenes/cornell at 256², 64 spp, depth 8, 2 threads, relMSE of each render against the
# committed 4096-spp reference, samples/s as each renderer reports it, all in one run; then
# the same on glossy and envmap, each renderer against its own reference (see below).
#   lab/bench/cycles/sampler_compare.sh [BUILD_DIR] [SPP] [REPEATS]
# Needs Debian's `blender` (make bench-deps). Exit code 2 when it is missing.
set -euo pipefail
cd "$(dirname "$0")/../../.."
BUILD_DIR=${1:-build}
SPP=${2:-64}
REPEATS=${3:-3}
GLINT="$BUILD_DIR/bin/glint-render"
IMAGE="$BUILD_DIR/bin/glint-image"
OUT=${TMPDIR:-/tmp}/glint-sampler-compare.$$
mkdir -p "$OUT"
source "$(dirname "$0")/with_sampler.sh"
trap 'rm -rf "$OUT"; remove_sampler_copies' EXIT
command -v blender >/dev/null || { echo "sampler_compare.sh: blender not found (make bench-deps)" >&2; exit 2; }

relmse() { "$IMAGE" diff "$1" --reference "$2" --metric relmse --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["value"])'; }

echo "scene renderer sampler spp samples_per_s relMSE relMSE_over_rate"
for ((i = 1; i <= REPEATS; ++i)); do
  line=$(blender -b -P lab/bench/cycles/cornell_cycles.py -- --spp "$SPP" --threads 2 --max-depth 8 \
    --out "$OUT/cycles.exr" 2>/dev/null | grep '^{"renderer": "cycles"')
  rate=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["samplesPerSecond"])' "$line")
  err=$(relmse "$OUT/cycles.exr" scenes/cornell/reference.exr)
  python3 -c "import sys; r,e=float(sys.argv[1]),float(sys.argv[2]); print(f'cornell cycles pmj $SPP {r/1e6:.3f}M {e:.5f} {e/r*1e6:.5f}')" "$rate" "$err"
  for sampler in stratified sobol zsobol; do
    rate=$("$GLINT" "$(with_sampler scenes/cornell/scene.json $sampler)" --spp "$SPP" --set maxDepth=8 --threads 2 \
      --seed "$i" --out "$OUT/glint.exr" --json 2>/dev/null | python3 -c 'import json,sys; print(json.load(sys.stdin)["samplesPerSecond"])')
    err=$(relmse "$OUT/glint.exr" scenes/cornell/reference.exr)
    python3 -c "import sys; r,e=float(sys.argv[1]),float(sys.argv[2]); print(f'cornell glint $sampler $SPP {r/1e6:.3f}M {e:.5f} {e/r*1e6:.5f}')" "$rate" "$err"
  done
done
# glossy and envmap: Cycles renders the same scene (scene_cycles.py; the conversion and where it
# differs are in its header), so each renderer is measured against its own converged reference:
# Glint's committed 16384-spp reference, and a Cycles reference at CYCLES_REF_SPP (default 4096)
# rendered once and kept in CACHE (glossy ~1 min, envmap ~4 min on 2 cores).
CACHE=${GLINT_CYCLES_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/glint-cycles}
REF_SPP=${CYCLES_REF_SPP:-4096}
mkdir -p "$CACHE"
for scene in glossy envmap; do
  key=$(cat scenes/$scene/scene.json lab/bench/cycles/scene_cycles.py | sha256sum | cut -c1-12)
  ref="$CACHE/${scene}-${REF_SPP}spp-${key}.exr"
  if [ ! -f "$ref" ]; then
    echo "(rendering the Cycles reference of $scene at $REF_SPP spp into $ref)" >&2
    blender -b -P lab/bench/cycles/scene_cycles.py -- scenes/$scene/scene.json --spp "$REF_SPP" \
      --threads 2 --seed 4242 --out "$OUT/ref.exr" >/dev/null 2>&1
    mv "$OUT/ref.exr" "$ref"
  fi
  for ((i = 1; i <= REPEATS; ++i)); do
    line=$(blender -b -P lab/bench/cycles/scene_cycles.py -- scenes/$scene/scene.json --spp "$SPP" \
      --threads 2 --seed "$i" --out "$OUT/cycles.exr" 2>/dev/null | grep '^{"renderer": "cycles"')
    rate=$(python3 -c 'import json,sys; print(json.loads(sys.argv[1])["samplesPerSecond"])' "$line")
    err=$(relmse "$OUT/cycles.exr" "$ref")
    python3 -c "import sys; r,e=float(sys.argv[1]),float(sys.argv[2]); print(f'$scene cycles pmj $SPP {r/1e6:.3f}M {e:.5f} {e/r*1e6:.5f}')" "$rate" "$err"
    for sampler in stratified sobol zsobol; do
      rate=$("$GLINT" "$(with_sampler scenes/$scene/scene.json $sampler)" --spp "$SPP" --threads 2 \
        --seed "$i" --out "$OUT/glint.exr" --json 2>/dev/null | python3 -c 'import json,sys; print(json.load(sys.stdin)["samplesPerSecond"])')
      err=$(relmse "$OUT/glint.exr" scenes/$scene/reference.exr)
      python3 -c "import sys; r,e=float(sys.argv[1]),float(sys.argv[2]); print(f'$scene glint $sampler $SPP {r/1e6:.3f}M {e:.5f} {e/r*1e6:.5f}')" "$rate" "$err"
    done
  done
done
