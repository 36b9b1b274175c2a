#!/usr/bin/env bash
# One task of glint-farm's bank array job: members [k*C, (k+1)*C) into the shared folder.
# On failure the task requeues itself (only this part reruns), at most $GLINT_RETRIES times.
set -uo pipefail
k="${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}"
attempt="${SLURM_RESTART_COUNT:-0}"
first=$((k * GLINT_CHUNK)) end=$(((k + 1) * GLINT_CHUNK))
echo "glint-farm: bank part $k members $first:$end attempt $attempt on $(hostname)"
args=("$GLINT_INPUT" --size "$GLINT_SIZE" --seed "$GLINT_SEED" --out "$GLINT_WORK" --json)
[ -n "$GLINT_FILTERS" ] && args+=(--filters "$GLINT_FILTERS")
rc=0
if [ "${GLINT_FARM_FAIL_ONCE:-}" = "$k" ] && [ "$attempt" = 0 ]; then
  echo "glint-farm: injected failure" >&2; rc=1
else
  "$GLINT_BIN/glint-denoise" bank "${args[@]}" --members "$first:$end" \
    >"$GLINT_WORK/part-$k.json" || rc=$?
fi
if [ "$rc" -ne 0 ] && [ "$attempt" -lt "$GLINT_RETRIES" ]; then
  echo "glint-farm: part $k failed ($rc); requeueing it" >&2
  scontrol requeue "${SLURM_ARRAY_JOB_ID}_${k}"
  sleep 60
fi
exit "$rc"
