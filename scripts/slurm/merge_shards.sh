#!/usr/bin/env bash
# glint-farm's merge jobs, run once every job they depend on succeeded (afterok).
# As a task g of the partial-merge array (more than GLINT_FAN_IN shards): shards
# [g*F, min((g+1)*F, N)) into WORK/part-g-of-G.exr with `glint-image merge --partial`.
# Otherwise the final merge into GLINT_OUT: of every shard (N <= F), or of the G parts.
set -euo pipefail
n="$GLINT_PARTS" fan_in="${GLINT_FAN_IN:-$GLINT_PARTS}"
groups=$(( (n + fan_in - 1) / fan_in ))
part() { echo "$GLINT_WORK/part-$1-of-$groups.exr"; }
inputs=()
if [ -n "${SLURM_ARRAY_TASK_ID:-}" ]; then
  g="$SLURM_ARRAY_TASK_ID"
  first=$((g * fan_in)) end=$(( (g + 1) * fan_in < n ? (g + 1) * fan_in : n ))
  echo "glint-farm: partial merge $g of shards $first-$((end - 1))/$n on $(hostname)"
  out="$(part "$g")"
  if [ -f "$out" ]; then echo "glint-farm: $out is there already"; exit 0; fi
  for ((i = first; i < end; i++)); do inputs+=("$GLINT_WORK/shard-$i-of-$n.exr"); done
  "$GLINT_BIN/glint-image" merge "${inputs[@]}" --partial --out "$out" --json |
    tee "$GLINT_WORK/merge-part-$g.json"
elif [ "$n" -gt "$fan_in" ]; then
  for ((g = 0; g < groups; g++)); do inputs+=("$(part "$g")"); done
  "$GLINT_BIN/glint-image" merge "${inputs[@]}" --out "$GLINT_OUT" --json | tee "$GLINT_WORK/merge.json"
else
  for ((i = 0; i < n; i++)); do inputs+=("$GLINT_WORK/shard-$i-of-$n.exr"); done
  "$GLINT_BIN/glint-image" merge "${inputs[@]}" --out "$GLINT_OUT" --json | tee "$GLINT_WORK/merge.json"
fi
