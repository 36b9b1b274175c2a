#!/usr/bin/env bash
# Glint against Open Image Denoise (docs/auto.md, "Against OIDN"): for each scene, spp and render
# seed, a render with half buffers, its 64-member bank (seed 1), and SSIM on display values against
# the committed reference of
#   - auto (the halves estimator, its defaults) and the per-pixel oracle (`glint-denoise oracle`),
#   - OIDN's RT filter with albedo and normal, HDR (the peer of ../shared/peers/oidn, when it is
#     installed: its column is empty otherwise),
#   - with ARTIST=1, the local artist (`glint-denoise navigate --simulate --local`) after 10 and
#     after 30 strokes (docs/navigation.md, "The local artist").
# All SSIMs are glint::ssim (oracle, navigate, `glint-image diff --metric ssim`), full frame.
#   tests/perf/oidn_compare.sh [build] [scenes...]
# Environment: SPPS (default "4 16 64"), SEEDS (render seeds, default 7), OIDN (the installed peer's
# folder, default /tmp/oidn), ARTIST (1: the local artist's columns), ARTIST_FLAGS (more flags for
# navigate, e.g. "--start best").
set -euo pipefail
source "$(dirname "$0")/../../scripts/lib/cells.sh"
spps=${SPPS:-4 16 64}
seeds=${SEEDS:-7}
oidn=${OIDN:-/tmp/oidn}
artist=${ARTIST:-0}
have_oidn=0
if [ -f "$oidn/oidn_peer.js" ] && [ -d "$oidn/node_modules" ] && command -v node >/dev/null; then
  have_oidn=1
else
  echo "note: no OIDN peer installed at $oidn (see ../shared/peers/oidn/README.md): the OIDN column is empty" >&2
fi
header="| scene | spp | seed | Glint auto (halves) | OIDN | Glint per-pixel oracle |"
rule="|---|---|---|---|---|---|"
if [ "$artist" = 1 ]; then
  header="$header local artist, 10 strokes | local artist, 30 strokes | start |"
  rule="$rule---|---|---|"
fi
echo "$header"
echo "$rule"
for scene in $scenes; do
  for spp in $spps; do
    for seed in $seeds; do
      ref="scenes/$scene/reference.exr"
      "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "$seed" --half-buffers \
        --out "$work/in.exr" >/dev/null 2>&1
      "$bin/glint-denoise" bank "$work/in.exr" --out "$work/bank" --size 64 --seed 1 >/dev/null
      "$bin/glint-denoise" oracle "$work/in.exr" --reference "$ref" --bank "$work/bank" \
        --json >"$work/oracle.json"
      echo '{}' >"$work/oidn.json"
      if [ "$have_oidn" = 1 ]; then
        # OIDN reads PFM: the colour, albedo and normal (in [-1, 1]) of the full render.
        /usr/bin/python3 "$oidn/exr_to_pfm.py" "$work/in.exr" "$work/color.pfm" >/dev/null
        /usr/bin/python3 "$oidn/exr_to_pfm.py" "$work/in.exr" "$work/albedo.pfm" --layer albedo >/dev/null
        /usr/bin/python3 "$oidn/exr_to_pfm.py" "$work/in.exr" "$work/normal.pfm" \
          --channels normal.X,normal.Y,normal.Z >/dev/null
        node "$oidn/oidn_peer.js" --color "$work/color.pfm" --albedo "$work/albedo.pfm" \
          --normal "$work/normal.pfm" --out "$work/oidn.pfm" --hdr --quiet
        /usr/bin/python3 "$oidn/pfm_to_exr.py" "$work/oidn.pfm" "$work/oidn.exr" >/dev/null
        "$bin/glint-image" diff "$work/oidn.exr" --reference "$ref" --metric ssim \
          --json >"$work/oidn.json"
      fi
      echo '{}' >"$work/artist.json"
      if [ "$artist" = 1 ]; then
        # shellcheck disable=SC2086
        "$bin/glint-denoise" navigate "$work/in.exr" --bank "$work/bank" --reference "$ref" \
          --simulate --local --strokes 30 ${ARTIST_FLAGS:-} --json >"$work/artist.json"
      fi
      python3 - "$scene" "$spp" "$seed" "$work" <<'PY'
import json, sys
scene, spp, seed, work = sys.argv[1:]
o = json.load(open(work + "/oracle.json"))
d = json.load(open(work + "/oidn.json"))
a = json.load(open(work + "/artist.json"))
assert o["auto"]["estimator"] == "halves", o["auto"]
row = "| %s | %s | %s | %.4f | %s | %.4f |" % (
    scene, spp, seed, o["auto"]["ssim"], "%.4f" % d["value"] if "value" in d else "",
    o["perPixel"])
if a:
    after = {s["stroke"]: s["ssim"] for s in a["strokes"]}
    last = lambda n: after[max(k for k in after if k <= n)] if after else a["start"]["ssim"]
    row += " %.4f | %.4f | %s %.4f |" % (last(10), last(30), a["start"]["kind"], a["start"]["ssim"])
print(row, flush=True)
PY
      rm -rf "$work/bank"
    done
  done
done
