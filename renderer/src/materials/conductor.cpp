// conductor — GGX microfacet metal (Walter et al. 2007) with height-correlated Smith masking
// (Heitz 2014) and visible-normal sampling (Heitz 2018). alpha = roughness^2; alpha < 1e-3 is a
// perfect mirror. Fresnel: complex IOR (eta, k) per channel, else Schlick from `specular`.
#include <cmath>

#include "materials/bsdf.h"

namespace glint::render {

namespace {
/// scene.json: {"type": "conductor", "roughness": 0.3, "eta": [..], "k": [..] | "specular": [..],
///              "albedo": [r,g,b]}
const MaterialParameter kConductorParameters[] = {
    colourParameter("albedo", "tint", 0.0, 1.0, 1.0, &detail::Material::albedo,
                    "Colour that multiplies what the metal reflects.")
        .inLook(),
    numberParameter("roughness", "roughness", 0.0, 1.0, 0.0, &detail::Material::roughness,
                    "GGX roughness: α = roughness² (α < 0.001 is a perfect mirror).")
        .inLook(),
    colourParameter("eta", "η", 1e-4, 100.0, 1.0, &detail::Material::eta,
                    "Complex index of refraction, real part, per channel (given with `k`).")
        .givenWith("k", &detail::Material::hasEtaK),
    colourParameter("k", "κ", 0.0, 100.0, 0.0, &detail::Material::k,
                    "Complex index of refraction, imaginary part (given with `eta`).")
        .givenWith("eta", &detail::Material::hasEtaK),
    colourParameter("specular", "specular", 0.0, 1.0, 1.0, &detail::Material::specular,
                    "Reflectance at normal incidence for Schlick's Fresnel, used when `eta` and "
                    "`k` are absent."),
};
}  // namespace

namespace {
float conductorFresnel1(float cosI, float eta, float k) {
    // Exact Fresnel reflectance of a conductor from air (PBR 3rd ed., sec. 8.2.1).
    const float cos2 = cosI * cosI, sin2 = 1.0f - cos2;
    const float eta2 = eta * eta, k2 = k * k;
    const float t0 = eta2 - k2 - sin2;
    const float a2b2 = std::sqrt(std::max(0.0f, t0 * t0 + 4.0f * eta2 * k2));
    const float t1 = a2b2 + cos2;
    const float a = std::sqrt(std::max(0.0f, 0.5f * (a2b2 + t0)));
    const float t2 = 2.0f * cosI * a;
    const float rs = (t1 - t2) / (t1 + t2);
    const float t3 = cos2 * a2b2 + sin2 * sin2;
    const float t4 = t2 * sin2;
    const float rp = rs * (t3 - t4) / (t3 + t4);
    return 0.5f * (rp + rs);
}
}  // namespace

Vec3 conductorFresnel(const Bsdf& b, float cosI) {
    cosI = std::clamp(cosI, 0.0f, 1.0f);
    if (b.hasEtaK)
        return {conductorFresnel1(cosI, b.eta.x, b.k.x), conductorFresnel1(cosI, b.eta.y, b.k.y),
                conductorFresnel1(cosI, b.eta.z, b.k.z)};
    // Schlick 1994.
    const float m = 1.0f - cosI, m5 = m * m * m * m * m;
    return b.specular + (Vec3{1.0f, 1.0f, 1.0f} - b.specular) * m5;
}

float ggxD(const Vec3& h, float alpha) {
    if (h.z <= 0.0f) return 0.0f;
    // D = α² / (π (α² cos²θ + sin²θ)²), with sin²θ from x and y: 1 − cos²θ would cancel
    // catastrophically near the peak of a narrow lobe (α = 1e-3 puts it at sin²θ ~ 1e-6).
    const float a2 = alpha * alpha;
    const float d = a2 * h.z * h.z + (h.x * h.x + h.y * h.y);
    return a2 / (kPi * d * d);
}

float ggxLambda(const Vec3& w, float alpha) {
    const float cos2 = w.z * w.z;
    if (cos2 <= 0.0f) return 0.0f;
    const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

Vec3 ggxSampleVisibleNormal(const Vec3& wo, float alpha, Vec2 u) {
    // Heitz 2018, listing 1: stretch, sample the projected hemisphere, unstretch.
    const Vec3 vh = normalize(Vec3{alpha * wo.x, alpha * wo.y, wo.z});
    const float lensq = vh.x * vh.x + vh.y * vh.y;
    const Vec3 t1 = lensq > 0.0f ? Vec3{-vh.y, vh.x, 0.0f} / std::sqrt(lensq) : Vec3{1, 0, 0};
    const Vec3 t2 = cross(vh, t1);
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    const float s = 0.5f * (1.0f + vh.z);
    const float p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * r * std::sin(phi);
    const Vec3 nh = t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    return normalize(Vec3{alpha * nh.x, alpha * nh.y, std::max(1e-7f, nh.z)});
}

namespace {
/// Visible-normal density D_wo(h) = G1 max(0, wo·h) D / cosθo, times the reflection Jacobian
/// 1 / (4 wo·h) (Heitz 2018, eq. 17), from D(h) and Λ(wo).
float conductorDensity(const Vec3& wo, float d, float lambdaO) {
    const float g1 = 1.0f / (1.0f + lambdaO);
    return g1 * d / (4.0f * wo.z);
}

float conductorPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    const Vec3 h = normalize(wo + wi);
    return conductorDensity(wo, ggxD(h, b.alpha), ggxLambda(wo, b.alpha));
}
}  // namespace

BsdfValue conductorEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    if (wo.z <= 0.0f || wi.z <= 0.0f) return {};
    const Vec3 h = normalize(wo + wi);
    const float d = ggxD(h, b.alpha);
    const float lo = ggxLambda(wo, b.alpha);
    // f = D G2 F / (4 cosθo cosθi) (Walter et al. 2007, eq. 20).
    const float g2 = 1.0f / (1.0f + lo + ggxLambda(wi, b.alpha));
    const float scale = d * g2 / (4.0f * wo.z * wi.z);
    return {conductorFresnel(b, dot(wo, h)) * b.albedo * scale, conductorDensity(wo, d, lo)};
}

