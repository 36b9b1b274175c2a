#!/usr/bin/env bash
# glint-final's cheapest plan (its fallback at the final auto's deadline) with and without the
# render itself (the identity filter), against the render and the default bank
# (docs/lab/cheapest-plan.md). For each scene: a render with half buffers, either
# at a fixed spp or for a time, then auto on it four ways, each against scenes/S/reference.exr.
# Prints one TSV row per render: scene, seed, mean spp, and the relMSE of the render, of fast with
# one cross-bilateral member, of the same with the identity (today's cheapestPlan()), of fast with
# one member of the default bank and of balanced.
#   lab/scripts/cheapest_plan.sh [--build DIR] [--seed N] [--spp N | --seconds T] SCENE...
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build seed=86 spp=0 seconds=13
scenes=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
[ ${#scenes[@]} -gt 0 ] || { echo "usage: $0 [--build DIR] [--seed N] [--spp N | --seconds T] SCENE..." >&2; exit 2; }
bin=$build/bin
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
relmse() { "$bin/glint-image" diff "$1" --reference "scenes/$2/reference.exr" --metric relmse | awk 'NR == 1 {print $2}'; }
echo -e "scene\tseed\tspp\trender\tcross-bilateral\tcross-bilateral+identity\tfast:1\tbalanced"
for scene in "${scenes[@]}"; do
  in=$work/$scene.exr
  if [ "$spp" -gt 0 ]; then
    "$bin/glint-render" "scenes/$scene/scene.json" --spp "$spp" --seed "$seed" --threads 2 \
      --set halfBuffers=true --out "$in" >/dev/null 2>&1
  else
    "$bin/glint-render" "scenes/$scene/scene.json" --spp 1000000 --time-limit "$seconds" \
      --seed "$seed" --threads 2 --set halfBuffers=true --out "$in" >/dev/null 2>&1
  fi
  mean=$("$bin/glint-image" info "$in" --json | /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["metadata"]["spp"])' 2>/dev/null || echo "?")
  row="$scene\t$seed\t$mean\t$(relmse "$in" "$scene")"
  for plan in "--quality fast --size 1 --filters cross-bilateral" \
              "--quality fast --size 1 --filters cross-bilateral,identity" \
              "--quality fast --size 1" "--quality balanced"; do
    # shellcheck disable=SC2086
    "$bin/glint-lab" auto "$in" --out "$work/out.exr" $plan >/dev/null 2>&1
    row="$row\t$(relmse "$work/out.exr" "$scene")"
  done
  echo -e "$row"
done
