#!/usr/bin/env bash
# The renderer's speed against the previous release (docs/renderer.md, "Performance"): builds
# glint-render of the commit named in lab/bench/previous_release.txt (or REF) in a worktree
# under BUILD_DIR/previous-release, renders scenes/cornell with it and with BUILD_DIR's
# glint-render in alternating order (256², 64 spp, depth 8, 2 threads, seed 1), prints each
# run's samples/s and rays, the best of each binary, their ratio, and exits 1 when the rays
# differ or the ratio falls below 1 - NOISE. A benchmark, not a unit test (not in `make test`).
#   lab/bench/render_vs_previous.sh [BUILD_DIR] [REF]
#   REPEATS=5 NOISE=0.05 THREADS=2 SPP=64 lab/bench/render_vs_previous.sh build
# PREVIOUS=BIN compares with that glint-render instead (REF is then only its label): no git and
# no build, for a run where the repository is not at hand (a sandbox, `slot`).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
ref=${2:-$(grep -v '^\s*#' "$root/lab/bench/previous_release.txt" | awk 'NF {print $1; exit}')}
repeats=${REPEATS:-5}
noise=${NOISE:-0.05}
threads=${THREADS:-2}
spp=${SPP:-64}
scene=${SCENE:-$root/scenes/cornell/scene.json}
new=$build/bin/glint-render
[ -x "$new" ] || { echo "render_vs_previous: $new is not built" >&2; exit 2; }
if [ -n "${PREVIOUS:-}" ]; then
    old=$PREVIOUS
    commit=$ref
    [ -x "$old" ] || { echo "render_vs_previous: $old is not a program" >&2; exit 2; }
else
    commit=$(git -C "$root" rev-parse --verify "$ref^{commit}") ||
        { echo "render_vs_previous: no commit '$ref'" >&2; exit 2; }

    # The previous release's glint-render, built once per commit with this build's type.
    prev=$build/previous-release
    if [ ! -e "$prev/src/.git" ]; then
        git -C "$root" worktree add --detach --force "$prev/src" "$commit" > /dev/null
    elif [ "$(git -C "$prev/src" rev-parse HEAD)" != "$commit" ]; then
        git -C "$prev/src" checkout --quiet --detach "$commit"
    fi
    type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt" 2> /dev/null || true)
    if [ ! -f "$prev/build/CMakeCache.txt" ]; then
        cmake -S "$prev/src" -B "$prev/build" -G Ninja -DCMAKE_BUILD_TYPE="${type:-RelWithDebInfo}" \
            > "$prev/configure.log"
    fi
    cmake --build "$prev/build" -j "${JOBS:-2}" --target glint-render > "$prev/build.log" ||
        { tail -20 "$prev/build.log" >&2; exit 2; }
    old=$prev/build/bin/glint-render
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# One render: prints "samplesPerSecond rays".
# The depth as each binary takes it: --set maxDepth=8, or --max-depth 8 before the flags were
# folded into --set.
depth() {
    if "$1" --help | grep -q -- '--max-depth'; then echo --max-depth 8; else echo --set maxDepth=8; fi
}
render() {
    # shellcheck disable=SC2046
    "$1" "$scene" --spp "$spp" $(depth "$1") --threads "$threads" --seed 1 --json \
        --out "$work/$2.exr" |
        /usr/bin/python3 -c 'import json, sys; j = json.load(sys.stdin); print(j["samplesPerSecond"], j["rays"])'
}
echo "previous release $commit ($ref) against $build, $(basename "$scene") ${spp} spp," \
    "$threads threads, $repeats rounds"
: > "$work/runs"
for ((i = 1; i <= repeats; ++i)); do
    # Alternate which binary runs first, so that neither always meets the other's cache state.
    if ((i % 2)); then order="old new"; else order="new old"; fi
    for which in $order; do
        bin=$old
        [ "$which" = new ] && bin=$new
        result=$(render "$bin" "$which")
        read -r sps rays <<< "$result"
        printf '  round %d %-3s %.3f M samples/s  %s rays\n' "$i" "$which" \
            "$(echo "$sps" | awk '{print $1 * 1e-6}')" "$rays"
        echo "$which $sps $rays" >> "$work/runs"
    done
done
/usr/bin/python3 - "$work/runs" "$noise" "$commit" <<'PY'
import json, statistics, sys
runs = [line.split() for line in open(sys.argv[1])]
noise = float(sys.argv[2])
rate = {w: [float(s) for k, s, _ in runs if k == w] for w in ("old", "new")}
rays = {w: {int(r) for k, _, r in runs if k == w} for w in ("old", "new")}
best = {w: max(v) for w, v in rate.items()}
median = {w: statistics.median(v) for w, v in rate.items()}
ratio = best["new"] / best["old"]
print(json.dumps({"previous": sys.argv[3],
                  "previousSamplesPerSecond": {"best": best["old"], "median": median["old"]},
                  "samplesPerSecond": {"best": best["new"], "median": median["new"]},
                  "ratio": round(ratio, 4), "medianRatio": round(median["new"] / median["old"], 4),
                  "previousRays": sorted(rays["old"]), "rays": sorted(rays["new"]),
                  "noise": noise}))
status = 0
if rays["old"] != rays["new"] or len(rays["new"]) != 1:
    print("render_vs_previous: the ray counts differ (the renders are not the same work)",
          file=sys.stderr)
    status = 1
if ratio < 1.0 - noise:
    print(f"render_vs_previous: {ratio:.3f}x the previous release's samples/s (best of each), "
          f"below the noise band 1 - {noise}", file=sys.stderr)
    status = 1
sys.exit(status)
PY
