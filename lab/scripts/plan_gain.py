#!/usr/bin/env python3
"""What each final-auto plan of glint-final gains over its cheapest plan on the same frame
(docs/lab/final-plan.md; `planGain` in pipeline/src/time_budget.cpp): uniform renders of each
scene at each spp (half buffers, maxDepth 8, 2 threads), denoised by every plan through the Python
module; per frame the render's relMSE, each plan's relMSE and seconds against
scenes/S/reference.exr, then per plan the gain (the cheapest plan's relMSE / the plan's) as a
geometric mean over the frames, overall and per spp.

  PYTHONPATH=build/python /usr/bin/python3 lab/scripts/plan_gain.py --seed 511 \\
      --spp 32,128,512 cornell fox dof glossy pool textured [--plans cheapest,fast:1,balanced]
"""
import argparse
import math
import time
from collections import defaultdict

import glint

# glint-final's ladder (choosePlan) and its cheapest plan.
PLANS = {
    "cheapest": dict(quality="fast", size=1, filters=["cross-bilateral", "identity"]),
    "fast:1": dict(quality="fast", size=1),
    "fast:4": dict(quality="fast", size=4),
    "fast:16": dict(quality="fast", size=16),
    "fast": dict(quality="fast"),
    "balanced": dict(quality="balanced"),
    "best": dict(quality="best"),
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+")
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--spp", default="32,128,512")
    ap.add_argument("--plans", default="cheapest,fast:1,fast:4,fast:16,fast,balanced")
    args = ap.parse_args()
    plans = args.plans.split(",")
    if plans[0] != "cheapest" or any(p not in PLANS for p in plans):
        ap.error(f"--plans: 'cheapest' first, then any of {', '.join(PLANS)}")
    spps = [int(s) for s in args.spp.split(",")]
    gains = defaultdict(list)  # (plan, spp) -> gains
    print("scene\tspp\trender\t" + "\t".join(f"{p}\t{p} s" for p in plans))
    for scene_name in args.scenes:
        reference = glint.read_exr(f"scenes/{scene_name}/reference.exr")["color"]
        with glint.load_scene(f"scenes/{scene_name}/scene.json") as scene:
            for n in spps:
                frame = scene.render(spp=n, seed=args.seed, half_buffers=True, max_depth=8,
                                     threads=2).frame
                row = [scene_name, str(n), "%.4g" % glint.relmse(frame["color"], reference)]
                errors = {}
                for p in plans:
                    start = time.time()
                    result = glint.auto(frame, threads=2, **PLANS[p])
                    seconds = time.time() - start
                    errors[p] = glint.relmse(result.composite, reference)
                    row += ["%.4g" % errors[p], "%.2f" % seconds]
                for p in plans[1:]:
                    gains[(p, n)].append(errors["cheapest"] / errors[p])
                print("\t".join(row), flush=True)

    def geo(values):
        return math.exp(sum(map(math.log, values)) / len(values))

    print("\nplan\tgain (geometric mean)\tmin\tmax\t" + "\t".join(f"at {n} spp" for n in spps))
    for p in plans[1:]:
        every = [g for n in spps for g in gains[(p, n)]]
        print(f"{p}\t{geo(every):.2f}\t{min(every):.2f}\t{max(every):.2f}\t" +
              "\t".join(f"{geo(gains[(p, n)]):.2f}" for n in spps))


if __name__ == "__main__":
    main()
