// BSDFs in the local shading frame (z = shading normal). Each material kind lives in its own
// file (diffuse.cpp, mirror.cpp, dielectric.cpp, rough_dielectric.cpp, conductor.cpp,
// metallic_roughness.cpp); Bsdf dispatches by kind (inline, below).
#pragma once

#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// Result of sampling a BSDF: incident direction, weight = f |cos θi| / pdf, and the pdf
/// (solid angle; 0 for specular events, whose weight already includes the discrete choice).
struct BsdfSample {
    Vec3 wi;
    Vec3 weight;
    float pdf = 0.0f;
    bool specular = false;
};

/// GGX alphas below this are treated as a perfect mirror (conductor) or smooth glass
/// (dielectric); the metallic-roughness
/// material clamps its alpha up to it instead, so that its lobe stays a sampled GGX.
inline constexpr float kMinGgxAlpha = 1e-3f;

/// A material evaluated at one shading point (texture already looked up).
struct Bsdf {
    detail::MaterialType type = detail::MaterialType::Diffuse;
    Vec3 albedo{};              ///< reflectance / tint / transmittance tint
    float ior = 1.5f;           ///< dielectric; metallicRoughness: f0 = ((ior − 1) / (ior + 1))²
    float alpha = 0.0f;         ///< conductor, dielectric, metallicRoughness: GGX alpha
    float metallic = 0.0f;      ///< metallicRoughness: 0 dielectric base, 1 metal
    float transmission = 0.0f;  ///< metallicRoughness: KHR_materials_transmission
    bool hasEtaK = false;
    Vec3 eta{1.0f, 1.0f, 1.0f}, k{};
    Vec3 specular{1.0f, 1.0f, 1.0f};

    /// Builds the BSDF of `material` with (possibly textured) albedo. A metallicRoughness
    /// material takes its factors from `material`; use metallicRoughness() for textured ones.
    /// Inline, as the dispatch below: built at every hit.
    static Bsdf fromMaterial(const detail::Material& material, const Vec3& albedo);
    /// Builds the glTF metallic-roughness BSDF from per-hit values: the base colour (factor ×
    /// texture), metallic and perceptual roughness (factors × the texture's B and G), the IOR
    /// (KHR_materials_ior) and the transmission factor. metallic and roughness are clamped to
    /// [0, 1]; alpha = max(roughness², kMinGgxAlpha).
    static Bsdf metallicRoughness(const Vec3& baseColor, float metallic, float roughness,
                                  float ior = 1.5f, float transmission = 0.0f);

    /// True when every event is a delta (mirror, smooth dielectric, conductor with tiny alpha).
    bool isSpecular() const;
    /// True when light passes the surface (dielectric, metallicRoughness with transmission):
    /// wo and wi may lie on either side, wo.z < 0 meaning wo is inside.
    bool transmits() const {
        return type == detail::MaterialType::Dielectric ||
               (type == detail::MaterialType::MetallicRoughness && transmission > 0.0f);
    }
    /// Which of sample()'s numbers it reads: the direction pair `u` (diffuse, conductor,
    /// metallicRoughness, rough dielectric: the microfacet) and the component number `uc`
    /// (dielectric: reflect or refract). A sampler with a fixed slot per number need not draw
    /// the others.
    bool readsDirectionPair() const {
        return type == detail::MaterialType::Diffuse || type == detail::MaterialType::Conductor ||
               type == detail::MaterialType::MetallicRoughness ||
               (type == detail::MaterialType::Dielectric && !isSpecular());
    }
    bool readsComponentNumber() const { return type == detail::MaterialType::Dielectric; }
    /// f(wo, wi) without the cosine; 0 for specular BSDFs.
    Vec3 eval(const Vec3& wo, const Vec3& wi) const;
    /// Solid-angle density of sample() producing wi; 0 for specular BSDFs.
    float pdf(const Vec3& wo, const Vec3& wi) const;
    /// Samples wi from u (2D) and uc (for discrete choices); false when no valid direction.
    bool sample(const Vec3& wo, Vec2 u, float uc, BsdfSample& out) const;
};

// Per-material implementations (wo, wi in the local frame).
Vec3 diffuseEval(const Bsdf& b, const Vec3& wo, const Vec3& wi);
float diffusePdf(const Bsdf& b, const Vec3& wo, const Vec3& wi);
bool diffuseSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out);

bool mirrorSample(const Bsdf& b, const Vec3& wo, BsdfSample& out);

/// Unpolarised Fresnel reflectance of a dielectric interface; eta = ηt/ηi, cosI >= 0.
float fresnelDielectric(float cosI, float eta);
bool dielectricSample(const Bsdf& b, const Vec3& wo, float uc, BsdfSample& out);

