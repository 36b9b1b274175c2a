#!/usr/bin/env bash
# Runs every fuzz target for SECONDS each (default 600) on a corpus seeded from tests/fuzz/seeds/
# and the files under scenes/; crashes land in BUILD/fuzz-crashes/ (docs/reliability.md).
#   tests/fuzz/run.sh BUILD [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:?build folder}
seconds=${2:-600}
shift 2 || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(scene_json obj texture exr gltf tev denoise_input paint_script session bank_index shard_merge journal)
mkdir -p "$build/fuzz-crashes"
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  cp -n tests/fuzz/seeds/$t/* "$corpus/" 2>/dev/null || true
  case $t in
    scene_json) cp -n scenes/*/scene.json "$corpus/" 2>/dev/null || true
                for f in scenes/*/scene.json; do cp -n "$f" "$corpus/$(basename "$(dirname "$f")").json"; done ;;
    obj) for f in tests/render/data/cornell_box.obj scenes/textured/quad.obj scenes/door/door.obj; do
           cp -n "$f" "$corpus/$(basename "$f")"; done ;;
    gltf) for f in scenes/assets/*.glb scenes/assets/*/*.glb; do cp -n "$f" "$corpus/$(basename "$f")"; done ;;
    texture) for f in scenes/*/*.png; do
               # First byte 0 picks ".png" in the harness.
               printf '\000' | cat - "$f" > "$corpus/$(basename "$(dirname "$f")")-$(basename "$f")"; done ;;
  esac
  # A target's dictionary of keys and values (tests/fuzz/TARGET.dict), when it has one.
  dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  echo "== fuzz_$t for $seconds s"
  "$build/bin/fuzz_$t" "$corpus" "${dict[@]}" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=4096 \
      -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/fuzz-crashes/$t-" 2>&1 |
      grep -a -E "^#|Done|stat::|ERROR|SUMMARY|^(scene_json|obj|texture|exr|gltf):" | tail -12 || true
done
echo "crashes (if any): $(ls "$build/fuzz-crashes" | wc -l) file(s) in $build/fuzz-crashes"
