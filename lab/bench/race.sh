#!/usr/bin/env bash
# The equal-time race of issue 49 (docs/lab/race.md): Blender's Cycles with adaptive sampling (its
# default noise threshold and a tighter one) then Open Image Denoise, against Glint's glint-final
# (adaptive sampling steered by auto, then auto, in one command), at the same wall-clock budgets,
# on scenes/cornell and on the bare glTF asset scenes/fox/Fox.glb. Each result is measured against
# its own renderer's reference (the two renderers' pictures differ slightly): relMSE raw and with
# the reference's own noise subtracted (lab/bench/race_floor.py), SSIM and HDR-FLIP
# (`glint-image diff`). Writes race.csv and PNGs of the denoised images into OUT.
#
#   lab/bench/race.sh [BUILD_DIR] [OUT]          # OUT: default docs/tradeoffs
#   BUDGETS="2 8 32" SCENES="cornell fox" THRESHOLDS="0.01 0.002" SEEDS="1 2" lab/bench/race.sh build
#   lab/bench/race.sh build --references         # only the references (cached, see below)
#   lab/bench/race.sh build --collect            # only race.csv and the plots from the results so far
#
# Run it inside `slot` on the shared machine (2 cores): the budgets are wall-clock. It runs in
# pieces: every result is kept in RUN (default BUILD_DIR/race/run) and not run again, so calls
# with a few SCENES, BUDGETS and SEEDS each (each under 10 minutes) add up to the race; the last
# call (or --collect) writes race.csv and the plots from every result in RUN. Per scene, budget
# and seed Glint runs once and Cycles twice per threshold (OIDN's time counted, then not), Glint
# first for odd seeds and last for even ones. The 1-minute load average when each render starts is in the CSV.
#
# How time is counted: a budget is the wall-clock from starting the renderer's process to its
# denoised EXR written. Glint's is glint-final's whole run: loading, the BVH, the render, auto's
# refreshes and the final auto (`--time-limit BUDGET`). Cycles' includes Blender's start-up, the
# glTF import and the scene building (race_cycles.py takes them off Cycles' time limit) and
# OIDN's time, estimated natively: the OIDN peer that denoises Cycles' image is a single-threaded
# WebAssembly port many times slower than OIDN itself (its seconds are written beside,
# denoise_seconds), so just before each Cycles run the wall-clock of Glint's learned filter
# `unet` (OIDN's network and the weights the peer picks, rt_hdr_alb_nrm, run natively on the
# machine's 2 cores) as one process on a frame of the scene's size is measured (oidn_seconds:
# reading, the weights, the network, writing) and Cycles' render gets the budget less it. Each
# Cycles run is also made with the whole budget, OIDN not counted (oidn_counted 0), as before.
#
# References (REFS, default BUILD_DIR/race): per renderer and scene, the mean of one uniform render
# of REF_SPP spp (default 1024) for each of REF_SEEDS (default 99 100 101 102: 4096 spp in all),
# rendered once and cached in REFS/raw/; their spread estimates the reference's own noise, which
# race_floor.py subtracts. Needs blender (make bench-deps), python3-openimageio and the OIDN peer
# installed in OIDN (default /tmp/oidn; ../shared/peers/oidn/README.md). Exit 2 when one is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
OUT=${2:-docs/tradeoffs}
MODE=race
case $OUT in
  --references) MODE=references; OUT=docs/tradeoffs ;;
  --collect) MODE=collect; OUT=docs/tradeoffs ;;
esac
BUDGETS=${BUDGETS:-2 8 32}
SCENES=${SCENES:-cornell fox}
THRESHOLDS=${THRESHOLDS:-0.01 0.002}
SEEDS=${SEEDS:-1 2}
OIDN=${OIDN:-/tmp/oidn}
REFS=${REFS:-$BUILD_DIR/race}
RUN=${RUN:-$REFS/run}
BIN=$BUILD_DIR/bin
PY=/usr/bin/python3
FLOOR=lab/bench/race_floor.py
REF_SPP=${REF_SPP:-1024}
REF_SEEDS=${REF_SEEDS:-99 100 101 102}
MAX_SPP=4096 # Cycles' most samples a pixel in the race (its time limit ends it first)
PIECE=${PIECE:-0} # seconds: start no render that may not end within them (0: no limit)
SECONDS=0

