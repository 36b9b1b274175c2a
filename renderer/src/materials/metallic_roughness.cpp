// metallicRoughness — the glTF 2.0 metallic-roughness BSDF (glTF 2.0 specification, Appendix B,
// with KHR_materials_transmission):
//   f          = (1 − metallic) · dielectric + metallic · metal
//   dielectric = (1 − F_d) · mix(baseColor / π, baseColor · T, transmission) + F_d · S
//   F_d        = f0 + (1 − f0) (1 − |v·h|)⁵
//   metal      = F_m · S,  F_m = baseColor + (1 − baseColor) (1 − |v·h|)⁵
//   S          = D(h) G2(wo, wi) / (4 cosθo cosθi)
//   T          = the GGX BTDF of rough glass without its Fresnel (rough_dielectric.cpp, Walter
//                et al. 2007, eq. 21), h the refraction half vector
// D is GGX with alpha = roughness², G2 = 1 / (1 + Λ(wo) + Λ(wi)) the height-correlated Smith
// masking-shadowing (Heitz 2014), f0 = ((ior − 1) / (ior + 1))² (KHR_materials_ior; 0.04 at the
// default 1.5).
// Transmission makes a solid refracting surface, as Blender's importer maps it to Principled
// transmission: the normal points outside, light refracts in with η = ior and out with 1/ior,
// radiance scaled by 1/η² as the dielectric does; seen from inside (wo.z < 0) the surface is
// the same BSDF mirrored through its plane. From the denser side F_d is Schlick's at the
// refracted angle and 1 past the critical angle (so that F_d is the same on both sides of a
// refraction pair and total internal reflection reflects). glTF's thin-walled reading (no
// KHR_materials_volume: no refraction, the surface a membrane) is not modelled.
// alpha is clamped up to kMinGgxAlpha (roughness ≈ 0.032): a roughness-0 asset gets a very
// narrow but still sampled GGX lobe, so eval, pdf and sample stay one consistent density and
// the material never switches to a delta event.
// Sampling: one sample from a mixture of GGX reflection (visible normals, Heitz 2018) with
// probability pSpec(wo), GGX refraction through a visible normal with (1 − pSpec) ·
// transmission and the cosine-weighted Lambert lobe with the rest; the lobe is chosen by u.x,
// which is then stretched back to [0, 1). pdf() is the mixture density, and the sample weight
// is f |cosθi| / pdf (one-sample MIS over the lobes with the balance heuristic).
// Not energy conserving at grazing angles, as specified: the base is weighted by the Fresnel
// of its own direction pair's v·h, not by what the layer reflects (white, metallic 0,
// roughness 0.05: directional albedo 1.03 at 60°, 1.58 at 85°).
// Without transmission the material is opaque and one-sided (wo.z <= 0 or wi.z <= 0 give 0:
// the integrator faces the frame to the viewer first).
// Built from glTF materials (pbrMetallicRoughness) by the importer, or per hit by
// Bsdf::metallicRoughness when metallic, roughness or transmission are textured.
#include <cmath>

#include "materials/bsdf.h"
#include "sampling/warp.h"

