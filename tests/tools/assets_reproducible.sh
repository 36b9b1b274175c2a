#!/usr/bin/env bash
# The committed scene assets are exactly what the generators in tools/ write with the commands in
# scenes/README.md: meshes and PNGs byte for byte, EXRs pixel for pixel (OpenImageIO stamps a
# DateTime into EXR headers, so those are compared with idiff at zero tolerance).
# Usage: assets_reproducible.sh BIN_DIR   (run from the repository root)
set -euo pipefail
bin=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
same() {  # same GENERATED COMMITTED
  if ! cmp -s "$1" "$2"; then echo "differs: $2 (regenerate: see scenes/README.md)"; fail=1; fi
}
"$bin/glint-make-mesh" sphere --segments 48 --rings 24 --out "$tmp/s48.obj"
"$bin/glint-make-mesh" sphere --segments 48 --rings 24 --inward --out "$tmp/s48in.obj"
"$bin/glint-make-mesh" sphere --segments 32 --rings 16 --out "$tmp/s32.obj"
"$bin/glint-make-mesh" quad --out "$tmp/quad.obj"
same "$tmp/s48.obj" scenes/furnace/sphere.obj
same "$tmp/s48in.obj" scenes/furnace/sphere_inward.obj
same "$tmp/s32.obj" scenes/glossy/sphere.obj
same "$tmp/s48.obj" scenes/envmap/sphere.obj
same "$tmp/s48.obj" scenes/textured/sphere.obj
for s in glossy envmap textured; do same "$tmp/quad.obj" "scenes/$s/quad.obj"; done
"$bin/glint-make-texture" checker --size 512 --cells 128 --out "$tmp/floor512.png"
"$bin/glint-make-texture" checker --size 256 --cells 16 --out "$tmp/floor256.png"
same "$tmp/floor512.png" scenes/textured/floor.png
same "$tmp/floor256.png" scenes/dof/floor.png
mkdir "$tmp/pool"
"$bin/glint-make-pool" --out-dir "$tmp/pool" >/dev/null
for f in cloth.png stripe.png solid.png ball.obj cushion.obj; do same "$tmp/pool/$f" "scenes/pool/$f"; done
"$bin/glint-make-sky" --out "$tmp/sky.exr" >/dev/null
if ! idiff -fail 0 -warn 0 "$tmp/sky.exr" scenes/envmap/sky.exr >/dev/null; then
  echo "differs: scenes/envmap/sky.exr"; fail=1
fi
[ "$fail" -eq 0 ] && echo "all scene assets reproduced by tools/"
exit "$fail"
