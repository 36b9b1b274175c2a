#!/usr/bin/env bash
# Runs every benchmark once with the settings the docs report (`make bench`). Each prints its own
# figures; peers (OpenCV, scikit-image, Blender/Cycles) run in the same invocation where an issue
# names one. Long equal-time MLT runs are left to docs/metropolis.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
bin=$build/bin
run() { echo; echo "== $*"; "$@"; }

run "$bin/bench_exr_io" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
run /usr/bin/python3 lab/bench/ssim_skimage.py "$bin/bench_ssim" --repeat 20
run "$bin/bench_render"
# The renderer against the previous release (lab/bench/previous_release.txt): a slower render
# fails `make bench` at the end, after the other benchmarks have run.
regression=0
run lab/bench/render_vs_previous.sh "$build" || regression=$?
run "$bin/bench_asset_load" write /tmp/glint-bench-asset.glb --triangles 4000000
run "$bin/bench_asset_load" load /tmp/glint-bench-asset.glb --threads 2
run "$bin/bench_texture"
run "$bin/bench_mlt" throughput tests/render/data/cornell.json --spp 32 --repeat 5 --threads 2
run "$bin/bench_denoise_a" --threads 2 --size 1024 --reps 5
run "$bin/bench_denoise_b"
run "$bin/bench_auto" --reps 3
if [ -x lab/bench/cycles/run_compare.sh ]; then
  run lab/bench/cycles/run_compare.sh "$build"
fi
exit "$regression"
