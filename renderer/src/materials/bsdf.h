// BSDFs in the local shading frame (z = shading normal), and the material kinds that make them.
// Each kind lives in its own file (diffuse.cpp, mirror.cpp, dielectric.cpp with
// rough_dielectric.cpp, conductor.cpp, metallic_roughness.cpp) and is registered by one line of
// material_kinds.h; Bsdf dispatches through its kind's MaterialKind. Integrators ask a material
// or a BSDF what it does (BsdfFlags), never which kind it is.
#pragma once

#include <span>

#include "materials/material_kinds.h"
#include "materials/material_parameters.h"
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

/// f(wo, wi) without the cosine and the solid-angle density of sample() producing wi,
/// computed together (next-event estimation needs both).
struct BsdfValue {
    Vec3 f;
    float pdf = 0.0f;
};

/// What a BSDF does and which of sample()'s numbers it reads; for a material (materialFlags),
/// what the BSDF built from its factors does, which a hit's textures can only narrow
/// (textures lower a transmission factor, never raise it).
struct BsdfFlags {
    bool specular = false;   ///< every event is a delta: no next-event estimation, eval is 0
    bool transmits = false;  ///< light passes the surface: wo and wi may lie on either side
    /// sample() reads the direction pair `u` (a microfacet, a cosine-weighted direction...).
    bool directionPair = false;
    /// sample() reads the component number `uc` (the dielectric's reflect or refract).
    bool componentNumber = false;
};

/// What a hit's textures give a BSDF: the base colour (albedo, tint) and the metallic-roughness
/// material's metallic, perceptual roughness and transmission (factors times textures).
struct BsdfInputs {
    Vec3 albedo;
    float metallic = 0.0f;
    float roughness = 0.0f;
    float transmission = 0.0f;
};

/// GGX alphas below this are treated as a perfect mirror (conductor) or smooth glass
/// (dielectric); the metallic-roughness
/// material clamps its alpha up to it instead, so that its lobe stays a sampled GGX.
inline constexpr float kMinGgxAlpha = 1e-3f;

struct MaterialKind;

/// A material evaluated at one shading point (texture already looked up).
struct Bsdf {
    const MaterialKind* kind = nullptr;  ///< set by the kind that built it
    BsdfFlags flags;
    Vec3 albedo{};              ///< reflectance / tint / transmittance tint
    float ior = 1.5f;           ///< dielectric; metallicRoughness: f0 = ((ior − 1) / (ior + 1))²
    float alpha = 0.0f;         ///< conductor, dielectric, metallicRoughness: GGX alpha
    float metallic = 0.0f;      ///< metallicRoughness: 0 dielectric base, 1 metal
    float transmission = 0.0f;  ///< metallicRoughness: KHR_materials_transmission
    bool hasEtaK = false;
    Vec3 eta{1.0f, 1.0f, 1.0f}, k{};
    Vec3 specular{1.0f, 1.0f, 1.0f};

    /// The BSDF of `material` at a hit whose textures give `inputs`; `flags` are
    /// materialFlags(material) (an integrator finds them once per render).
    static Bsdf at(const detail::Material& material, const BsdfFlags& flags,
                   const BsdfInputs& inputs);
    /// Builds the BSDF of `material` with (possibly textured) albedo and the material's
    /// factors otherwise.
    static Bsdf fromMaterial(const detail::Material& material, const Vec3& albedo);
    /// Builds the glTF metallic-roughness BSDF from per-hit values: the base colour (factor ×
    /// texture), metallic and perceptual roughness (factors × the texture's B and G), the IOR
    /// (KHR_materials_ior) and the transmission factor. metallic and roughness are clamped to
    /// [0, 1]; alpha = max(roughness², kMinGgxAlpha).
    static Bsdf metallicRoughness(const Vec3& baseColor, float metallic, float roughness,
                                  float ior = 1.5f, float transmission = 0.0f);
    /// A BSDF of `kind` with the fields every kind but metallicRoughness takes from its material:
    /// albedo (possibly textured), ior, alpha = roughness², the conductor's Fresnel terms.
    static Bsdf fromFactors(const MaterialKind& kind, const detail::Material& material,
                            const Vec3& albedo);

    /// True when every event is a delta (mirror, smooth dielectric, conductor with tiny alpha).
    bool isSpecular() const { return flags.specular; }
    /// True when light passes the surface (dielectric, metallicRoughness with transmission):
    /// wo and wi may lie on either side, wo.z < 0 meaning wo is inside.
    bool transmits() const { return flags.transmits; }
    /// Which of sample()'s numbers it reads: the direction pair `u` (diffuse, conductor,
    /// metallicRoughness, rough dielectric: the microfacet) and the component number `uc`
    /// (dielectric: reflect or refract). A sampler with a fixed slot per number need not draw
    /// the others.
    bool readsDirectionPair() const { return flags.directionPair; }
    bool readsComponentNumber() const { return flags.componentNumber; }
    /// f(wo, wi) without the cosine and the density of sample() producing wi; both 0 for
    /// specular BSDFs.
    BsdfValue evaluate(const Vec3& wo, const Vec3& wi) const;
    /// f(wo, wi) without the cosine; 0 for specular BSDFs (evaluate()'s f).
    Vec3 eval(const Vec3& wo, const Vec3& wi) const { return evaluate(wo, wi).f; }
    /// Solid-angle density of sample() producing wi; 0 for specular BSDFs (evaluate()'s pdf).
    float pdf(const Vec3& wo, const Vec3& wi) const { return evaluate(wo, wi).pdf; }
    /// Samples wi from u (2D) and uc (for discrete choices); false when no valid direction.
    bool sample(const Vec3& wo, Vec2 u, float uc, BsdfSample& out) const;
};