namespace glint::render {

namespace {

/// Smallest and largest probability of either lobe when both carry energy: a lobe whose
/// Fresnel estimate is tiny still gets a tenth of the samples, so that a sharp highlight or the
/// diffuse base is never left to a handful of samples with huge weights.
constexpr float kMinLobeProbability = 0.1f;

/// A glTF shape's "edits": {"albedo": [r,g,b], "metallic": 1, "roughness": 1, "ior": 1.5,
/// "transmission": 0, "emission": [r,g,b]}, each over the asset's own factor.
const MaterialParameter kMetallicRoughnessParameters[] = {
    colourParameter("albedo", "base colour", 0.0, 1.0, 1.0, &detail::Material::albedo,
                    "Base colour: the diffuse colour of a dielectric, the reflectance of a metal "
                    "(multiplies the base colour texture).")
        .inLook()
        .timesTexture(),
    numberParameter("metallic", "metallic", 0.0, 1.0, 1.0, &detail::Material::metallic,
                    "0 is a dielectric base under a specular coat, 1 a metal (multiplies the "
                    "metallic-roughness texture's B).")
        .inLook(),
    numberParameter("roughness", "roughness", 0.0, 1.0, 1.0, &detail::Material::roughness,
                    "Perceptual roughness (GGX α = roughness²; multiplies the metallic-roughness "
                    "texture's G).")
        .inLook(),
    numberParameter("ior", "index of refraction", 1.0, 10.0, 1.5, &detail::Material::ior,
                    "The dielectric base's index (its specular f0).")
        .inLook(),
    numberParameter("transmission", "transmission", 0.0, 1.0, 0.0, &detail::Material::transmission,
                    "How much of the dielectric base refracts (rough glass) instead of scattering "
                    "diffusely (KHR_materials_transmission).")
        .inLook(),
};

float pow5(float x) {
    const float x2 = x * x;
    return x2 * x2 * x;
}

/// Schlick's Fresnel with reflectance f0 at incidence cosI from a medium of relative index eta
/// (= η far side / η near side): from the denser side (eta < 1) at the refracted angle, and 1
/// past the critical angle.
float schlickFresnel(float f0, float cosI, float eta) {
    cosI = std::clamp(cosI, 0.0f, 1.0f);
    if (eta < 1.0f) {
        const float sin2T = (1.0f - cosI * cosI) / (eta * eta);
        if (sin2T >= 1.0f) return 1.0f;
        cosI = std::sqrt(1.0f - sin2T);
    }
    return f0 + (1.0f - f0) * pow5(1.0f - cosI);
}

/// The index of refraction the transmission lobe uses: at ior 1 refraction would not bend and
/// the BTDF would be a delta, so ior is kept 1e-3 away from 1.
float transmissionIor(float ior) {
    constexpr float kMinBend = 1e-3f;
    if (std::abs(ior - 1.0f) >= kMinBend) return ior;
    return ior < 1.0f ? 1.0f - kMinBend : 1.0f + kMinBend;
}

/// wo and wi as the lobes see them: mirrored through the surface plane when wo is inside (only
/// a transmitting material has an inside), with the relative index of the far side.
struct Local {
    Vec3 wo, wi;
    float eta;  ///< η of the far side / η of wo's side
    float ior;  ///< the material's, kept away from 1 when it transmits
};

bool toLocal(const Bsdf& b, const Vec3& wo, const Vec3& wi, Local& l) {
    if (b.transmission > 0.0f) {
        if (wo.z == 0.0f || wi.z == 0.0f) return false;
        l.ior = transmissionIor(b.ior);
    } else {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return false;
        l.ior = b.ior;
    }
    const float side = wo.z > 0.0f ? 1.0f : -1.0f;
    l.wo = {wo.x, wo.y, wo.z * side};
    l.wi = {wi.x, wi.y, wi.z * side};
    l.eta = side > 0.0f ? l.ior : 1.0f / l.ior;
    return true;
}

/// The probabilities of sample()'s three lobes at wo (wo.z > 0 after toLocal).
struct Lobes {
    float reflect, refract, diffuse;
};

Lobes lobeProbabilities(const Bsdf& b, const Vec3& wo, float ior, float eta) {
    // Expected weight of each lobe from Schlick's Fresnel at the macro normal (cosθo) in place
    // of v·h, in luminance: the GGX reflection against the base, whose share transmission
    // splits between refraction and the Lambert lobe.
    const float w5 = pow5(1.0f - std::clamp(wo.z, 0.0f, 1.0f));
    const float fd = schlickFresnel(schlickF0(ior), wo.z, eta);
    const float base = luminance(b.albedo);
    const float m = b.metallic;
    const float spec = (1.0f - m) * fd + m * (base + (1.0f - base) * w5);
    const float under = (1.0f - m) * (1.0f - fd) * base;
    float pSpec;
    if (!(under > 0.0f))
        pSpec = 1.0f;
    else if (!(spec > 0.0f))
        pSpec = 0.0f;
    else
        pSpec = std::clamp(spec / (spec + under), kMinLobeProbability, 1.0f - kMinLobeProbability);
    return {pSpec, (1.0f - pSpec) * b.transmission, (1.0f - pSpec) * (1.0f - b.transmission)};
}

/// f(wo, wi) and the mixture pdf of wi, sharing D, Λ and the Fresnel weights.
void evalAndPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi, Vec3& f, float& pdf) {
    f = {};
    pdf = 0.0f;
    Local l;
    if (!toLocal(b, wo, wi, l)) return;
    const Lobes p = lobeProbabilities(b, l.wo, l.ior, l.eta);
    const float m = b.metallic;
    const float f0 = schlickF0(l.ior);
    if (l.wi.z < 0.0f) {
        // Refraction (transmission only): (1 − metallic) transmission (1 − F_d) baseColor T,
        // F_d at the refraction half vector, from the cosine on the rarer side (taken as it is,
        // not through Snell's law, so that F_d is the same both ways); density of a visible
        // normal refracted.
        GgxRefraction r;
        if (!ggxRefraction(l.wo, l.wi, b.alpha, l.eta, r)) return;
        const float fd = schlickFresnel(f0, l.eta >= 1.0f ? r.woh : -r.wih, 1.0f);
        f = b.albedo * ((1.0f - m) * b.transmission * (1.0f - fd) * r.btdf);
        pdf = p.refract * r.pdfVisible;
        return;
    }
    // Step 1: microfacet terms of the reflection half vector (Walter et al. 2007, eq. 13).
    const Vec3 h = normalize(l.wo + l.wi);
    const float d = ggxD(h, b.alpha);
    const float lo = ggxLambda(l.wo, b.alpha), li = ggxLambda(l.wi, b.alpha);
    // S = D G2 / (4 cosθo cosθi) (Walter et al. 2007, eq. 20), G2 height-correlated.
    const float s = d / ((1.0f + lo + li) * 4.0f * l.wo.z * l.wi.z);
    // Step 2: Schlick weights at |v·h| (= |l·h|, so f stays reciprocal).
    const float voh = std::clamp(std::abs(dot(l.wo, h)), 0.0f, 1.0f);
    const float w5 = pow5(1.0f - voh);
    const float fd = schlickFresnel(f0, voh, l.eta);
    const Vec3 fm = b.albedo + (Vec3{1.0f, 1.0f, 1.0f} - b.albedo) * w5;
    // Step 3: mix dielectric (fresnel_mix of Lambert, weighted by 1 − transmission, and GGX)
    // and metal by metallic.
    f = b.albedo * ((1.0f - m) * (1.0f - fd) * (1.0f - b.transmission) * kInvPi) +
        (fm * m + Vec3{1.0f, 1.0f, 1.0f} * ((1.0f - m) * fd)) * s;
    // Step 4: mixture pdf, visible-normal density G1(wo) D / (4 cosθo) (Heitz 2018, eq. 17) and
    // cosθi / π.
    const float pdfSpec = d / ((1.0f + lo) * 4.0f * l.wo.z);
    pdf = p.reflect * pdfSpec + p.diffuse * cosineHemispherePdf(l.wi.z);
}

}  // namespace

