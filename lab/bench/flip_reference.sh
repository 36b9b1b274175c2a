#!/bin/sh
# Reference FLIP means for tests/image/flip_test.cpp from the authors' implementation.
#   lab/bench/flip_reference.sh /path/to/NVlabs-flip-checkout
# Compiles lab/bench/flip_reference.cpp against <checkout>/src/cpp/FLIP.h (the same code the
# authors' Python package flip-evaluator wraps) and prints the table rows.
set -eu
flip=${1:?usage: $0 FLIP_CHECKOUT}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
g++ -std=c++17 -O2 -I"$flip/src/cpp" -I"$here/../../tests/image" "$here/flip_reference.cpp" -o "$out/flip_reference"
"$out/flip_reference"
