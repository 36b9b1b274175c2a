#!/usr/bin/env bash
# Fails (exit 1, naming each file and line) when a product source — under image/, renderer/,
# denoise/ or gui/ — includes a lab header (glint/lab/…, or any path through lab/). The product
# never depends on the lab; the lab depends on the product (docs/architecture.md).
#   lab/checks/product_includes_no_lab.sh SOURCE_DIR
#   lab/checks/product_includes_no_lab.sh --self-test SOURCE_DIR   # the check fails on a bad tree
set -euo pipefail

check() {
    local root=$1 hits
    hits=$(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]([^>"]*/)?(glint/lab/|lab/)' \
        --include='*.h' --include='*.hpp' --include='*.cpp' --include='*.cc' --include='*.inl' \
        "$root/image" "$root/renderer" "$root/denoise" "$root/gui" 2>/dev/null || true)
    if [[ -n $hits ]]; then
        echo "product sources include lab headers:"
        echo "$hits"
        return 1
    fi
    echo "no product source includes a lab header"
}

if [[ ${1:-} == --self-test ]]; then
    root=$2
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    for m in image renderer denoise gui; do mkdir -p "$tmp/$m"; done
    cp "$root/denoise/src/bank/navigation.cpp" "$tmp/denoise/navigation.cpp"
    check "$tmp" >/dev/null || { echo "self-test: a clean copy was refused"; exit 1; }
    printf '#include "glint/lab/oracle.h"\n' >>"$tmp/denoise/navigation.cpp"
    if check "$tmp" >/dev/null; then
        echo "self-test: an include of glint/lab/oracle.h was not caught"
        exit 1
    fi
    echo "self-test: the check catches a lab include"
    exit 0
fi
check "$1"
