#!/usr/bin/env bash
# The main job: render scenes/cornell at 16 spp, denoise it with a classical filter and with the
# learned one (unet), and compare each with the reference.
# Usage: scripts/demo.sh [BUILD_DIR]   (run by `make demo` after deps and build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin=$build/bin
scene=scenes/cornell/scene.json
ref=scenes/cornell/reference.exr
mkdir -p out

echo "== render: $scene at 16 spp"
"$bin/glint-render" "$scene" --spp 16 --seed 1 --out out/cornell-16spp.exr
"$bin/glint-image" convert out/cornell-16spp.exr out/cornell-16spp.png

echo "== denoise: cross-bilateral on the colour, guided by albedo, normal and depth"
"$bin/glint-denoise" apply out/cornell-16spp.exr --filter cross-bilateral \
    --out out/cornell-16spp-denoised.exr
"$bin/glint-image" convert out/cornell-16spp-denoised.exr out/cornell-16spp-denoised.png

echo "== denoise: unet, Open Image Denoise's learned network with its trained weights (docs/learned.md)"
"$bin/glint-denoise" apply out/cornell-16spp.exr --filter unet --out out/cornell-16spp-unet.exr
"$bin/glint-image" convert out/cornell-16spp-unet.exr out/cornell-16spp-unet.png

if [ -f "$ref" ]; then
  echo "== SSIM against the reference ($ref)"
  printf 'noisy:           '; "$bin/glint-image" diff out/cornell-16spp.exr --reference "$ref" --metric ssim
  printf 'cross-bilateral: '; "$bin/glint-image" diff out/cornell-16spp-denoised.exr --reference "$ref" --metric ssim
  printf 'unet (learned):  '; "$bin/glint-image" diff out/cornell-16spp-unet.exr --reference "$ref" --metric ssim
fi
echo "== outputs in out/: cornell-16spp.{exr,png}, cornell-16spp-denoised.{exr,png}, cornell-16spp-unet.{exr,png}"
