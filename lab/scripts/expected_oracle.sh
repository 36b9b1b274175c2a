#!/usr/bin/env bash
# The expected-error oracle of docs/lab/oidn-gap.md ("What limits the share"): for cornell, pool, dof and
# glossy at 4, 16 and 64 spp, a render with half buffers (seed 1) and its 64-member bank (seed 1),
# as in lab/scripts/auto_quality.sh, plus seven more renders of the scene at the same spp (seeds 2-8);
# then `glint-lab oracle --expected` chooses per pixel by each member's error averaged over the
# eight renders, at radii 0, 2, 4 and 8. Prints the share of the way from the best single member to
# the per-pixel oracle per cell and the average (about 3 minutes on 2 cores).
#   lab/scripts/expected_oracle.sh [build] [scenes...]
set -euo pipefail
source "$(dirname "$0")/lib/cells.sh"
echo "| scene | spp | best single | per-pixel | expected error, radius 0 / 2 / 4 / 8 (share of the way) |"
echo "|---|---|---|---|---|"
for scene in $scenes; do
  for spp in 4 16 64; do
    "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed 1 --set halfBuffers=true \
      --out "$work/in.exr" >/dev/null 2>&1
    others=""
    for seed in 2 3 4 5 6 7 8; do
      "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "$seed" --set halfBuffers=true \
        --out "$work/r$seed.exr" >/dev/null 2>&1
      others="$others${others:+,}$work/r$seed.exr"
    done
    "$bin/glint-denoise" bank "$work/in.exr" --out "$work/bank" --size 64 --seed 1 >/dev/null
    "$bin/glint-lab" oracle "$work/in.exr" --reference "scenes/$scene/reference.exr" \
      --bank "$work/bank" --expected "$others" --json >"$work/$scene-$spp.json"
    python3 - "$scene" "$spp" "$work/$scene-$spp.json" <<'PY'
import json, sys
scene, spp, path = sys.argv[1:]
o = json.load(open(path))
e = o["expected"]
print("| %s | %s | %.4f | %.4f | %s |" % (scene, spp, o["bestSingle"], o["perPixel"], " / ".join(
    "%.4f (%+.0f %%)" % (s, 100 * f) for s, f in zip(e["ssim"], e["share"]))))
PY
    rm -rf "$work/bank"
  done
done
python3 - "$work" <<'PY'
import glob, json, sys
shares = [json.load(open(p))["expected"]["share"] for p in sorted(glob.glob(sys.argv[1] + "/*.json"))]
print("average share: " + " / ".join("%+.0f %%" % (100 * sum(s[i] for s in shares) / len(shares))
                                     for i in range(len(shares[0]))))
PY
