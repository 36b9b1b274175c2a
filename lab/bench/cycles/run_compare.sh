#!/usr/bin/env bash
# Same-run speed comparison on scenes/cornell (256 x 256, 64 spp, max depth 8, 2 threads):
# Blender's Cycles (lab/bench/cycles/cornell_cycles.py) and then glint-render, both timed
# around the render only. Prints both samples/s and the ratio Glint / Cycles.
#   lab/bench/cycles/run_compare.sh [BUILD_DIR] [SPP] [THREADS] [REPEATS]
# Needs Debian's `blender` (make bench-deps). Exit code 2 when a tool is missing.
set -euo pipefail
cd "$(dirname "$0")/../../.."
BUILD_DIR=${1:-build}
SPP=${2:-64}
THREADS=${3:-2}
REPEATS=${4:-1}
GLINT="$BUILD_DIR/bin/glint-render"
OUT=${TMPDIR:-/tmp}/glint-cycles-compare.$$
mkdir -p "$OUT"
trap 'rm -rf "$OUT"' EXIT

command -v blender >/dev/null || { echo "run_compare.sh: blender not found (apt-get install -y blender)" >&2; exit 2; }
command -v python3 >/dev/null || { echo "run_compare.sh: python3 not found" >&2; exit 2; }

for ((i = 1; i <= REPEATS; ++i)); do
  blender -b -P lab/bench/cycles/cornell_cycles.py -- --spp "$SPP" --threads "$THREADS" \
    --max-depth 8 --out "$OUT/cycles.exr" 2>/dev/null | grep '^{"renderer": "cycles"' >> "$OUT/cycles.jsonl"
  if [[ -x "$GLINT" ]]; then
    "$GLINT" scenes/cornell/scene.json --spp "$SPP" --set maxDepth=8 --threads "$THREADS" \
      --out "$OUT/glint.exr" --json 2>/dev/null | tail -n 1 >> "$OUT/glint.jsonl"
  fi
done

python3 - "$OUT" "$GLINT" <<'PY'
import json, os, statistics, sys
out, glint = sys.argv[1], sys.argv[2]

def load(name):
    path = os.path.join(out, name)
    if not os.path.exists(path):
        return []
    return [json.loads(line) for line in open(path) if line.strip()]

def rate(d):
    # glint-render --json and the Cycles script both report samplesPerSecond.
    if "samplesPerSecond" in d:
        return float(d["samplesPerSecond"])
    return d["width"] * d["height"] * d["spp"] / d["seconds"]

cycles = load("cycles.jsonl")
if not cycles:
    print("run_compare.sh: the Cycles script printed no result", file=sys.stderr)
    sys.exit(1)
c = statistics.median(rate(d) for d in cycles)
result = {"cycles": {"samplesPerSecond": c,
                     "seconds": statistics.median(d["seconds"] for d in cycles),
                     "blender": cycles[0]["blender"]}}
print(f"Cycles {cycles[0]['blender']}: {c / 1e6:.3f} M samples/s "
      f"({result['cycles']['seconds']:.2f} s, median of {len(cycles)})")
g = load("glint.jsonl")
if g:
    gr = statistics.median(rate(d) for d in g)
    result["glint"] = {"samplesPerSecond": gr,
                       "seconds": statistics.median(d["seconds"] for d in g)}
    if "raysPerSecond" in g[0]:
        result["glint"]["raysPerSecond"] = statistics.median(d["raysPerSecond"] for d in g)
    result["ratio"] = gr / c
    print(f"Glint:        {gr / 1e6:.3f} M samples/s ({result['glint']['seconds']:.2f} s)")
    print(f"ratio Glint / Cycles: {gr / c:.2f} (issue 3 asks for >= 1.5)")
else:
    print(f"Glint: {glint} not found or failed; build it first")
print(json.dumps(result))
PY
