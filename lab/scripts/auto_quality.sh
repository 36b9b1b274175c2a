#!/usr/bin/env bash
# The auto-start quality table of docs/auto.md ("Quality"): for cornell, pool, dof and glossy at 4,
# 16 and 64 spp (seed 1), a render with half buffers, a 64-member bank (seed 1) and the oracle with
# the auto composite (its default estimator: cross-validation on the halves), plus auto with SURE on
# the same render; then the same scene rendered without half buffers (noisy, best single and auto by
# SURE: the cost of splitting the samples, and the SURE table). SSIM on display values against the
# committed references. Same machinery as lab/scripts/navigation_quality.sh.
#   lab/scripts/auto_quality.sh [build] [scenes...]
set -euo pipefail
source "$(dirname "$0")/lib/cells.sh"
echo "| scene | spp | noisy | best single (with the reference) | auto, halves | auto, SURE | best 3 | per-pixel | halves' share of the way from best single to per-pixel | members used | auto s | without half buffers: noisy, best single, auto (SURE) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
for scene in $scenes; do
  for spp in 4 16 64; do
    for kind in plain halves; do
      flags=""
      [ "$kind" = halves ] && flags="--set halfBuffers=true"
      "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed 1 $flags \
        --out "$work/$kind.exr" >/dev/null 2>&1
      "$bin/glint-denoise" bank "$work/$kind.exr" --out "$work/bank_$kind" --size 64 --seed 1 >/dev/null
      "$bin/glint-lab" oracle "$work/$kind.exr" --reference "scenes/$scene/reference.exr" \
        --bank "$work/bank_$kind" --json >"$work/oracle_$kind.json"
    done
    "$bin/glint-lab" auto "$work/halves.exr" --bank "$work/bank_halves" --estimator sure \
      --reference "scenes/$scene/reference.exr" --out "$work/sure.exr" --json >"$work/sure.json"
    python3 - "$scene" "$spp" "$work" <<'PY'
import json, sys
scene, spp, work = sys.argv[1], sys.argv[2], sys.argv[3]
o = json.load(open(work + "/oracle_halves.json"))
p = json.load(open(work + "/oracle_plain.json"))
s = json.load(open(work + "/sure.json"))
a = o["auto"]
assert a["estimator"] == "halves", a
share = (a["ssim"] - o["bestSingle"]) / (o["perPixel"] - o["bestSingle"]) if o["perPixel"] > o["bestSingle"] else 0.0
assert p["auto"]["estimator"] == "sure", p["auto"]
print("| %s | %s | %.4f | %.4f (%s) | %.4f | %.4f | %.4f | %.4f | %+.0f %% | %d | %.2f | %.4f, %.4f, %.4f |" % (
    scene, spp, o["noisy"], o["bestSingle"], o["bestMember"]["filter"], a["ssim"],
    s["metrics"]["ssim"], o["best3"], o["perPixel"], 100 * share, a["membersUsed"], a["seconds"],
    p["noisy"], p["bestSingle"], p["auto"]["ssim"]))
PY
    rm -rf "$work"/bank_*
  done
done
