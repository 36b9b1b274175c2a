#!/usr/bin/env bash
# glint-final of two builds paired on the same scenes, budgets and seeds (docs/research/
# freed-frames.md): which build runs first alternates with the seed's parity; each run's wall
# clock from the shell's start to the EXR, the loop's own seconds, the mean spp, the final plan
# as first planned, the relMSE after auto against scenes/S/reference.exr and the plan that ran
# (a late re-plan or the deadline's fallback may differ). One TSV row per run on stdout. A scene
# given by a path (a scene.json or an asset glint-final reads) is compared with REFERENCE.
#   lab/bench/final_paired.sh OLD_BUILD NEW_BUILD "BUDGETS" "SEEDS" "SCENES"
#   slot lab/bench/final_paired.sh /work/prev/build build "8" "91 92" "cornell dof glossy pool"
#   REFERENCE=duck.exr lab/bench/final_paired.sh OLD NEW "8" "91" scenes/assets/duck/Duck.glb
set -euo pipefail
(($# == 5)) || { echo "usage: $0 OLD_BUILD NEW_BUILD \"BUDGETS\" \"SEEDS\" \"SCENES\"" >&2; exit 2; }
root=$(cd "$(dirname "$0")/../.." && pwd)
old=$1 new=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'budget\tscene\tseed\tbuild\twall\tloop\tspp\tplan\trelmse\tran\n'
for budget in $3; do for seed in $4; do for scene in $5; do
    file=$root/scenes/$scene/scene.json reference=$root/scenes/$scene/reference.exr
    if [[ $scene == */* ]]; then
        file=$scene reference=${REFERENCE:?a scene given by a path needs REFERENCE=ITS_REFERENCE.exr}
    fi
    order=("$old" "$new")
    ((seed % 2 == 0)) && order=("$new" "$old")
    for build in "${order[@]}"; do
        name=old
        [[ $build == "$new" ]] && name=new
        start=$(date +%s.%N)
        log=$("$build/bin/glint-final" "$file" --time-limit "$budget" \
            --threads 2 --set maxDepth=8 --set seed="$seed" --out "$work/$name.exr" 2>&1)
        wall=$(echo "$(date +%s.%N) - $start" | bc)
        loop=$(grep -oP 'estimated relMSE [0-9.e+-]+ in \K[0-9.]+' <<<"$log" || true)
        spp=$(grep -oP '[0-9]+x[0-9]+, \K[0-9.]+(?= spp a pixel)' <<<"$log" | head -1 || true)
        plan=$(grep -oP 'final auto planned: \K.*' <<<"$log" | tail -1 || true)
        ran=$(grep -oP '^  final auto: \K.*' <<<"$log" | tail -1 || true)
        relmse=$("$new/bin/glint-image" diff "$work/$name.exr" \
            --reference "$reference" --metric relmse | awk '/^relmse/ {print $2}')
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$budget" "$scene" "$seed" "$name" \
            "$wall" "$loop" "$spp" "$plan" "$relmse" "$ran"
    done
done; done; done
