#!/usr/bin/env bash
# The unet filter against the OIDN peer (docs/learned.md, "Equality with the peer"): for each scene,
# a 16-spp render (seed 7), the peer (../shared/peers/oidn installed in $OIDN, HDR, albedo and
# normal, quality balanced) and `glint-denoise apply --filter unet` on the same layers, compared by
# unet_vs_peer.py (mean |difference| / mean value < 1e-3, every display value within 1/255).
#   lab/bench/unet_peer_compare.sh [build] [scenes...]
# Environment: OIDN (the installed peer, default /tmp/oidn), WORK (scratch folder, default a
# temporary one), PARAMS (more --param flags for unet, e.g. "--param aux=clean"), PEER_FLAGS (the
# matching peer flags, e.g. "--clean-aux").
set -euo pipefail
build=${1:-build}
shift || true
scenes=${*:-cornell pool dof glossy}
oidn=${OIDN:-/tmp/oidn}
work=${WORK:-$(mktemp -d)}
here=$(cd "$(dirname "$0")" && pwd)
status=0
for s in $scenes; do
  in="$work/$s.exr"
  [ -f "$in" ] || "$build/bin/glint-render" "scenes/$s/scene.json" --spp 16 --seed 7 --out "$in" >/dev/null
  python3 "$oidn/exr_to_pfm.py" "$in" "$work/$s.color.pfm" >/dev/null
  python3 "$oidn/exr_to_pfm.py" "$in" "$work/$s.albedo.pfm" --layer albedo >/dev/null
  python3 "$oidn/exr_to_pfm.py" "$in" "$work/$s.normal.pfm" --layer normal >/dev/null
  # shellcheck disable=SC2086
  node "$oidn/oidn_peer.js" --color "$work/$s.color.pfm" --albedo "$work/$s.albedo.pfm" \
    --normal "$work/$s.normal.pfm" --hdr --quality balanced ${PEER_FLAGS:-} --quiet \
    --out "$work/$s.peer.pfm"
  # shellcheck disable=SC2086
  "$build/bin/glint-denoise" apply "$in" --filter unet ${PARAMS:-} --out "$work/$s.unet.exr" >/dev/null
  python3 "$oidn/exr_to_pfm.py" "$work/$s.unet.exr" "$work/$s.unet.pfm" >/dev/null
  python3 "$here/unet_vs_peer.py" "$work/$s.unet.pfm" "$work/$s.peer.pfm" "$s" || status=1
done
exit $status