command -v blender >/dev/null || { echo "race.sh: blender not found (make bench-deps)" >&2; exit 2; }
"$PY" -c "import OpenImageIO" 2>/dev/null ||
  { echo "race.sh: python3-openimageio not found (make bench-deps)" >&2; exit 2; }
[ -f "$OIDN/oidn_peer.js" ] && [ -d "$OIDN/node_modules" ] ||
  { echo "race.sh: no OIDN peer installed in $OIDN (../shared/peers/oidn/README.md)" >&2; exit 2; }
for b in glint-render glint-final glint-image glint-denoise; do
  [ -x "$BIN/$b" ] || { echo "race.sh: $BIN/$b not built" >&2; exit 2; }
done
mkdir -p "$REFS/raw" "$RUN/rows" "$OUT"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/glint-race.XXXXXX")
trap 'rm -rf "$WORK"' EXIT

# Glint's scene file of a race scene. The bare asset: 256 x 192 under the white sky of radiance 1
# that glint-render gives a bare asset, through the framing camera Blender's import of it gets
# (gltf_cycles.py) narrowed to a 20-degree field of view so that the fox fills the frame's height
# (race_cycles.py --glint-camera writes it): the same picture in both renderers.
glint_scene() {
  case $1 in
    cornell) echo scenes/cornell/scene.json ;;
    fox)
      if [ ! -f "$REFS/fox_bare.json" ]; then
        blender -b -P lab/bench/cycles/race_cycles.py -- $(cycles_scene fox) --spp 1 \
          --glint-camera "$WORK/camera.json" --out "$WORK/camera.exr" >/dev/null 2>&1
        cat >"$REFS/fox_bare.json" <<JSON
{"film": {"width": 256, "height": 192},
 "camera": $(cat "$WORK/camera.json"),
 "environment": {"color": [1, 1, 1]},
 "shapes": [{"gltf": "$PWD/scenes/fox/Fox.glb"}],
 "render": {"maxDepth": 8}}
JSON
      fi
      echo "$REFS/fox_bare.json" ;;
    *) echo "race.sh: unknown scene $1 (cornell, fox)" >&2; exit 2 ;;
  esac
}
# Cycles' arguments of a race scene.
cycles_scene() {
  case $1 in
    cornell) echo "cornell --width 256 --height 256" ;;
    fox) echo "$PWD/scenes/fox/Fox.glb --width 256 --height 192 --fov-y 20" ;;
  esac
}

# Cycles' render (race_cycles.py) into $2 (multilayer EXR); $1 scene, then its options. Prints
# the render's wall-clock seconds, counted from the shell's start of Blender.
cycles_render() {
  local scene=$1 out=$2
  shift 2
  local started line
  started=$(date +%s.%N)
  # shellcheck disable=SC2046
  line=$(blender -b -P lab/bench/cycles/race_cycles.py -- $(cycles_scene "$scene") \
    --threads 2 --max-depth 8 --started "$started" --out "$out" "$@" 2>/dev/null |
    grep '^{"renderer": "cycles"')
  "$PY" -c 'import json,sys,time; print("%.3f" % (time.time() - float(sys.argv[1])))' "$started"
  echo "$line" >>"$WORK/cycles.jsonl"
}

# A plain RGB EXR of layer $2 (a channel prefix, e.g. "ViewLayer.Combined.") of $1 into $3.
exr_layer() {
  "$PY" "$OIDN/exr_to_pfm.py" "$1" "$WORK/layer.pfm" --channels "$2R,$2G,$2B" >/dev/null
  "$PY" "$OIDN/pfm_to_exr.py" "$WORK/layer.pfm" "$3" >/dev/null
}

