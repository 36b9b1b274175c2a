#!/usr/bin/env bash
# Counts the flags of the product CLIs from their --help: each program's own options and each
# subcommand's (--help itself not counted; a positional is not a flag). Prints one line per
# program and subcommand and the total; with --max N, fails when the total is above N.
#   lab/checks/count_product_flags.sh [--max 70] build/bin/glint-image build/bin/glint-render … build/bin/glint-final
set -euo pipefail

max=
if [[ ${1:-} == --max ]]; then
    max=$2
    shift 2
fi
(($# > 0)) || { echo "usage: $0 [--max N] CLI..." >&2; exit 2; }

# The long options listed in one help text, up to its list of subcommands.
flags() {
    awk '/^Subcommands:/ { exit } { print }' |
        grep -oE '^ +(-[a-zA-Z],)?--[a-z0-9][-a-z0-9]*' | sed -E 's/.*--/--/' |
        grep -vx -- '--help' | sort -u || true
}

total=0
for cli in "$@"; do
    help=$("$cli" --help)
    subcommands=$(awk '/^Subcommands:/ { s = 1; next } s && /^  [a-z]/ { print $1 }' <<<"$help")
    n=$(flags <<<"$help" | grep -c . || true)
    echo "$(basename "$cli"): $n"
    total=$((total + n))
    for sub in $subcommands; do
        n=$("$cli" "$sub" --help | flags | grep -c . || true)
        echo "$(basename "$cli") $sub: $n"
        total=$((total + n))
    done
done
echo "total: $total${max:+ (at most $max)}"
if [[ -n $max ]] && ((total > max)); then
    echo "the product CLIs have $total flags, more than $max: move measurement flags to glint-lab"
    exit 1
fi
