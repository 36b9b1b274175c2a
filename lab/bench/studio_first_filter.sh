#!/usr/bin/env bash
# Which filter the studio's first denoise should use (docs/lab/studio.md, "Which filter
# denoises the first image"): SSIM against each scene's committed reference of cross-bilateral (its defaults, the
# studio's first layer until issue 46) and unet (its defaults), at the studio's 16 spp, on render
# seeds no choice was tuned on.
#   lab/bench/studio_first_filter.sh [build] [scenes...]
# Environment: SEEDS (default "7 8 9"), SPP (default 16), WORK (scratch folder, default a temporary
# one), FILTERS (default "cross-bilateral unet"; the studio's candidates since issue 48:
# "unet cross-bilateral nlmeans guided", docs/lab/first-denoise.md). Prints one line per scene and
# seed: scene seed spp ssim(noisy) and the SSIM of each filter's defaults.
set -euo pipefail
build=${1:-build}
shift || true
scenes=${*:-cornell pool dof glossy}
seeds=${SEEDS:-7 8 9}
spp=${SPP:-16}
work=${WORK:-$(mktemp -d)}
ssim() { "$build/bin/glint-image" diff "$1" --reference "$2" --metric ssim 2>/dev/null | awk '{print $NF}'; }
filters=${FILTERS:-cross-bilateral unet}
printf '%-8s %4s %4s %8s' scene seed spp noisy
for f in $filters; do printf ' %16s' "$f"; done
echo
for s in $scenes; do
  ref="scenes/$s/reference.exr"
  for seed in $seeds; do
    in="$work/$s-$seed.exr"
    "$build/bin/glint-render" "scenes/$s/scene.json" --spp "$spp" --seed "$seed" --out "$in" >/dev/null 2>&1
    printf '%-8s %4s %4s %8s' "$s" "$seed" "$spp" "$(ssim "$in" "$ref")"
    for f in $filters; do
      "$build/bin/glint-denoise" apply "$in" --filter "$f" --out "$work/$s-$seed-$f.exr" >/dev/null 2>&1
      printf ' %16s' "$(ssim "$work/$s-$seed-$f.exr" "$ref")"
    done
    echo
  done
done