# Glint's side: glint-final renders and denoises scene $1 within budget $2 seconds (all of it:
# the render, auto's refreshes and the final auto) into $3, its log (the probe, the refreshes,
# the final auto's plan and times) into $4. Prints "seconds auto_seconds spp_mean" (auto's
# seconds are inside the budget).
glint_side() {
  local scene=$1 budget=$2 out=$3 log=$4 t0 t1
  t0=$(date +%s.%N)
  "$BIN/glint-final" "$(glint_scene "$scene")" --out "$out" --time-limit "$budget" --threads 2 \
    --set maxDepth=8 --set seed="$SEED" >"$WORK/final.txt" 2>"$log"
  t1=$(date +%s.%N)
  "$PY" -c 'import re,sys; a,b=map(float,sys.argv[1:3]); t=open(sys.argv[3]).read()
m=re.search(r"([0-9.]+) spp a pixel.*\(auto ([0-9.]+) s\)", t, re.S)
print("%.3f %s %s" % (b - a, m.group(2), m.group(1)))' "$t0" "$t1" "$WORK/final.txt"
}

# A frame of scene $1's size with albedo and normal (glint-render, 4 spp; cached in REFS) on
# which native OIDN's time is measured.
oidn_frame() {
  local frame=$REFS/oidn_frame_$1.exr
  if [ ! -f "$frame" ]; then
    "$BIN/glint-render" "$(glint_scene "$1")" --threads 2 --set maxDepth=8 --spp 4 --seed 1 \
      --out "$WORK/oidn_frame.exr" >/dev/null 2>&1
    mv "$WORK/oidn_frame.exr" "$frame"
  fi
  echo "$frame"
}

# Native OIDN's seconds on scene $1's frame, estimated by Glint's learned filter `unet` (OIDN's
# network and weights; with a colour, a noisy albedo and normal and no quality given it takes
# rt_hdr_alb_nrm, the weights the peer takes for Cycles' passes) as one process, its start
# included: the wall-clock of `glint-denoise apply --filter unet` on the machine's 2 cores.
oidn_seconds() {
  local frame t0 t1
  frame=$(oidn_frame "$1")
  t0=$(date +%s.%N)
  "$BIN/glint-denoise" apply "$frame" --filter unet --out "$WORK/unet.exr" >/dev/null 2>&1
  t1=$(date +%s.%N)
  "$PY" -c 'import sys; print("%.3f" % (float(sys.argv[2]) - float(sys.argv[1])))' "$t0" "$t1"
}

# Cycles' side: renders scene $1 within budget $2 at threshold $3, OIDN (colour, albedo, normal,
# HDR) into $4; with $5 = 1 native OIDN's seconds $6 come off the budget (counted). Prints
# "render_seconds denoise_seconds".
cycles_side() {
  local scene=$1 budget=$2 threshold=$3 out=$4 counted=$5 oidn=$6 seconds t0 t1 L=ViewLayer.
  if [ "$counted" = 1 ]; then
    budget=$("$PY" -c 'import sys; print("%.3f" % (float(sys.argv[1]) - float(sys.argv[2])))' \
      "$budget" "$oidn")
  fi
  seconds=$(cycles_render "$scene" "$WORK/cycles.exr" --seed "$SEED" --spp $MAX_SPP \
    --budget "$budget" --noise-threshold "$threshold" --passes)
  t0=$(date +%s.%N)
  "$PY" "$OIDN/exr_to_pfm.py" "$WORK/cycles.exr" "$WORK/color.pfm" \
    --channels "${L}Combined.R,${L}Combined.G,${L}Combined.B" >/dev/null
  "$PY" "$OIDN/exr_to_pfm.py" "$WORK/cycles.exr" "$WORK/albedo.pfm" \
    --channels "${L}Denoising Albedo.R,${L}Denoising Albedo.G,${L}Denoising Albedo.B" >/dev/null
  "$PY" "$OIDN/exr_to_pfm.py" "$WORK/cycles.exr" "$WORK/normal.pfm" \
    --channels "${L}Denoising Normal.X,${L}Denoising Normal.Y,${L}Denoising Normal.Z" >/dev/null
  node "$OIDN/oidn_peer.js" --color "$WORK/color.pfm" --albedo "$WORK/albedo.pfm" \
    --normal "$WORK/normal.pfm" --out "$WORK/oidn.pfm" --hdr --quiet
  "$PY" "$OIDN/pfm_to_exr.py" "$WORK/oidn.pfm" "$out" >/dev/null
  t1=$(date +%s.%N)
  "$PY" -c 'import sys; print("%s %.3f" % (sys.argv[1], float(sys.argv[3]) - float(sys.argv[2])))' \
    "$seconds" "$t0" "$t1"
}

