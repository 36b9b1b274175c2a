// dielectric — smooth glass: Fresnel-weighted choice between specular reflection and refraction.
//   scene.json: {"type": "dielectric", "ior": 1.5, "albedo": [r,g,b] (transmission tint)}
// A "roughness" whose alpha reaches kMinGgxAlpha makes it rough glass (rough_dielectric.cpp),
// of which this is the smooth limit.
// The geometric normal points outside: wo.z > 0 means the ray arrives from outside.
#include <cmath>

#include "materials/bsdf.h"

namespace glint::render {

float fresnelDielectric(float cosI, float eta) {
    // Fresnel equations for unpolarised light (Hecht, Optics, sec. 4.6); eta = ηt / ηi.
    const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return 1.0f;  // total internal reflection
    const float cosT = std::sqrt(1.0f - sin2T);
    const float rParallel = (eta * cosI - cosT) / (eta * cosI + cosT);
    const float rPerpendicular = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

bool dielectricSample(const Bsdf& b, const Vec3& wo, float uc, BsdfSample& out) {
    if (wo.z == 0.0f) return false;
    const bool entering = wo.z > 0.0f;
    const float eta = entering ? b.ior : 1.0f / b.ior;
    const float cosI = std::abs(wo.z);
    const float f = fresnelDielectric(cosI, eta);
    out.pdf = 0.0f;
    out.specular = true;
    if (uc < f) {
        // Reflect with probability F: weight F / F = 1.
        out.wi = {-wo.x, -wo.y, wo.z};
        out.weight = {1.0f, 1.0f, 1.0f};
        return true;
    }
    // Refract with probability 1 - F (Snell's law). Radiance is scaled by 1/eta^2 across the
    // interface (Veach 1997, sec. 5.2).
    const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    const float cosT = std::sqrt(std::max(0.0f, 1.0f - sin2T));
    const float nz = entering ? 1.0f : -1.0f;
    out.wi = Vec3{-wo.x / eta, -wo.y / eta, -nz * cosT};
    out.weight = b.albedo * (1.0f / (eta * eta));
    return true;
}

}  // namespace glint::render
