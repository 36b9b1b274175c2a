// metallicRoughness — the glTF 2.0 metallic-roughness BRDF (glTF 2.0 specification, Appendix B):
//   f          = (1 − metallic) · dielectric + metallic · metal
//   dielectric = (1 − F_d) · baseColor / π + F_d · S,  F_d = f0 + (1 − f0) (1 − |v·h|)⁵
//   metal      = F_m · S,  F_m = baseColor + (1 − baseColor) (1 − |v·h|)⁵
//   S          = D(h) G2(wo, wi) / (4 cosθo cosθi)
// D is GGX with alpha = roughness², G2 = 1 / (1 + Λ(wo) + Λ(wi)) the height-correlated Smith
// masking-shadowing (Heitz 2014), f0 = ((ior − 1) / (ior + 1))² (KHR_materials_ior; 0.04 at the
// default 1.5).
// alpha is clamped up to kMinGgxAlpha (roughness ≈ 0.032): a roughness-0 asset gets a very
// narrow but still sampled GGX lobe, so eval, pdf and sample stay one consistent density and
// the material never switches to a delta event.
// Sampling: one sample from a two-lobe mixture, GGX visible normals (Heitz 2018) with
// probability pSpec(wo) and the cosine-weighted Lambert lobe otherwise; the lobe is chosen by
// u.x, which is then stretched back to [0, 1). pdf() is the mixture density, and the sample
// weight is f cosθi / pdf (one-sample MIS over the lobes with the balance heuristic).
// Not energy conserving at grazing angles, as specified: the base is weighted by the Fresnel
// of its own direction pair's v·h, not by what the layer reflects (white, metallic 0,
// roughness 0.05: directional albedo 1.03 at 60°, 1.58 at 85°).
// KHR_materials_transmission is not read yet: the material is opaque, wi.z <= 0 gives 0.
// Built from glTF materials (pbrMetallicRoughness) by the importer, or per hit by
// Bsdf::metallicRoughness when metallic and roughness are textured.
#include <cmath>

#include "materials/bsdf.h"
#include "sampling/warp.h"

namespace glint::render {

namespace {

/// Smallest and largest probability of either lobe when both carry energy: a lobe whose
/// Fresnel estimate is tiny still gets a tenth of the samples, so that a sharp highlight or the
/// diffuse base is never left to a handful of samples with huge weights.
constexpr float kMinLobeProbability = 0.1f;

float pow5(float x) {
    const float x2 = x * x;
    return x2 * x2 * x;
}

/// f(wo, wi) and the mixture pdf of wi, sharing D, Λ and the Fresnel weights.
void evalAndPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi, Vec3& f, float& pdf) {
    f = {};
    pdf = 0.0f;
    if (wo.z <= 0.0f || wi.z <= 0.0f) return;
    // Step 1: microfacet terms of the reflection half vector (Walter et al. 2007, eq. 13).
    const Vec3 h = normalize(wo + wi);
    const float d = ggxD(h, b.alpha);
    const float lo = ggxLambda(wo, b.alpha), li = ggxLambda(wi, b.alpha);
    // S = D G2 / (4 cosθo cosθi) (Walter et al. 2007, eq. 20), G2 height-correlated.
    const float s = d / ((1.0f + lo + li) * 4.0f * wo.z * wi.z);
    // Step 2: Schlick weights at |v·h| (= |l·h|, so f stays reciprocal).
    const float w5 = pow5(1.0f - std::clamp(std::abs(dot(wo, h)), 0.0f, 1.0f));
    const float f0 = schlickF0(b.ior);
    const float fd = f0 + (1.0f - f0) * w5;
    const Vec3 fm = b.albedo + (Vec3{1.0f, 1.0f, 1.0f} - b.albedo) * w5;
    // Step 3: mix dielectric (fresnel_mix of Lambert and GGX) and metal by metallic.
    const float m = b.metallic;
    f = b.albedo * ((1.0f - m) * (1.0f - fd) * kInvPi) +
        (fm * m + Vec3{1.0f, 1.0f, 1.0f} * ((1.0f - m) * fd)) * s;
    // Step 4: mixture pdf, visible-normal density G1(wo) D / (4 cosθo) (Heitz 2018, eq. 17) and
    // cosθi / π.
    const float pSpec = metallicRoughnessSpecularProbability(b, wo);
    const float pdfSpec = d / ((1.0f + lo) * 4.0f * wo.z);
    pdf = pSpec * pdfSpec + (1.0f - pSpec) * cosineHemispherePdf(wi.z);
}

}  // namespace

float schlickF0(float ior) {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

Bsdf Bsdf::metallicRoughness(const Vec3& baseColor, float metallic, float roughness, float ior,
                             float transmission) {
    Bsdf b;
    b.type = detail::MaterialType::MetallicRoughness;
    b.albedo = baseColor;
    b.metallic = std::clamp(metallic, 0.0f, 1.0f);
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    b.alpha = std::max(r * r, kMinGgxAlpha);
    b.ior = ior;
    b.transmission = std::clamp(transmission, 0.0f, 1.0f);
    return b;
}

float metallicRoughnessSpecularProbability(const Bsdf& b, const Vec3& wo) {
    // Expected weight of each lobe from Schlick's Fresnel at the macro normal (cosθo) in place
    // of v·h, in luminance.
    const float w5 = pow5(1.0f - std::clamp(wo.z, 0.0f, 1.0f));
    const float f0 = schlickF0(b.ior);
    const float fd = f0 + (1.0f - f0) * w5;
    const float base = luminance(b.albedo);
    const float m = b.metallic;
    const float spec = (1.0f - m) * fd + m * (base + (1.0f - base) * w5);
    const float diffuse = (1.0f - m) * (1.0f - fd) * base;
    if (!(diffuse > 0.0f)) return 1.0f;
    if (!(spec > 0.0f)) return 0.0f;
    return std::clamp(spec / (spec + diffuse), kMinLobeProbability, 1.0f - kMinLobeProbability);
}

Vec3 metallicRoughnessEval(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    Vec3 f;
    float pdf;
    evalAndPdf(b, wo, wi, f, pdf);
    return f;
}

float metallicRoughnessPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    Vec3 f;
    float pdf;
    evalAndPdf(b, wo, wi, f, pdf);
    return pdf;
}

bool metallicRoughnessSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out) {
    if (wo.z <= 0.0f) return false;
    // Step 1: choose the lobe with u.x and stretch the part used back to [0, 1).
    constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
    const float pSpec = metallicRoughnessSpecularProbability(b, wo);
    if (u.x < pSpec) {
        u.x = std::min(u.x / pSpec, kOneMinusEpsilon);
        // Step 2a: reflect wo about a visible normal.
        const Vec3 h = ggxSampleVisibleNormal(wo, b.alpha, u);
        const float woh = dot(wo, h);
        if (woh <= 0.0f) return false;
        out.wi = h * (2.0f * woh) - wo;
        if (out.wi.z <= 0.0f) return false;
    } else {
        u.x = std::min((u.x - pSpec) / (1.0f - pSpec), kOneMinusEpsilon);
        // Step 2b: cosine-weighted hemisphere.
        out.wi = sampleCosineHemisphere(u);
    }
    // Step 3: weight by the whole BRDF over the mixture density.
    Vec3 f;
    evalAndPdf(b, wo, out.wi, f, out.pdf);
    if (!(out.pdf > 0.0f)) return false;
    out.weight = f * (out.wi.z / out.pdf);
    out.specular = false;
    return true;
}

}  // namespace glint::render