# Whether $1 more seconds fit in the PIECE; if not, says so (a later call goes on).
fits() {
  [ "$STOPPED" = 0 ] || return 1
  if [ "$PIECE" -gt 0 ] && [ $((SECONDS + $1)) -gt "$PIECE" ]; then
    echo "race.sh: stopping at $SECONDS s of PIECE=$PIECE: call again to go on" >&2
    STOPPED=1
    return 1
  fi
}
STOPPED=0

# The references' renders of scene $1 by renderer $2, one a seed.
ref_renders() {
  local seed
  for seed in $REF_SEEDS; do echo "$REFS/raw/$2_$1_$seed.exr"; done
}

# The references: every missing render (one a seed, REF_SPP uniform samples), then their mean.
if [ "$MODE" != collect ]; then
  for scene in $SCENES; do
    # Seconds the scene's slowest reference render may take on the shared machine (1024 spp:
    # about 170 s for Cycles' cornell, 30 for the fox).
    if [ "$scene" = cornell ]; then ref_seconds=200; else ref_seconds=80; fi
    ref_seconds=$((ref_seconds * REF_SPP / 1024))
    for seed in $REF_SEEDS; do
      raw=$REFS/raw/glint_${scene}_$seed.exr
      if [ ! -f "$raw" ] && fits "$ref_seconds"; then
        echo "race.sh: Glint's $scene reference, $REF_SPP spp, seed $seed" >&2
        "$BIN/glint-render" "$(glint_scene "$scene")" --threads 2 --set maxDepth=8 --spp "$REF_SPP" \
          --seed "$seed" --out "$WORK/ref.exr" >/dev/null 2>&1
        exr_layer "$WORK/ref.exr" "" "$WORK/ref_rgb.exr"
        mv "$WORK/ref_rgb.exr" "$raw"
      fi
      raw=$REFS/raw/cycles_${scene}_$seed.exr
      if [ ! -f "$raw" ] && fits "$ref_seconds"; then
        echo "race.sh: Cycles' $scene reference, $REF_SPP spp, seed $seed" >&2
        cycles_render "$scene" "$WORK/ref.exr" --spp "$REF_SPP" --seed "$seed" >/dev/null
        exr_layer "$WORK/ref.exr" ViewLayer.Combined. "$WORK/ref_rgb.exr"
        mv "$WORK/ref_rgb.exr" "$raw"
      fi
    done
    for r in glint cycles; do
      for raw in $(ref_renders "$scene" $r); do [ -f "$raw" ] || continue 2; done
      # shellcheck disable=SC2046
      "$PY" $FLOOR mean "$REFS/${r}_$scene.exr" $(ref_renders "$scene" $r)
    done
  done
fi
[ "$STOPPED" = 1 ] && exit 3
[ "$MODE" = references ] && exit 0

# Errors of result $1 against renderer $2's reference of scene $3: "relmse floor corrected
# corrected_a corrected_b ssim flip" (race_floor.py: relMSE raw, the reference's floor, relMSE
# corrected against all the renders and against each half of them; then glint-image's SSIM, FLIP).
errors() {
  local floor
  # shellcheck disable=SC2046
  floor=$("$PY" $FLOOR relmse "$1" $(ref_renders "$3" "$2") --split)
  "$BIN/glint-image" diff "$1" --reference "$REFS/$2_$3.exr" --metric ssim --metric flip \
    --json | "$PY" -c 'import json,sys
r = {m["request"]: m["value"] for m in json.load(sys.stdin)["results"]}
print("%s %.6g %.6g" % (sys.argv[1], r["ssim"], r["flip"]))' "$floor"
}
load() { cut -d' ' -f1 /proc/loadavg; }

