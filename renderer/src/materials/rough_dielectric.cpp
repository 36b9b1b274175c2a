// rough dielectric — rough glass: GGX microfacet reflection and refraction (Walter et al. 2007,
// "Microfacet Models for Refraction through Rough Surfaces") with height-correlated Smith
// masking-shadowing (Heitz 2014) and visible-normal sampling (Heitz 2018); the reflect/refract
// choice is made per sampled microfacet by its exact Fresnel reflectance.
// α < kMinGgxAlpha (and ior = 1, where refraction does not bend) is the smooth dielectric
// (dielectric.cpp): sample() hands over to dielectricSample, eval and pdf are 0.
// Radiance form, as the smooth dielectric: crossing into a medium of relative index η scales
// radiance by 1/η² (Veach 1997, sec. 5.2). The BTDF is Walter's eq. 21 with ηo² (the index on
// wo's side) in the numerator; it obeys the generalised reciprocity f(wo, wi) / ηo² =
// f(wi, wo) / ηi² (Veach 1997, eq. 5.14), reflection is reciprocal as it stands.
// The geometric normal points outside: wo.z > 0 means wo is outside, where the index is 1.
#include <cmath>

#include "materials/bsdf.h"

namespace glint::render {

namespace {
/// scene.json: {"type": "dielectric", "ior": 1.5, "roughness": 0.2, "albedo": [r,g,b]}
const MaterialParameter kDielectricParameters[] = {
    colourParameter("albedo", "tint", 0.0, 1.0, 1.0, &detail::Material::albedo,
                    "Colour that multiplies what the surface transmits.")
        .inLook(),
    numberParameter("ior", "index of refraction", 1e-3, 100.0, 1.5, &detail::Material::ior,
                    "Index of refraction inside the surface; outside is air, 1 (glass about 1.5).")
        .inLook(),
    numberParameter("roughness", "roughness", 0.0, 1.0, 0.0, &detail::Material::roughness,
                    "GGX roughness: α = roughness² (α < 0.001 is smooth glass).")
        .inLook(),
};
}  // namespace

bool refractThrough(const Vec3& wo, const Vec3& h, float eta, Vec3& wi) {
    // Snell's law about h (PBR 4th ed., sec. 9.3.2); cosI = wo·h > 0.
    const float cosI = dot(wo, h);
    const float sin2T = std::max(0.0f, 1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return false;  // total internal reflection
    const float cosT = std::sqrt(1.0f - sin2T);
    wi = wo * (-1.0f / eta) + h * (cosI / eta - cosT);
    return true;
}

bool ggxRefraction(const Vec3& wo, const Vec3& wi, float alpha, float eta, GgxRefraction& out) {
    if (wo.z <= 0.0f || wi.z >= 0.0f) return false;
    // Step 1: the refraction half vector ht = −(ηo wo + ηi wi) (Walter et al. 2007, eq. 16),
    // divided by ηo and turned to the outside (the sign does not matter once normalised).
    Vec3 h = wo + wi * eta;
    const float len = length(h);
    if (!(len > 0.0f)) return false;  // η = 1 and wi = −wo: no defined microfacet
    h = h / len;
    if (h.z < 0.0f) h = -h;
    // Step 2: wo in front of the microfacet and wi behind it (the χ⁺ of eq. 23).
    out.woh = dot(wo, h);
    out.wih = dot(wi, h);
    if (out.woh <= 0.0f || out.wih >= 0.0f) return false;
    out.h = h;
    // Step 3: D, G2 and the Jacobian |∂ωh/∂ωi| = η² |wi·h| / (wo·h + η wi·h)² (eq. 17, over ηo²).
    out.d = ggxD(h, alpha);
    const float lo = ggxLambda(wo, alpha), li = ggxLambda(wi, alpha);
    const float denom = out.woh + eta * out.wih;
    const float denom2 = denom * denom;
    if (!(denom2 > 0.0f)) return false;
    // f without (1 − F) and tint: D G2 |wi·h| |wo·h| / (|cosθi| cosθo (wo·h + η wi·h)²)
    // (eq. 21 with ηo² in the numerator, divided through by ηo²).
    out.btdf =
        out.d * std::abs(out.wih) * out.woh / ((1.0f + lo + li) * std::abs(wi.z) * wo.z * denom2);
    // Visible-normal density G1(wo) D wo·h / cosθo (Heitz 2018, eq. 3) times the Jacobian.
    out.pdfVisible =
        out.d * out.woh / ((1.0f + lo) * wo.z) * eta * eta * std::abs(out.wih) / denom2;
    return true;
}

namespace {

/// Fresnel reflectance of a refraction pair from both its cosines (cosI on the side of wo, cosT
/// on the far side, eta = η far / η near): the same as fresnelDielectric(cosI, eta), but
/// symmetric in the two sides to the last bit, where recomputing cosT from Snell's law would
/// cancel catastrophically near grazing refraction from the denser side.
float fresnelPair(float cosI, float cosT, float eta) {
    const float rParallel = (eta * cosI - cosT) / (eta * cosI + cosT);
    const float rPerpendicular = (cosI - eta * cosT) / (cosI + eta * cosT);
    return 0.5f * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

/// wo and wi mirrored through the surface plane when wo is inside, so that wo.z > 0; the
/// relative index of the far side is then η = ior (wo outside) or 1/ior (inside).
struct Upper {
    Vec3 wo, wi;
    float eta;
};
Upper toUpper(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    if (wo.z > 0.0f) return {wo, wi, b.ior};
    return {{wo.x, wo.y, -wo.z}, {wi.x, wi.y, -wi.z}, 1.0f / b.ior};
}

/// f(wo, wi) and the density of sample() producing wi, sharing D and Λ.
void evalAndPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi, Vec3& f, float& pdf) {
    f = {};
    pdf = 0.0f;
    if (wo.z == 0.0f || wi.z == 0.0f) return;
    const Upper u = toUpper(b, wo, wi);
    const float lo = ggxLambda(u.wo, b.alpha);
    if (u.wi.z > 0.0f) {
        // Reflection: f = F D G2 / (4 cosθo cosθi) (Walter et al. 2007, eq. 20); density
        // G1 D / (4 cosθo) (visible normals times the reflection Jacobian) times the choice F.
        const Vec3 h = normalize(u.wo + u.wi);
        const float woh = dot(u.wo, h);
        if (woh <= 0.0f) return;
        const float fr = fresnelDielectric(woh, u.eta);
        const float d = ggxD(h, b.alpha);
        const float li = ggxLambda(u.wi, b.alpha);
        const float s = fr * d / ((1.0f + lo + li) * 4.0f * u.wo.z * u.wi.z);
        f = {s, s, s};
        pdf = fr * d / ((1.0f + lo) * 4.0f * u.wo.z);
        return;
    }
    // Refraction: (1 − F) times the BTDF, tinted; density times the choice 1 − F.
    GgxRefraction r;
    if (!ggxRefraction(u.wo, u.wi, b.alpha, u.eta, r)) return;
    const float ft = 1.0f - fresnelPair(r.woh, -r.wih, u.eta);
    f = b.albedo * (ft * r.btdf);
    pdf = ft * r.pdfVisible;
}

}  // namespace

BsdfValue roughDielectricEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    BsdfValue v;
    evalAndPdf(b, wo, wi, v.f, v.pdf);
    return v;
}

bool roughDielectricSample(const Bsdf& b, const Vec3& wo, Vec2 u, float uc, BsdfSample& out) {
    if (roughDielectricIsSmooth(b)) return dielectricSample(b, wo, uc, out);
    if (wo.z == 0.0f) return false;
    // Step 1: a visible normal seen from wo (on the upper side).
    const float side = wo.z > 0.0f ? 1.0f : -1.0f;
    const Vec3 o{wo.x, wo.y, wo.z * side};
    const float eta = wo.z > 0.0f ? b.ior : 1.0f / b.ior;
    const Vec3 h = ggxSampleVisibleNormal(o, b.alpha, u);
    const float woh = dot(o, h);
    if (woh <= 0.0f) return false;
    // Step 2: reflect with the microfacet's Fresnel reflectance, else refract (Walter et al.
    // 2007, sec. 5.3); total internal reflection has F = 1.
    Vec3 i;
    if (uc < fresnelDielectric(woh, eta)) {
        i = h * (2.0f * woh) - o;
        if (i.z <= 0.0f) return false;
    } else {
        if (!refractThrough(o, h, eta, i) || i.z >= 0.0f) return false;
    }
    out.wi = renormalize(Vec3{i.x, i.y, i.z * side});
    // Step 3: weight and density from eval and pdf, so that they agree with them exactly.
    Vec3 f;
    evalAndPdf(b, wo, out.wi, f, out.pdf);
    if (!(out.pdf > 0.0f)) return false;
    out.weight = f * (std::abs(out.wi.z) / out.pdf);
    out.specular = false;
    return true;
}

namespace {
/// The smooth dielectric (roughDielectricIsSmooth) is a delta BSDF; both read the component
/// number, the rough one a microfacet too.
BsdfFlags dielectricFlags(const detail::Material& m) {
    const float alpha = m.roughness * m.roughness;
    const bool smooth = alpha < kMinGgxAlpha || m.ior == 1.0f;
    return {smooth, true, !smooth, true};
}
}  // namespace

const MaterialKind dielectricKind{
    "dielectric",
    "Glass: exact Fresnel reflection and refraction, smooth or rough (GGX microfacets).",
    true,
    kDielectricParameters,
    dielectricFlags,
    nullptr,
    roughDielectricEvaluate,
    roughDielectricSample};

}  // namespace glint::render