/// A kind of material: its name, its parameters and its BSDF. One object per kind, defined in
/// the kind's file and listed in material_kinds.h.
struct MaterialKind {
    const char* name;     ///< scene.json's "type" (detail::materialTypeName)
    const char* summary;  ///< what it is, one sentence (docs/scene-format.md's table)
    /// scene.json's materials may be of this kind; else only importers make it (glTF, MTL), and
    /// its parameters are a glTF shape's `edits`.
    bool inSceneJson;
    /// Its parameters beside those of every kind (texture, emission): read, edited in a look
    /// panel and written as they describe.
    std::span<const MaterialParameter> parameters;
    /// What the BSDF built from the material's factors does (materialFlags).
    BsdfFlags (*flags)(const detail::Material& material);
    /// The BSDF at a hit (Bsdf::at); null for a kind whose BSDF takes the material's factors
    /// as they are (Bsdf::fromFactors) and its flags, built inline.
    Bsdf (*bsdf)(const detail::Material& material, const BsdfInputs& inputs);
    /// f and pdf of a BSDF of this kind that is not specular (Bsdf::evaluate).
    BsdfValue (*evaluate)(const Bsdf& b, const Vec3& wo, const Vec3& wi);
    /// Bsdf::sample.
    bool (*sample)(const Bsdf& b, const Vec3& wo, Vec2 u, float uc, BsdfSample& out);
};

#define GLINT_DECLARE_MATERIAL_KIND(Enum, object) extern const MaterialKind object;
GLINT_MATERIAL_KINDS(GLINT_DECLARE_MATERIAL_KIND)
#undef GLINT_DECLARE_MATERIAL_KIND

/// Every material kind, indexed by detail::MaterialType.
inline constexpr const MaterialKind* kMaterialKinds[] = {
#define GLINT_MATERIAL_KIND_ADDRESS(Enum, object) &object,
    GLINT_MATERIAL_KINDS(GLINT_MATERIAL_KIND_ADDRESS)
#undef GLINT_MATERIAL_KIND_ADDRESS
};

/// The kind of material `type`.
inline const MaterialKind& materialKind(detail::MaterialType type) {
    return *kMaterialKinds[int(type)];
}

/// What the BSDF of `material` does, known before a hit is shaded (its factors' BsdfFlags).
inline BsdfFlags materialFlags(const detail::Material& material) {
    return materialKind(material.type).flags(material);
}

// Per-material implementations (wo, wi in the local frame).
BsdfValue diffuseEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi);
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
BsdfValue roughDielectricEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi);
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
BsdfValue conductorEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi);
bool conductorSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out);

/// Schlick's f0 of a dielectric of index `ior` seen from air: ((ior − 1) / (ior + 1))².
float schlickF0(float ior);
/// Probability that metallicRoughnessSample picks GGX reflection at wo (else, split by the
/// transmission factor, GGX refraction or the Lambert lobe).
float metallicRoughnessSpecularProbability(const Bsdf& b, const Vec3& wo);
BsdfValue metallicRoughnessEvaluate(const Bsdf& b, const Vec3& wo, const Vec3& wi);
bool metallicRoughnessSample(const Bsdf& b, const Vec3& wo, Vec2 u, BsdfSample& out);

// Bsdf's dispatch through its kind, inline: called at every hit.

inline Bsdf Bsdf::at(const detail::Material& material, const BsdfFlags& flags,
                     const BsdfInputs& inputs) {
    const MaterialKind& kind = materialKind(material.type);
    if (kind.bsdf) return kind.bsdf(material, inputs);
    Bsdf b = fromFactors(kind, material, inputs.albedo);
    b.flags = flags;
    return b;
}

inline Bsdf Bsdf::fromMaterial(const detail::Material& material, const Vec3& albedo) {
    return at(material, materialFlags(material),
              {albedo, material.metallic, material.roughness, material.transmission});
}

inline Bsdf Bsdf::fromFactors(const MaterialKind& kind, const detail::Material& material,
                              const Vec3& albedo) {
    Bsdf b;
    b.kind = &kind;
    b.albedo = albedo;
    b.ior = material.ior;
    b.alpha = material.roughness * material.roughness;
    b.hasEtaK = material.hasEtaK;
    b.eta = material.eta;
    b.k = material.k;
    b.specular = material.specular;
    return b;
}

inline BsdfValue Bsdf::evaluate(const Vec3& wo, const Vec3& wi) const {
    if (flags.specular) return {};
    return kind->evaluate(*this, wo, wi);
}

inline bool Bsdf::sample(const Vec3& wo, Vec2 u, float uc, BsdfSample& out) const {
    return kind->sample(*this, wo, u, uc, out);
}

}  // namespace glint::render
