#!/usr/bin/env bash
# Whether the studio's render bar should render half buffers by default (docs/lab/studio-halves.md):
# each scene rendered with and without them at the same spp and seed, then what the artist gets
# from it — the first image's filter (unet at its defaults) and Auto Start (glint-denoise auto with
# its defaults: the halves' cross-validation when the render has them, SURE from the variance
# layer when not) — as relMSE and SSIM against the scene's committed reference. The duck (a
# Khronos asset no one here made, scenes/assets/duck) gets a 1024-spp reference rendered here
# (seed 1000).
#   lab/bench/studio_halves.sh [build] [scenes...]
# Environment: SEEDS (default "41 42"), SPPS (default "4 16"), WORK (scratch folder, default a
# temporary one). Prints one line per scene, spp, seed and halves: relMSE / SSIM of the raw
# render, of unet and of auto.
set -euo pipefail
build=${1:-build}
shift || true
scenes=${*:-cornell glossy dof pool duck}
seeds=${SEEDS:-41 42}
spps=${SPPS:-4 16}
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
bin=$build/bin
metric() { "$bin/glint-image" diff "$1" --reference "$2" --metric "$3" 2>/dev/null | awk 'NR==1{print $2}'; }
printf '%-8s %4s %4s %-6s %22s %22s %22s\n' scene spp seed halves "raw relMSE/SSIM" \
    "unet relMSE/SSIM" "auto relMSE/SSIM"
for scene in $scenes; do
    if [ "$scene" = duck ]; then
        input=scenes/assets/duck/Duck.glb
        ref=$work/duck-reference.exr
        [ -f "$ref" ] || "$bin/glint-render" "$input" --spp 1024 --seed 1000 --threads 2 \
            --out "$ref" >/dev/null 2>&1
    else
        input=scenes/$scene/scene.json
        ref=scenes/$scene/reference.exr
    fi
    for spp in $spps; do
        for seed in $seeds; do
            for halves in false true; do
                f=$work/$scene-$spp-$seed-$halves
                "$bin/glint-render" "$input" --spp "$spp" --seed "$seed" --threads 2 \
                    --set "halfBuffers=$halves" --out "$f.exr" >/dev/null 2>&1
                "$bin/glint-denoise" apply "$f.exr" --filter unet --out "$f.unet.exr" >/dev/null
                "$bin/glint-denoise" auto "$f.exr" --out "$f.auto.exr" >/dev/null 2>&1
                cells=()
                for out in "$f.exr" "$f.unet.exr" "$f.auto.exr"; do
                    cells+=("$(metric "$out" "$ref" relmse) / $(metric "$out" "$ref" ssim)")
                done
                printf '%-8s %4s %4s %-6s %22s %22s %22s\n' "$scene" "$spp" "$seed" "$halves" \
                    "${cells[0]}" "${cells[1]}" "${cells[2]}"
            done
        done
    done
done