/// Refracts wo (wo·h > 0) through the microfacet h into a medium of relative index eta
/// (= η of wi's side / η of wo's side); false on total internal reflection.
bool refractThrough(const Vec3& wo, const Vec3& h, float eta, Vec3& wi);
/// GGX terms of a refraction pair wo.z > 0 > wi.z, eta = η below / η above.
struct GgxRefraction {
    Vec3 h;          ///< the refraction half vector, h.z > 0
    float woh, wih;  ///< wo·h > 0 > wi·h
    float d;         ///< D(h)
    float btdf;      ///< the radiance BTDF without (1 − F) and tint (Walter et al. 2007, eq. 21)
    float pdfVisible;  ///< visible-normal density of h times |∂ωh/∂ωi|
};
/// Fills `out` for a pair that refracts through some microfacet; false when none does.
bool ggxRefraction(const Vec3& wo, const Vec3& wi, float alpha, float eta, GgxRefraction& out);
/// A dielectric with alpha < kMinGgxAlpha (or ior 1) is the smooth one, a delta BSDF.
inline bool roughDielectricIsSmooth(const Bsdf& b) {
    return b.alpha < kMinGgxAlpha || b.ior == 1.0f;
}
Vec3 roughDielectricEval(const Bsdf& b, const Vec3& wo, const Vec3& wi);
float roughDielectricPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi);
/// GGX reflection or refraction (chosen by uc against the microfacet's Fresnel); the smooth
/// dielectric's dielectricSample when roughDielectricIsSmooth.
bool roughDielectricSample(const Bsdf& b, const Vec3& wo, Vec2 u, float uc, BsdfSample& out);

/// Conductor Fresnel reflectance (per channel eta, k; or Schlick from `specular`).
Vec3 conductorFresnel(const Bsdf& b, float cosI);
/// GGX normal distribution D(h) (Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33).
float ggxD(const Vec3& h, float alpha);
/// Smith Λ for GGX (Heitz 2014, eq. 72).
float ggxLambda(const Vec3& w, float alpha);
/// Visible-normal sample of GGX seen from wo (Heitz 2018, "Sampling the GGX Distribution of
/// Visible Normals").
Vec3 ggxSampleVisibleNormal(const Vec3& wo, float alpha, Vec2 u);
Vec3 conductorEval(const Bsdf& b, const Vec3& wo, const Vec3& wi);
float conductorPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi);
bool conductorSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out);

/// Schlick's f0 of a dielectric of index `ior` seen from air: ((ior − 1) / (ior + 1))².
float schlickF0(float ior);
/// Probability that metallicRoughnessSample picks GGX reflection at wo (else, split by the
/// transmission factor, GGX refraction or the Lambert lobe).
float metallicRoughnessSpecularProbability(const Bsdf& b, const Vec3& wo);
Vec3 metallicRoughnessEval(const Bsdf& b, const Vec3& wo, const Vec3& wi);
float metallicRoughnessPdf(const Bsdf& b, const Vec3& wo, const Vec3& wi);
bool metallicRoughnessSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out);

// Bsdf's dispatch by kind, inline: called at every hit, it folds into the integrator's code
// (a plain material then pays one test and the call of its own kind's function).

inline Bsdf Bsdf::fromMaterial(const detail::Material& material, const Vec3& albedo) {
    if (material.type == detail::MaterialType::MetallicRoughness)
        return metallicRoughness(albedo, material.metallic, material.roughness, material.ior,
                                 material.transmission);
    Bsdf b;
    b.type = material.type;
    b.albedo = albedo;
    b.ior = material.ior;
    b.alpha = material.roughness * material.roughness;
    b.hasEtaK = material.hasEtaK;
    b.eta = material.eta;
    b.k = material.k;
    b.specular = material.specular;
    return b;
}

inline bool Bsdf::isSpecular() const {
    switch (type) {
        case detail::MaterialType::Diffuse:
        case detail::MaterialType::MetallicRoughness:
            return false;
        case detail::MaterialType::Mirror:
            return true;
        case detail::MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this);
        case detail::MaterialType::Conductor:
            return alpha < kMinGgxAlpha;
    }
    return false;
}

inline Vec3 Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    switch (type) {
        case detail::MaterialType::Diffuse:
            return diffuseEval(*this, wo, wi);
        case detail::MaterialType::MetallicRoughness:
            return metallicRoughnessEval(*this, wo, wi);
        case detail::MaterialType::Conductor:
            return alpha < kMinGgxAlpha ? Vec3{} : conductorEval(*this, wo, wi);
        case detail::MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this) ? Vec3{} : roughDielectricEval(*this, wo, wi);
        default:
            return {};
    }
}

inline float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    switch (type) {
        case detail::MaterialType::Diffuse:
            return diffusePdf(*this, wo, wi);
        case detail::MaterialType::MetallicRoughness:
            return metallicRoughnessPdf(*this, wo, wi);
        case detail::MaterialType::Conductor:
            return alpha < kMinGgxAlpha ? 0.0f : conductorPdf(*this, wo, wi);
        case detail::MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this) ? 0.0f : roughDielectricPdf(*this, wo, wi);
        default:
            return 0.0f;
    }
}

inline bool Bsdf::sample(const Vec3& wo, Vec2 u, float uc, BsdfSample& out) const {
    switch (type) {
        case detail::MaterialType::Diffuse:
            return diffuseSample(*this, wo, u, out);
        case detail::MaterialType::MetallicRoughness:
            return metallicRoughnessSample(*this, wo, u, out);
        case detail::MaterialType::Mirror:
            return mirrorSample(*this, wo, out);
        case detail::MaterialType::Dielectric:
            return roughDielectricSample(*this, wo, u, uc, out);
        case detail::MaterialType::Conductor:
            return conductorSample(*this, wo, u, out);
    }
    return false;
}

}  // namespace glint::render
