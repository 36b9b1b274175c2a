"""Error against samples per pixel, of the render and of auto's result (docs/python.md).

    PYTHONPATH=build/python python3 python/examples/spp_study.py scenes/cornell/scene.json spp.png
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no window
import matplotlib.pyplot as plt

import glint

scene_file, plot_file = sys.argv[1], sys.argv[2]
spps = [4, 16, 64]
with glint.load_scene(scene_file) as scene:
    # The reference: 16 times the largest budget, another seed.
    reference = scene.render(spp=16 * spps[-1], seed=1000).frame["color"]
    raw, denoised = [], []
    for spp in spps:
        frame = scene.render(spp=spp, seed=1, half_buffers=True).frame
        raw.append(glint.relmse(frame["color"], reference))
        result = glint.auto(frame, quality="fast")  # halves estimator: no reference needed
        denoised.append(glint.relmse(result.composite, reference))
        print(f"{spp:4d} spp: relMSE {raw[-1]:.5f}, after auto {denoised[-1]:.5f}")

plt.figure(figsize=(5, 3.5))
plt.loglog(spps, raw, "o-", label="render")
plt.loglog(spps, denoised, "s-", label="auto")
plt.xlabel("samples per pixel")
plt.ylabel("relMSE against the reference")
plt.legend()
plt.tight_layout()
plt.savefig(plot_file, dpi=120)
