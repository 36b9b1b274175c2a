# The directional albedo, under a uniform white sky, of the glTF metallic-roughness BRDF (a
# Lambert base weighted by 1 - F(v.h) plus the GGX layer with height-correlated Smith masking,
# as Glint evaluates it) and of what Blender 3.4's Principled BSDF makes of the same glTF
# material (Disney's diffuse with its retro-reflection, not weighted by Fresnel, plus a GGX layer
# with specular 0.5, i.e. f0 = 0.04, whose masking is the separable product G1(l) G1(v)), by
# numerical integration over the hemisphere. With --metal the material is metallic 1 (a grey
# base as f0; no diffuse) and the two differ only in the masking. It separates the difference
# that is in the BRDF models from anything in the renderers (docs/assets.md, "Against Cycles").
#   /usr/bin/python3 lab/bench/cycles/gltf_brdf_albedo.py [BASE] [ROUGHNESS] [--metal]
import sys

import numpy as np


def ggx_d(nh, a):
    d = nh * nh * (a * a - 1) + 1
    return a * a / (np.pi * d * d)


def smith_lambda(c, a):
    return 0.5 * (-1 + np.sqrt(1 + a * a * (1 - c * c) / (c * c)))


def albedo(model, base, roughness, theta_v, metal=False, n=400):
    a = roughness * roughness
    v = np.array([np.sin(theta_v), 0.0, np.cos(theta_v)])
    th = (np.arange(n) + 0.5) / n * np.pi / 2
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    t, p = np.meshgrid(th, ph, indexing="ij")
    l = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    dw = (np.pi / 2 / n) * (np.pi / n) * np.sin(t)
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nl, nv, nh, vh = l[..., 2], v[2], h[..., 2], (h * v).sum(-1)
    f0 = base if metal else 0.04
    f = f0 + (1 - f0) * (1 - vh) ** 5
    if model == "gltf":  # height-correlated (glTF spec, Heitz 2014 eq. 99)
        g2 = 1 / (1 + smith_lambda(nl, a) + smith_lambda(nv, a))
    else:  # separable, as Cycles before 4.0 evaluates it
        g2 = 1 / ((1 + smith_lambda(nl, a)) * (1 + smith_lambda(nv, a)))
    specular = f * ggx_d(nh, a) * g2 / (4 * nl * nv)
    if metal:
        brdf = specular
    elif model == "gltf":
        brdf = (1 - f) * base / np.pi + specular
    else:
        fd90 = 0.5 + 2 * roughness * vh ** 2
        brdf = base / np.pi * (1 + (fd90 - 1) * (1 - nl) ** 5) * (1 + (fd90 - 1) * (1 - nv) ** 5)
        brdf = brdf + specular
    return float((brdf * nl * dw).sum())


args = [a for a in sys.argv[1:] if a != "--metal"]
metal = "--metal" in sys.argv[1:]
base = float(args[0]) if len(args) > 0 else 0.7
roughness = float(args[1]) if len(args) > 1 else 1.0
print(f"base {base}, metallic {int(metal)}, roughness {roughness}")
print(f"{'view':>5} {'glTF':>8} {'Principled':>11} {'glTF vs Principled':>19}")
for degrees in (0, 30, 60, 80):
    g = albedo("gltf", base, roughness, np.radians(degrees), metal)
    d = albedo("principled", base, roughness, np.radians(degrees), metal)
    print(f"{degrees:4d}° {g:8.4f} {d:11.4f} {100 * (g - d) / d:+18.1f} %")
