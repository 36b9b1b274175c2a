#!/usr/bin/env bash
# ctest Report.Smoke: glint-report's part 5 on a tiny render (cornell at 32x32, 4 spp, two
# sigmas) writes a CSV with the expected columns, 2 sigmas x 4 patterns x 7 k rows and finite
# numbers, and leaves no temporary file behind. Needs neither blender nor matplotlib.
#   smoke_test.sh GLINT_REPORT SOURCE_DIR
set -euo pipefail
REPORT=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$REPORT" bilateral-mc "$SRC/scenes/cornell" --scale 8 --spp 4 --sigmas 5,40 \
  --out "$TMP/bilateral_mc.csv" 2>/dev/null
header=$(head -1 "$TMP/bilateral_mc.csv")
expected="sigma_s,radius,pattern,k,samples,seconds,exact_seconds,psnr"
[ "$header" = "$expected" ] || { echo "header '$header', expected '$expected'"; exit 1; }
rows=$(($(wc -l < "$TMP/bilateral_mc.csv") - 1))
[ "$rows" -eq 56 ] || { echo "$rows rows, expected 56"; exit 1; }
[ ! -e "$TMP/bilateral_mc.csv.tmp" ] || { echo "temporary file left behind"; exit 1; }
# Every number finite and positive; PSNR rises from k = 1 to k = 7 for every sigma and pattern.
awk -F, 'NR > 1 {
  for (i = 6; i <= 8; ++i)
    if ($i !~ /^[0-9.e+-]+$/ || $i + 0 <= 0) { print "bad value in line " NR ": " $0; bad = 1 }
  key = $1 "/" $3
  if ($4 == 1) first[key] = $8
  if ($4 == 7 && $8 + 0 <= first[key] + 0) { print "PSNR does not rise with k for " key; bad = 1 }
} END { exit bad }' "$TMP/bilateral_mc.csv"
echo "report smoke test: $rows rows, columns and values as expected"
