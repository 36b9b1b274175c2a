#!/usr/bin/env bash
# Counts the lines of the reference docs: the Markdown pages directly in DOCS (docs/*.md; the
# lab's pages under docs/lab/ are not reference and are not counted). Prints one line per page,
# longest first, and the total; with --max N, fails when the total is above N (issue 47: the
# reference docs are at most 4,500 lines; measurement history belongs in docs/lab/).
#   lab/checks/count_reference_doc_lines.sh [--max 4500] docs
set -euo pipefail

max=
if [[ ${1:-} == --max ]]; then
    max=$2
    shift 2
fi
(($# == 1)) && [[ -d $1 ]] || { echo "usage: $0 [--max N] DOCS_DIR" >&2; exit 2; }

shopt -s nullglob
pages=("$1"/*.md)
total=0
for page in "${pages[@]}"; do
    n=$(wc -l <"$page")
    echo "$n $(basename "$page")"
    total=$((total + n))
done | sort -rn
for page in "${pages[@]}"; do
    total=$((total + $(wc -l <"$page")))
done
echo "total: $total${max:+ (at most $max)}"
if [[ -n $max ]] && ((total > max)); then
    echo "the reference docs hold $total lines, more than $max: move measurements, logs and test" \
         "inventories to docs/lab/ (one 'Measurements:' link per page)"
    exit 1
fi
