#!/usr/bin/env bash
# The equal-time race of issue 49 (docs/lab/race.md): Blender's Cycles with adaptive sampling (its
# default noise threshold and a tighter one) then Open Image Denoise, against Glint with adaptive
# sampling then `glint-denoise auto`, at the same wall-clock render budgets, on scenes/cornell and
# on the bare glTF asset scenes/fox/Fox.glb. Each result is measured against its own renderer's
# 4096-spp reference (the two renderers' pictures differ slightly): relMSE, SSIM and HDR-FLIP
# (`glint-image diff`). Writes race.csv and PNGs of every denoised image into OUT.
#
#   lab/bench/race.sh [BUILD_DIR] [OUT]          # OUT: default docs/tradeoffs
#   BUDGETS="2 8 32" SCENES="cornell fox" THRESHOLDS="0.01 0.002" SEED=1 lab/bench/race.sh build
#   lab/bench/race.sh build --references         # only the references (cached, see below)
#
# Run it inside `slot` on the shared machine (2 cores, one run at a time): the budgets are
# wall-clock. How time is counted: a budget is the render's wall-clock from starting the renderer's
# process to its EXR written, so Cycles' includes Blender's start-up, the glTF import and the
# scene building (race_cycles.py takes them off Cycles' time limit); Glint's includes loading and
# the BVH. The denoisers' wall-clock is measured and written beside it (auto_seconds,
# oidn_seconds) but not counted: the OIDN peer is a single-threaded WebAssembly port of OIDN, many
# times slower than OIDN itself.
#
# References (REFS, default BUILD_DIR/race): 4096 spp, seed 99 (no race seed), rendered once and
# cached; Glint's cornell reference is the committed scenes/cornell/reference.exr (4096 spp, seed
# 7). Needs blender (make bench-deps), python3-openimageio and the OIDN peer installed in OIDN
# (default /tmp/oidn; ../shared/peers/oidn/README.md). Exit 2 when one is missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD_DIR=${1:-build}
OUT=${2:-docs/tradeoffs}
ONLY_REFERENCES=0
if [ "$OUT" = --references ]; then ONLY_REFERENCES=1; OUT=docs/tradeoffs; fi
BUDGETS=${BUDGETS:-2 8 32}
SCENES=${SCENES:-cornell fox}
THRESHOLDS=${THRESHOLDS:-0.01 0.002}
SEED=${SEED:-1}
OIDN=${OIDN:-/tmp/oidn}
REFS=${REFS:-$BUILD_DIR/race}
BIN=$BUILD_DIR/bin
PY=/usr/bin/python3
REF_SPP=${REF_SPP:-4096}
REF_SEED=99

command -v blender >/dev/null || { echo "race.sh: blender not found (make bench-deps)" >&2; exit 2; }
"$PY" -c "import OpenImageIO" 2>/dev/null ||
  { echo "race.sh: python3-openimageio not found (make bench-deps)" >&2; exit 2; }
[ -f "$OIDN/oidn_peer.js" ] && [ -d "$OIDN/node_modules" ] ||
  { echo "race.sh: no OIDN peer installed in $OIDN (../shared/peers/oidn/README.md)" >&2; exit 2; }
for b in glint-render glint-denoise glint-image; do
  [ -x "$BIN/$b" ] || { echo "race.sh: $BIN/$b not built" >&2; exit 2; }
done
mkdir -p "$REFS" "$OUT"
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

# Glint's side: renders scene $1 within budget $2 seconds at threshold $3 and denoises into $4.
# Prints "render_seconds denoise_seconds spp_mean". The one function to switch to loop49's
# render-and-denoise command.
glint_side() {
  local scene=$1 budget=$2 threshold=$3 out=$4 t0 t1 t2
  t0=$(date +%s.%N)
  "$BIN/glint-render" "$(glint_scene "$scene")" --threads 2 --set maxDepth=8 --seed "$SEED" \
    --spp $REF_SPP --time-limit "$budget" --set halfBuffers=true --set adaptive=true \
    --set noiseThreshold="$threshold" --json --out "$WORK/glint.exr" >"$WORK/glint.json" 2>/dev/null
  t1=$(date +%s.%N)
  "$BIN/glint-denoise" auto "$WORK/glint.exr" --out "$out" >/dev/null 2>&1
  t2=$(date +%s.%N)
  "$PY" -c 'import json,sys; a,b,c=map(float,sys.argv[1:4]); m=json.load(open(sys.argv[4]))
print("%.3f %.3f %.1f" % (b - a, c - b, m["meanSpp"]))' "$t0" "$t1" "$t2" "$WORK/glint.json"
}

