#!/usr/bin/env bash
# The committed scene files stay small (scenes/README.md): no file under scenes/ is over 1 MiB
# (the references are half float, zip- or pxr24-compressed; the largest, scenes/cornell/reference.exr, is 0.7 MB).
# Usage: scene_sizes.sh   (run from the repository root)
set -euo pipefail
limit=1048576
fail=0
while IFS= read -r -d '' file; do
  size=$(stat -c %s "$file")
  if [ "$size" -gt "$limit" ]; then
    echo "too large: $file ($size bytes, at most $limit)"
    fail=1
  fi
done < <(find scenes -type f -print0)
exit $fail
