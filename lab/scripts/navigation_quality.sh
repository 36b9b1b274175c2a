#!/usr/bin/env bash
# The quality table of docs/navigation.md: for cornell, pool and dof at 16 spp (seed 1), a
# 64-member bank (seed 1), the oracle measures and the simulated user's SSIM after each choice.
#   lab/scripts/navigation_quality.sh [build] [--prefilter]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
pre=${2:-}
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| scene | noisy | best single | best 3 | per-pixel | simulated user: SSIM after each choice (share of the best single gain) | choices to 90 % |"
echo "|---|---|---|---|---|---|---|"
for scene in cornell pool dof; do
  "$bin/glint-render" "scenes/$scene/scene.json" --spp 16 --seed 1 --out "$work/$scene.exr" >/dev/null 2>&1
  "$bin/glint-denoise" bank "$work/$scene.exr" --out "$work/bank_$scene" --size 64 --seed 1 $pre >/dev/null
  oracle=$("$bin/glint-lab" oracle "$work/$scene.exr" --reference "scenes/$scene/reference.exr" \
           --bank "$work/bank_$scene" --json)
  nav=$("$bin/glint-lab" navigate "$work/$scene.exr" --reference "scenes/$scene/reference.exr" \
        --bank "$work/bank_$scene" --simulate --json)
  python3 - "$scene" "$oracle" "$nav" <<'PY'
import json, sys
scene, o, n = sys.argv[1], json.loads(sys.argv[2]), json.loads(sys.argv[3])
steps = ", ".join("%.4f (%.0f %%)" % (c["ssim"], 100 * c["shareOfBestGain"]) for c in n["choices"])
within = n["choicesTo90PercentOfBestGain"]
print("| %s | %.4f | %.4f (%s) | %.4f | %.4f | %s | %s |" % (
    scene, o["noisy"], o["bestSingle"], o["bestMember"]["filter"], o["best3"], o["perPixel"],
    steps, within if within is not None else "not reached"))
PY
done