bool conductorSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out) {
    if (wo.z <= 0.0f) return false;
    if (b.alpha < kMinGgxAlpha) {
        out.wi = {-wo.x, -wo.y, wo.z};
        out.weight = conductorFresnel(b, wo.z) * b.albedo;
        out.pdf = 0.0f;
        out.specular = true;
        return true;
    }
    const Vec3 h = ggxSampleVisibleNormal(wo, b.alpha, u);
    const float woh = dot(wo, h);
    out.wi = h * (2.0f * woh) - wo;
    if (out.wi.z <= 0.0f || woh <= 0.0f) return false;
    out.pdf = conductorPdf(b, wo, out.wi);
    if (!(out.pdf > 0.0f)) return false;
    // weight = f cosθi / pdf = F G2 / G1(wo) (Heitz 2018, sec. 2).
    const float lo = ggxLambda(wo, b.alpha), li = ggxLambda(out.wi, b.alpha);
    out.weight = conductorFresnel(b, woh) * b.albedo * ((1.0f + lo) / (1.0f + lo + li));
    out.specular = false;
    return true;
}

namespace {
BsdfFlags conductorFlags(const detail::Material& m) {
    return {.specular = m.roughness * m.roughness < kMinGgxAlpha, .directionPair = true};
}
}  // namespace

const MaterialKind conductorKind{
    "conductor",
    "Rough metal: GGX microfacets, visible-normal sampling; Fresnel from `eta` and `k`, else "
    "Schlick's from `specular`.",
    true,
    kConductorParameters,
    conductorFlags,
    nullptr,
    conductorEvaluate,
    [](const Bsdf& b, const Vec3& wo, Vec2 u, float, BsdfSample& out) {
        return conductorSample(b, wo, u, out);
    }};

}  // namespace glint::render
