#!/usr/bin/env bash
# One task of glint-farm's render array job: shard $SLURM_ARRAY_TASK_ID of $GLINT_PARTS.
# On failure the task requeues itself (only this task reruns), at most $GLINT_RETRIES times.
# GLINT_FARM_FAIL_ONCE=i makes shard i fail its first attempt (the requeue test).
set -uo pipefail
i="${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}"
attempt="${SLURM_RESTART_COUNT:-0}"
out="$GLINT_WORK/shard-$i-of-$GLINT_PARTS.exr"
echo "glint-farm: shard $i/$GLINT_PARTS attempt $attempt on $(hostname) at $(date +%s.%N)"
if [ -f "$out" ]; then echo "glint-farm: $out is there already"; exit 0; fi
rc=0
if [ "${GLINT_FARM_FAIL_ONCE:-}" = "$i" ] && [ "$attempt" = 0 ]; then
  echo "glint-farm: injected failure" >&2; rc=1
else
  # shellcheck disable=SC2086  # GLINT_RENDER_ARGS is a list of options
  "$GLINT_BIN/glint-render" "$GLINT_INPUT" --spp "$GLINT_SPP" --seed "$GLINT_SEED" \
    --shard "$i/$GLINT_PARTS" --threads "$GLINT_THREADS" --out "$out" --json \
    $GLINT_RENDER_ARGS >"$GLINT_WORK/shard-$i.json" || rc=$?
fi
if [ "$rc" -ne 0 ] && [ "$attempt" -lt "$GLINT_RETRIES" ]; then
  echo "glint-farm: shard $i failed ($rc); requeueing it" >&2
  scontrol requeue "${SLURM_ARRAY_JOB_ID}_${i}"
  sleep 60  # Slurm stops this attempt
fi
exit "$rc"