# Cycles' side: renders scene $1 within budget $2 at threshold $3, OIDN (colour, albedo, normal,
# HDR) into $4. Prints "render_seconds denoise_seconds".
cycles_side() {
  local scene=$1 budget=$2 threshold=$3 out=$4 seconds t0 t1 L=ViewLayer.
  seconds=$(cycles_render "$scene" "$WORK/cycles.exr" --seed "$SEED" --spp $REF_SPP \
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

# The references, once (a cached file is kept).
for scene in $SCENES; do
  if [ "$scene" = cornell ]; then
    [ -f "$REFS/glint_cornell.exr" ] || cp scenes/cornell/reference.exr "$REFS/glint_cornell.exr"
  elif [ ! -f "$REFS/glint_$scene.exr" ]; then
    echo "race.sh: Glint's $scene reference, $REF_SPP spp" >&2
    "$BIN/glint-render" "$(glint_scene "$scene")" --threads 2 --set maxDepth=8 --spp $REF_SPP \
      --seed $REF_SEED --out "$REFS/glint_$scene.tmp.exr" >/dev/null 2>&1
    mv "$REFS/glint_$scene.tmp.exr" "$REFS/glint_$scene.exr"
  fi
  if [ ! -f "$REFS/cycles_$scene.exr" ]; then
    echo "race.sh: Cycles' $scene reference, $REF_SPP spp" >&2
    cycles_render "$scene" "$WORK/ref.exr" --spp $REF_SPP --seed $REF_SEED >/dev/null
    exr_layer "$WORK/ref.exr" ViewLayer.Combined. "$REFS/cycles_$scene.tmp.exr"
    mv "$REFS/cycles_$scene.tmp.exr" "$REFS/cycles_$scene.exr"
  fi
done
[ "$ONLY_REFERENCES" = 1 ] && exit 0

# relMSE, SSIM and FLIP of $1 against $2: "relmse ssim flip".
errors() {
  "$BIN/glint-image" diff "$1" --reference "$2" --metric relmse --metric ssim --metric flip \
    --json | "$PY" -c 'import json,sys
r = {m["request"]: m["value"] for m in json.load(sys.stdin)["results"]}
print("%.6g %.6g %.6g" % (r["relmse"], r["ssim"], r["flip"]))'
}

CSV="$WORK/race.csv"
echo "scene,renderer,threshold,budget,render_seconds,denoise_seconds,mean_spp,relmse,ssim,flip,noisy_relmse" >"$CSV"
for scene in $SCENES; do
  for budget in $BUDGETS; do
    for threshold in $THRESHOLDS; do
      read -r rs ds < <(cycles_side "$scene" "$budget" "$threshold" "$WORK/oidn.exr")
      exr_layer "$WORK/cycles.exr" ViewLayer.Combined. "$WORK/cycles_rgb.exr"
      read -r e s f < <(errors "$WORK/oidn.exr" "$REFS/cycles_$scene.exr")
      read -r noisy _ < <(errors "$WORK/cycles_rgb.exr" "$REFS/cycles_$scene.exr")
      echo "$scene,cycles+oidn,$threshold,$budget,$rs,$ds,,$e,$s,$f,$noisy" | tee -a "$CSV"
      cp "$WORK/oidn.exr" "$WORK/img_${scene}_cycles_${threshold}_$budget.exr"

      read -r rs ds spp < <(glint_side "$scene" "$budget" "$threshold" "$WORK/auto.exr")
      read -r e s f < <(errors "$WORK/auto.exr" "$REFS/glint_$scene.exr")
      read -r noisy _ < <(errors "$WORK/glint.exr" "$REFS/glint_$scene.exr")
      echo "$scene,glint+auto,$threshold,$budget,$rs,$ds,$spp,$e,$s,$f,$noisy" | tee -a "$CSV"
      cp "$WORK/auto.exr" "$WORK/img_${scene}_glint_${threshold}_$budget.exr"
    done
  done
done
cp "$CSV" "$OUT/race.csv"
"$PY" lab/bench/report/plot_race.py "$OUT" --images "$WORK" --references "$REFS"
echo "race.sh: $OUT/race.csv, $OUT/race.png, $OUT/race_<scene>.png"
