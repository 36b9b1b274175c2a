#!/usr/bin/env bash
# Glint against Open Image Denoise (docs/lab/auto.md, "Against OIDN"): for each scene, spp and render
# seed, a render with half buffers, its 64-member banks (seed 1) and SSIM on display values
# against the committed reference of
#   - auto (the halves estimator, its defaults) over the bank of the filters before the learned
#     member ("classical": gaussian … nlmeans, `--filters`), as auto was before unet joined,
#   - auto over the default bank (the same members and unet, docs/auto.md, "The learned member"),
#   - unet alone (`glint-denoise apply --filter unet`, its defaults),
#   - OIDN's RT filter with albedo and normal, HDR (the peer of ../shared/peers/oidn, when it is
#     installed: its column is empty otherwise),
#   - the per-pixel oracle over the default bank (`glint-lab oracle`),
#   - with ARTIST=1, the local artist (`glint-lab navigate --simulate --local`) over the default
#     bank after 10 and after 30 strokes (docs/lab/navigation.md, "The local artist in detail").
# With CYCLES=1, also the two Cycles frames of tests/data/cycles/ (no half buffers: auto takes the
# image-only estimator; `glint-lab auto --bank`), against their 4096-spp reference.
# All SSIMs are glint::ssim (oracle, auto, apply, navigate, `glint-image diff --metric ssim`), full
# frame.
#   lab/scripts/oidn_compare.sh [build] [scenes...]
# Scenes: cornell pool dof glossy by default; any folder of scenes/ with a scene.json and its
# reference.exr, e.g. `fox` (the Khronos glTF Fox, on which no choice was tuned; its reference is
# rendered with seed 1000, no test seed).
# Environment: SPPS (default "4 16 64"), SEEDS (render seeds, default 7), OIDN (the installed peer's
# folder, default /tmp/oidn), ARTIST (1: the local artist's columns), ARTIST_FLAGS (more flags for
# navigate, e.g. "--start best"), CYCLES (1: the Cycles rows), KEEP (a folder: each cell's JSON
# outputs are kept there as SCENE-SPP-SEED-{oracle,auto,auto-classical,unet,oidn,artist}.json).
set -euo pipefail
source "$(dirname "$0")/lib/cells.sh"
spps=${SPPS:-4 16 64}
seeds=${SEEDS:-7}
oidn=${OIDN:-/tmp/oidn}
artist=${ARTIST:-0}
cycles=${CYCLES:-0}
classical=gaussian,bilateral,bilateral-mc,cross-bilateral,guided,nlmeans
have_oidn=0
if [ -f "$oidn/oidn_peer.js" ] && [ -d "$oidn/node_modules" ] && command -v node >/dev/null; then
  have_oidn=1
else
  echo "note: no OIDN peer installed at $oidn (see ../shared/peers/oidn/README.md): the OIDN column is empty" >&2
fi
header="| scene | spp | seed | auto, classical bank | auto with unet | unet alone | OIDN | per-pixel oracle (with unet) |"
rule="|---|---|---|---|---|---|---|---|"
if [ "$artist" = 1 ]; then
  header="$header local artist, 10 strokes | local artist, 30 strokes | start |"
  rule="$rule---|---|---|"
fi
echo "$header"
echo "$rule"

# OIDN on $1 (an EXR) with the colour, albedo and normal channels named by $2 $3 $4 (comma lists,
# empty: the default layer's R,G,B), SSIM against $5 into $work/oidn.json.
run_oidn() {
  local in=$1 color=$2 albedo=$3 normal=$4 ref=$5
  echo '{}' >"$work/oidn.json"
  [ "$have_oidn" = 1 ] || return 0
  # OIDN reads PFM: the colour, albedo and normal (in [-1, 1]) of the full render.
  /usr/bin/python3 "$oidn/exr_to_pfm.py" "$in" "$work/color.pfm" ${color:+--channels "$color"} >/dev/null
  /usr/bin/python3 "$oidn/exr_to_pfm.py" "$in" "$work/albedo.pfm" --channels "$albedo" >/dev/null
  /usr/bin/python3 "$oidn/exr_to_pfm.py" "$in" "$work/normal.pfm" --channels "$normal" >/dev/null
  node "$oidn/oidn_peer.js" --color "$work/color.pfm" --albedo "$work/albedo.pfm" \
    --normal "$work/normal.pfm" --out "$work/oidn.pfm" --hdr --quiet
  /usr/bin/python3 "$oidn/pfm_to_exr.py" "$work/oidn.pfm" "$work/oidn.exr" >/dev/null
  "$bin/glint-image" diff "$work/oidn.exr" --reference "$ref" --metric ssim \
    --json >"$work/oidn.json"
}

