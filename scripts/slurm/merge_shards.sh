#!/usr/bin/env bash
# glint-farm's merge job: runs once every shard task succeeded (afterok).
set -euo pipefail
shards=()
for ((i = 0; i < GLINT_PARTS; i++)); do shards+=("$GLINT_WORK/shard-$i-of-$GLINT_PARTS.exr"); done
"$GLINT_BIN/glint-image" merge "${shards[@]}" --out "$GLINT_OUT" --json | tee "$GLINT_WORK/merge.json"
