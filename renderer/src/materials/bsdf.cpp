#include "materials/bsdf.h"

namespace glint::render {

using detail::MaterialType;

Bsdf Bsdf::fromMaterial(const detail::Material& material, const Vec3& albedo) {
    if (material.type == MaterialType::MetallicRoughness)
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

bool Bsdf::isSpecular() const {
    switch (type) {
        case MaterialType::Diffuse:
        case MaterialType::MetallicRoughness:
            return false;
        case MaterialType::Mirror:
            return true;
        case MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this);
        case MaterialType::Conductor:
            return alpha < kMinGgxAlpha;
    }
    return false;
}

Vec3 Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    switch (type) {
        case MaterialType::Diffuse:
            return diffuseEval(*this, wo, wi);
        case MaterialType::MetallicRoughness:
            return metallicRoughnessEval(*this, wo, wi);
        case MaterialType::Conductor:
            return alpha < kMinGgxAlpha ? Vec3{} : conductorEval(*this, wo, wi);
        case MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this) ? Vec3{} : roughDielectricEval(*this, wo, wi);
        default:
            return {};
    }
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    switch (type) {
        case MaterialType::Diffuse:
            return diffusePdf(*this, wo, wi);
        case MaterialType::MetallicRoughness:
            return metallicRoughnessPdf(*this, wo, wi);
        case MaterialType::Conductor:
            return alpha < kMinGgxAlpha ? 0.0f : conductorPdf(*this, wo, wi);
        case MaterialType::Dielectric:
            return roughDielectricIsSmooth(*this) ? 0.0f : roughDielectricPdf(*this, wo, wi);
        default:
            return 0.0f;
    }
}

bool Bsdf::sample(const Vec3& wo, Vec2 u, float uc, BsdfSample& out) const {
    switch (type) {
        case MaterialType::Diffuse:
            return diffuseSample(*this, wo, u, out);
        case MaterialType::MetallicRoughness:
            return metallicRoughnessSample(*this, wo, u, out);
        case MaterialType::Mirror:
            return mirrorSample(*this, wo, out);
        case MaterialType::Dielectric:
            return roughDielectricSample(*this, wo, u, uc, out);
        case MaterialType::Conductor:
            return conductorSample(*this, wo, u, out);
    }
    return false;
}

}  // namespace glint::render
