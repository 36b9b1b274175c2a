#!/usr/bin/env bash
# Where auto with the learned member loses to unet alone (= OIDN) or to auto over the classical
# bank (docs/lab/auto.md, "Against OIDN"): for each CELL (scene:spp:seed), the render of
# lab/scripts/oidn_compare.sh (half buffers, the same seed), its default bank (64 members, seed 1,
# unet among them) and SSIM against the committed reference of
#   - auto with its defaults, the share of the blend's weight unet holds, and auto's own single
#     choice (the member of smallest estimated error),
#   - auto without the stacking (--stack 0), and without the stacking and the feathering,
#   - the best single member chosen with the reference (`glint-lab oracle`), and the per-pixel
#     oracle.
#   lab/scripts/auto_unet_causes.sh [build] -- CELL...      e.g. -- cornell:4:7 glossy:16:21
set -euo pipefail
source "$(dirname "$0")/lib/cells.sh"
echo "| cell | auto | unet's share | auto's single choice | --stack 0 | --stack 0 --feather 0 | best single (with the reference) | unet alone | per-pixel |"
echo "|---|---|---|---|---|---|---|---|---|"
for cell in "${rest[@]}"; do
  IFS=: read -r scene spp seed <<<"$cell"
  ref="scenes/$scene/reference.exr"
  "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "$seed" --set halfBuffers=true \
    --out "$work/in.exr" >/dev/null 2>&1
  "$bin/glint-denoise" bank "$work/in.exr" --out "$work/bank" --size 64 --seed 1 >/dev/null
  "$bin/glint-lab" oracle "$work/in.exr" --reference "$ref" --bank "$work/bank" \
    --json >"$work/oracle.json"
  auto() { "$bin/glint-lab" auto "$work/in.exr" --bank "$work/bank" --reference "$ref" \
    --out "$work/a.exr" --json "$@" 2>/dev/null; }
  auto >"$work/auto.json"
  auto --stack 0 >"$work/nostack.json"
  auto --stack 0 --feather 0 >"$work/nofeather.json"
  "$bin/glint-denoise" apply "$work/in.exr" --filter unet --reference "$ref" \
    --out "$work/unet.exr" --json >"$work/unet.json"
  python3 - "$cell" "$work" <<'PY'
import json, sys
cell, work = sys.argv[1:]
load = lambda n: json.load(open("%s/%s.json" % (work, n)))
o, a, s, f, u = load("oracle"), load("auto"), load("nostack"), load("nofeather"), load("unet")
share = sum(l["share"] for l in a["layers"] if l["filter"] == "unet")
print("| %s | %.4f | %.2f | %s %.4f | %.4f | %.4f | %s %.4f | %.4f | %.4f |" % (
    cell, a["metrics"]["ssim"], share, a["bestMember"]["filter"], a["metricsBestMember"]["ssim"],
    s["metrics"]["ssim"], f["metrics"]["ssim"], o["bestMember"]["filter"], o["bestSingle"],
    u["metrics"]["ssim"], o["perPixel"]), flush=True)
PY
  rm -rf "$work/bank"
done
