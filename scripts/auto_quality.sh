#!/usr/bin/env bash
# The auto-start quality table of docs/navigation.md ("Automatic start by SURE"): for cornell,
# pool, dof and glossy at 4, 16 and 64 spp (seed 1), a 64-member bank (seed 1) and the oracle
# measures with the SURE auto composite (default options), SSIM on display values against the
# committed references. Same machinery as scripts/navigation_quality.sh.
#   scripts/auto_quality.sh [build] [scenes...]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
scenes=${*:-cornell pool dof glossy}
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| scene | spp | noisy | best single (with the reference) | auto (SURE, without it) | best 3 | per-pixel | auto's share of the way from best single to per-pixel | members used | auto s |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for scene in $scenes; do
  for spp in 4 16 64; do
    "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed 1 --out "$work/$scene.exr" >/dev/null 2>&1
    "$bin/glint-denoise" bank "$work/$scene.exr" --out "$work/bank_$scene" --size 64 --seed 1 >/dev/null
    oracle=$("$bin/glint-denoise" oracle "$work/$scene.exr" --reference "scenes/$scene/reference.exr" \
             --bank "$work/bank_$scene" --json)
    python3 - "$scene" "$spp" "$oracle" <<'PY'
import json, sys
scene, spp, o = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
a = o["auto"]
share = (a["ssim"] - o["bestSingle"]) / (o["perPixel"] - o["bestSingle"]) if o["perPixel"] > o["bestSingle"] else 0.0
print("| %s | %s | %.4f | %.4f (%s) | %.4f | %.4f | %.4f | %+.0f %% | %d | %.2f |" % (
    scene, spp, o["noisy"], o["bestSingle"], o["bestMember"]["filter"], a["ssim"], o["best3"],
    o["perPixel"], 100 * share, a["membersUsed"], a["seconds"]))
PY
    rm -rf "$work/bank_$scene"
  done
done
