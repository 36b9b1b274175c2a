// diffuse — Lambertian reflection: f = albedo / π, sampled with a cosine-weighted hemisphere.
#include "materials/bsdf.h"
#include "sampling/warp.h"

namespace glint::render {

namespace {
/// scene.json: {"type": "diffuse", "albedo": [r,g,b] | "texture": "file", "emission": [r,g,b]}
const MaterialParameter kDiffuseParameters[] = {
    colourParameter("albedo", "base colour", 0.0, 1.0, 0.8, &detail::Material::albedo,
                    "Diffuse reflectance.")
        .inLook(),
};
}  // namespace

BsdfValue diffuseEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return {};
    return {b.albedo * kInvPi, cosineHemispherePdf(wi.z)};
}

bool diffuseSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out) {
    if (wo.z <= 0.0f) return false;
    out.wi = sampleCosineHemisphere(u);
    out.pdf = cosineHemispherePdf(out.wi.z);
    if (!(out.pdf > 0.0f)) return false;
    // f cosθ / pdf = (albedo/π) cosθ / (cosθ/π) = albedo.
    out.weight = b.albedo;
    out.specular = false;
    return true;
}

namespace {
BsdfFlags diffuseFlags(const detail::Material&) {
    return {.directionPair = true};
}
}  // namespace

const MaterialKind diffuseKind{"diffuse",
                               "Lambertian reflection.",
                               true,
                               kDiffuseParameters,
                               diffuseFlags,
                               nullptr,
                               diffuseEvaluate,
                               [](const Bsdf& b, const Vec3& wo, Vec2 u, float, BsdfSample& out) {
                                   return diffuseSample(b, wo, u, out);
                               }};

}  // namespace glint::render
