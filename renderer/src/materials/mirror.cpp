// mirror — perfect specular reflection tinted by albedo.
#include "materials/bsdf.h"

namespace glint::render {

namespace {
/// scene.json: {"type": "mirror", "albedo": [r,g,b]}
const MaterialParameter kMirrorParameters[] = {
    colourParameter("albedo", "tint", 0.0, 1.0, 1.0, &detail::Material::albedo,
                    "Colour that multiplies what the mirror reflects.")
        .inLook(),
};
}  // namespace

bool mirrorSample(const Bsdf& b, const Vec3& wo, BsdfSample& out) {
    if (wo.z <= 0.0f) return false;
    out.wi = {-wo.x, -wo.y, wo.z};
    out.weight = b.albedo;
    out.pdf = 0.0f;
    out.specular = true;
    return true;
}

namespace {
BsdfFlags mirrorFlags(const detail::Material&) {
    return {.specular = true};
}
}  // namespace

const MaterialKind mirrorKind{"mirror", "Perfect mirror.", true, kMirrorParameters, mirrorFlags,
                              nullptr,
                              // A delta BSDF: Bsdf::evaluate never asks.
                              [](const Bsdf&, const Vec3&, const Vec3&) { return BsdfValue{}; },
                              [](const Bsdf& b, const Vec3& wo, Vec2, float, BsdfSample& out) {
                                  return mirrorSample(b, wo, out);
                              }};

}  // namespace glint::render
