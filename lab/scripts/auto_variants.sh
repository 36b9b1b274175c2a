#!/usr/bin/env bash
# The option tables of docs/lab/auto-notebook.md and the other renders' shares in docs/auto.md
# ("Quality"): for cornell, pool, dof and glossy at 4, 16 and 64 spp, the render with half buffers
# (seed 1) and its 64-member bank (seed 1), as in lab/scripts/auto_quality.sh; then `glint-lab auto`
# once per option set given after `--` (an empty string: the defaults). Prints one row per option
# set: SSIM per cell, how many cells are at least the best single member, and the average share of
# the way from the best single member to the per-pixel oracle (about 2 minutes on 2 cores, plus 15 s
# per option set). SEED=N renders with seed N instead of 1 (the bank keeps seed 1): the same table
# on other renders, to check defaults chosen on seed 1.
#   lab/scripts/auto_variants.sh [build] [scenes...] -- "" "--feather 0" "--feather 6 --feather-gate 10"
#   SEED=2 lab/scripts/auto_variants.sh build -- "" "--stack-smooth 0"
set -euo pipefail
source "$(dirname "$0")/lib/cells.sh"
[ ${#rest[@]} -gt 0 ] || rest=("")
for scene in $scenes; do
  for spp in 4 16 64; do
    cell="$work/$scene-$spp"
    mkdir -p "$cell"
    "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "${SEED:-1}" --set halfBuffers=true \
      --out "$cell/in.exr" >/dev/null 2>&1
    "$bin/glint-denoise" bank "$cell/in.exr" --out "$cell/bank" --size 64 --seed 1 >/dev/null
    "$bin/glint-lab" oracle "$cell/in.exr" --reference "scenes/$scene/reference.exr" \
      --bank "$cell/bank" --json >"$cell/oracle.json"
  done
done
echo "| options | $(for s in $scenes; do printf '%s 4 / 16 / 64 | ' "$s"; done)cells ≥ best single | share |"
echo "|---|$(for s in $scenes; do printf -- '---|'; done)---|---|"
index=0
for options in "${rest[@]}"; do
  index=$((index + 1))
  for scene in $scenes; do
    for spp in 4 16 64; do
      cell="$work/$scene-$spp"
      # shellcheck disable=SC2086  # the option set is split into words on purpose
      "$bin/glint-lab" auto "$cell/in.exr" --bank "$cell/bank" \
        --reference "scenes/$scene/reference.exr" --out "$cell/auto.exr" --json $options \
        >"$cell/auto-$index.json"
    done
  done
  python3 - "$work" "$index" "$options" $scenes <<'PY'
import json, sys
work, index, options, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
cols, shares, ok = [], [], 0
for scene in scenes:
    values = []
    for spp in (4, 16, 64):
        cell = "%s/%s-%d" % (work, scene, spp)
        o = json.load(open(cell + "/oracle.json"))
        s = json.load(open("%s/auto-%s.json" % (cell, index)))["metrics"]["ssim"]
        values.append("%.4f" % s)
        ok += s >= o["bestSingle"]
        gap = o["perPixel"] - o["bestSingle"]
        shares.append((s - o["bestSingle"]) / gap if gap > 0 else 0.0)
    cols.append(" / ".join(values))
print("| %s | %s | %d | %+.1f %% |" % ("`" + options + "`" if options else "defaults",
      " | ".join(cols), ok, 100 * sum(shares) / len(shares)))
PY
done