# One row: the banks of $work/in.exr (default and classical), auto over each, unet alone, OIDN,
# the oracle; $1 scene label, $2 spp, $3 seed, $4 reference, $5 1 for a render with half buffers.
row() {
  local label=$1 spp=$2 seed=$3 ref=$4 halves=$5
  "$bin/glint-denoise" bank "$work/in.exr" --out "$work/bank" --size 64 --seed 1 >/dev/null
  "$bin/glint-denoise" bank "$work/in.exr" --out "$work/bank-classical" --size 64 --seed 1 \
    --filters "$classical" >/dev/null
  # The oracle's auto column is auto with its defaults over the bank (the halves estimator); a
  # frame without half buffers gets it from `glint-lab auto` (the image-only estimator).
  "$bin/glint-lab" oracle "$work/in.exr" --reference "$ref" --bank "$work/bank" \
    --json >"$work/oracle.json"
  if [ "$halves" = 1 ]; then
    "$bin/glint-lab" oracle "$work/in.exr" --reference "$ref" --bank "$work/bank-classical" \
      --json >"$work/oracle-classical.json"
    python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
for oracle, auto in (("oracle", "auto"), ("oracle-classical", "auto-classical")):
    column = json.load(open("%s/%s.json" % (work, oracle)))["auto"]
    json.dump({"estimator": column["estimator"], "metrics": {"ssim": column["ssim"]}},
              open("%s/%s.json" % (work, auto), "w"))
PY
  else
    "$bin/glint-lab" auto "$work/in.exr" --bank "$work/bank" --reference "$ref" \
      --out "$work/auto.exr" --json 2>/dev/null >"$work/auto.json"
    "$bin/glint-lab" auto "$work/in.exr" --bank "$work/bank-classical" --reference "$ref" \
      --out "$work/auto-classical.exr" --json 2>/dev/null >"$work/auto-classical.json"
  fi
  "$bin/glint-denoise" apply "$work/in.exr" --filter unet --reference "$ref" \
    --out "$work/unet.exr" --json >"$work/unet.json"
  echo '{}' >"$work/artist.json"
  if [ "$artist" = 1 ]; then
    # shellcheck disable=SC2086
    "$bin/glint-lab" navigate "$work/in.exr" --bank "$work/bank" --reference "$ref" \
      --simulate --local --strokes 30 ${ARTIST_FLAGS:-} --json >"$work/artist.json"
  fi
  python3 - "$label" "$spp" "$seed" "$work" "$halves" <<'PY'
import json, sys
scene, spp, seed, work, halves = sys.argv[1:]
load = lambda name: json.load(open(work + "/" + name + ".json"))
o, d, a = load("oracle"), load("oidn"), load("artist")
auto, classical, unet = load("auto"), load("auto-classical"), load("unet")
want = "halves" if halves == "1" else "image"
assert auto["estimator"] == want and classical["estimator"] == want, (auto, classical)
row = "| %s | %s | %s | %.4f | %.4f | %.4f | %s | %.4f |" % (
    scene, spp, seed, classical["metrics"]["ssim"], auto["metrics"]["ssim"],
    unet["metrics"]["ssim"], "%.4f" % d["value"] if "value" in d else "", o["perPixel"])
if a:
    after = {s["stroke"]: s["ssim"] for s in a["strokes"]}
    last = lambda n: after[max(k for k in after if k <= n)] if after else a["start"]["ssim"]
    row += " %.4f | %.4f | %s %.4f |" % (last(10), last(30), a["start"]["kind"], a["start"]["ssim"])
print(row, flush=True)
PY
  if [ -n "${KEEP:-}" ]; then
    mkdir -p "$KEEP"
    for name in oracle auto auto-classical unet oidn artist; do
      cp "$work/$name.json" "$KEEP/${label// /_}-$spp-$seed-$name.json"
    done
  fi
  rm -rf "$work/bank" "$work/bank-classical"
}

for scene in $scenes; do
  for spp in $spps; do
    for seed in $seeds; do
      ref="scenes/$scene/reference.exr"
      "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "$seed" --set halfBuffers=true \
        --out "$work/in.exr" >/dev/null 2>&1
      run_oidn "$work/in.exr" "" albedo.R,albedo.G,albedo.B normal.X,normal.Y,normal.Z "$ref"
      row "$scene" "$spp" "$seed" "$ref" 1
    done
  done
done

if [ "$cycles" = 1 ]; then
  ref=tests/data/cycles/cornell_reference.exr
  for seed in 1 2; do
    cp "tests/data/cycles/cornell_8spp_seed$seed.exr" "$work/in.exr"
    run_oidn "$work/in.exr" ViewLayer.Combined.R,ViewLayer.Combined.G,ViewLayer.Combined.B \
      "ViewLayer.Denoising Albedo.R,ViewLayer.Denoising Albedo.G,ViewLayer.Denoising Albedo.B" \
      "ViewLayer.Denoising Normal.X,ViewLayer.Denoising Normal.Y,ViewLayer.Denoising Normal.Z" "$ref"
    row "Cycles cornell" 8 "$seed" "$ref" 0
  done
fi
