#!/usr/bin/env bash
# glint-farm's last bank job (after every part succeeded): the part that completed the bank
# wrote index.json; should two parts have finished at the same instant and each missed the
# other, an empty range merges the partial indices now.
set -euo pipefail
if [ ! -f "$GLINT_WORK/index.json" ]; then
  args=("$GLINT_INPUT" --size "$GLINT_SIZE" --seed "$GLINT_SEED" --out "$GLINT_WORK" --json)
  [ -n "$GLINT_FILTERS" ] && args+=(--filters "$GLINT_FILTERS")
  "$GLINT_BIN/glint-denoise" bank "${args[@]}" --members 0:0 >"$GLINT_WORK/index-merge.json"
fi
test -f "$GLINT_WORK/index.json"
echo "glint-farm: bank index $GLINT_WORK/index.json"