# One result a row file in RUN/rows (kept: a later call skips it), its image in RUN.
COLUMNS_CSV="scene,renderer,threshold,budget,seed,render_seconds,denoise_seconds,mean_spp,relmse,relmse_floor,relmse_corrected,relmse_corrected_a,relmse_corrected_b,ssim,flip,noisy_relmse,load,oidn_seconds,oidn_counted"
run_glint() {
  local scene=$1 budget=$2 row=$RUN/rows/${1}_glint_final_$2_$SEED.csv l rs ds spp e fl c a b s f
  [ -f "$row" ] && return 0
  l=$(load)
  read -r rs ds spp < <(glint_side "$scene" "$budget" "$WORK/final.exr" \
    "$RUN/log_${scene}_glint_final_${budget}_$SEED.txt")
  read -r e fl c a b s f < <(errors "$WORK/final.exr" glint "$scene")
  cp "$WORK/final.exr" "$RUN/img_${scene}_glint_final_${budget}_$SEED.exr"
  echo "$scene,glint-final,final,$budget,$SEED,$rs,$ds,$spp,$e,$fl,$c,$a,$b,$s,$f,,$l,," | tee "$row"
}
# Cycles + OIDN at threshold $3; $4 = 1: native OIDN's time counted in the budget, 0: not.
run_cycles() {
  local scene=$1 budget=$2 threshold=$3 counted=$4 l rs ds e fl c a b s f noisy oidn stem
  stem=cycles_$3; [ "$counted" = 1 ] || stem=cycles_uncounted_$3
  local row=$RUN/rows/${scene}_${stem}_${budget}_$SEED.csv
  [ -f "$row" ] && return 0
  l=$(load)
  oidn=$(oidn_seconds "$scene")
  read -r rs ds < <(cycles_side "$scene" "$budget" "$threshold" "$WORK/oidn.exr" "$counted" "$oidn")
  exr_layer "$WORK/cycles.exr" ViewLayer.Combined. "$WORK/cycles_rgb.exr"
  read -r e fl c a b s f < <(errors "$WORK/oidn.exr" cycles "$scene")
  # shellcheck disable=SC2046
  noisy=$("$PY" $FLOOR relmse "$WORK/cycles_rgb.exr" $(ref_renders "$scene" cycles) | cut -d' ' -f1)
  cp "$WORK/oidn.exr" "$RUN/img_${scene}_${stem}_${budget}_$SEED.exr"
  echo "$scene,cycles+oidn,$threshold,$budget,$SEED,$rs,$ds,,$e,$fl,$c,$a,$b,$s,$f,$noisy,$l,$oidn,$counted" |
    tee "$row"
}

if [ "$MODE" = race ]; then
  for scene in $SCENES; do
    for budget in $BUDGETS; do
      for SEED in $SEEDS; do
        # One piece holds a seed's runs of a budget (Glint and each Cycles threshold, OIDN
        # counted and not) together.
        if [ "$STOPPED" = 1 ] || ! fits $((5 * budget + 90)); then continue; fi
        if [ $((SEED % 2)) = 1 ]; then run_glint "$scene" "$budget"; fi
        for threshold in $THRESHOLDS; do
          run_cycles "$scene" "$budget" "$threshold" 1
          run_cycles "$scene" "$budget" "$threshold" 0
        done
        if [ $((SEED % 2)) = 0 ]; then run_glint "$scene" "$budget"; fi
      done
    done
  done
fi

[ "$STOPPED" = 1 ] && exit 3

# race.csv from every result in RUN, and the plots.
{
  echo "$COLUMNS_CSV"
  cat "$RUN"/rows/*.csv 2>/dev/null | sort -t, -k1,1 -k4,4n -k2,2 -k3,3r -k5,5n
} >"$OUT/race.csv"
"$PY" lab/bench/report/plot_race.py "$OUT" --images "$RUN" --references "$REFS"
echo "race.sh: $OUT/race.csv, $OUT/race.png, $OUT/race_<scene>.png"
