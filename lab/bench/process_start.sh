#!/usr/bin/env bash
# What a Glint command costs before its main() (docs/research/start-and-writing.md): the seconds
# of `--help` of each command-line tool, and of two empty programs, one linked to OpenImageIO
# alone and one to OpenEXR alone, built here in a temporary folder; the shared libraries each
# loads. RUNS runs each (default 5), the wall clock of each.
#   lab/bench/process_start.sh build            # slot lab/bench/process_start.sh build, as measured
set -euo pipefail
(($# == 1)) || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
build=$1
runs=${RUNS:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cat >"$work/oiio.cpp" <<'CPP'
#include <OpenImageIO/imageio.h>
int main(int argc, char**) { return argc > 9 && OIIO::ImageInput::open("x") ? 1 : 0; }
CPP
cat >"$work/exr.cpp" <<'CPP'
#include <OpenEXR/ImfRgbaFile.h>
int main(int argc, char**) { if (argc > 9) Imf::RgbaInputFile f("x"); return 0; }
CPP
c++ -O1 "$work/oiio.cpp" -o "$work/only-openimageio" -lOpenImageIO -lOpenImageIO_Util
c++ -O1 "$work/exr.cpp" -o "$work/only-openexr" -I/usr/include/OpenEXR -I/usr/include/Imath \
    -lOpenEXR-3_1 -lImath-3_1 -lIex-3_1
printf 'program\tlibraries\tseconds (each run)\n'
for program in "$build"/bin/glint-final "$build"/bin/glint-render "$build"/bin/glint-image \
    "$build"/bin/glint-denoise \
    "$work/only-openimageio" "$work/only-openexr"; do
    libraries=$(ldd "$program" | wc -l)
    times=()
    for ((i = 0; i < runs; ++i)); do
        start=$(date +%s.%N)
        "$program" --help >/dev/null 2>&1 || true
        times+=("$(echo "$(date +%s.%N) - $start" | bc | sed 's/^\./0./')")
    done
    printf '%s\t%s\t%s\n' "$(basename "$program")" "$libraries" "${times[*]}"
done