float schlickF0(float ior) {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

Bsdf Bsdf::metallicRoughness(const Vec3& baseColor, float metallic, float roughness, float ior,
                             float transmission) {
    Bsdf b;
    b.kind = &metallicRoughnessKind;
    b.albedo = baseColor;
    b.metallic = std::clamp(metallic, 0.0f, 1.0f);
    const float r = std::clamp(roughness, 0.0f, 1.0f);
    b.alpha = std::max(r * r, kMinGgxAlpha);
    b.ior = ior;
    b.transmission = std::clamp(transmission, 0.0f, 1.0f);
    b.flags = {.transmits = b.transmission > 0.0f, .directionPair = true};
    return b;
}

float metallicRoughnessSpecularProbability(const Bsdf& b, const Vec3& wo) {
    Local l;
    if (!toLocal(b, wo, wo, l)) return 1.0f;
    return lobeProbabilities(b, l.wo, l.ior, l.eta).reflect;
}

BsdfValue metallicRoughnessEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi) {
    BsdfValue v;
    evalAndPdf(b, wo, wi, v.f, v.pdf);
    return v;
}

bool metallicRoughnessSample(const Bsdf& b, const Vec3& wo0, Vec2 u, BsdfSample& out) {
    Local l;
    if (!toLocal(b, wo0, wo0, l)) return false;
    const Vec3& wo = l.wo;
    // Step 1: choose the lobe with u.x and stretch the part used back to [0, 1).
    constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
    const Lobes p = lobeProbabilities(b, wo, l.ior, l.eta);
    Vec3 wi;
    if (u.x < p.reflect) {
        u.x = std::min(u.x / p.reflect, kOneMinusEpsilon);
        // Step 2a: reflect wo about a visible normal.
        const Vec3 h = ggxSampleVisibleNormal(wo, b.alpha, u);
        const float woh = dot(wo, h);
        if (woh <= 0.0f) return false;
        wi = h * (2.0f * woh) - wo;
        if (wi.z <= 0.0f) return false;
    } else if (u.x < p.reflect + p.refract) {
        u.x = std::min((u.x - p.reflect) / p.refract, kOneMinusEpsilon);
        // Step 2b: refract wo through a visible normal.
        const Vec3 h = ggxSampleVisibleNormal(wo, b.alpha, u);
        if (dot(wo, h) <= 0.0f || !refractThrough(wo, h, l.eta, wi) || wi.z >= 0.0f) return false;
        wi = renormalize(wi);
    } else {
        u.x = std::min((u.x - p.reflect - p.refract) / p.diffuse, kOneMinusEpsilon);
        // Step 2c: cosine-weighted hemisphere.
        wi = sampleCosineHemisphere(u);
    }
    // Step 3: back to wo's side, weight by the whole BSDF over the mixture density.
    out.wi = wo0.z > 0.0f ? wi : Vec3{wi.x, wi.y, -wi.z};
    Vec3 f;
    evalAndPdf(b, wo0, out.wi, f, out.pdf);
    if (!(out.pdf > 0.0f)) return false;
    out.weight = f * (std::abs(out.wi.z) / out.pdf);
    out.specular = false;
    return true;
}

const MaterialKind metallicRoughnessKind{
    "metallicRoughness",
    "glTF 2.0 metallic-roughness, with KHR_materials_ior and KHR_materials_transmission (made by "
    "the glTF and MTL importers).",
    false,
    kMetallicRoughnessParameters,
    [](const detail::Material& m) {
        return BsdfFlags{.transmits = m.transmission > 0.0f, .directionPair = true};
    },
    [](const detail::Material& m, const BsdfInputs& in) {
        return Bsdf::metallicRoughness(in.albedo, in.metallic, in.roughness, m.ior,
                                       in.transmission);
    },
    metallicRoughnessEvaluate,
    [](const Bsdf& b, const Vec3& wo, Vec2 u, float, BsdfSample& out) {
        return metallicRoughnessSample(b, wo, u, out);
    }};

}  // namespace glint::render
