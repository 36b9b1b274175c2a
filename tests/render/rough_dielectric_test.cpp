// Tests of the transmitting BSDFs beyond the chi-square tests of their sampling
// (sampling_chi2_test.cpp): rough glass (materials/rough_dielectric.cpp) and the glTF
// metallic-roughness material with KHR_materials_transmission (materials/metallic_roughness.cpp).
// The smooth limit is exactly the smooth dielectric; eval obeys the generalised reciprocity of
// refraction; sample() agrees with pdf() and eval() where lobes are too narrow for a chi-square
// grid; white-furnace bounds. Fixed seeds; Monte Carlo bounds allow 4 standard errors (each
// fails by chance with p ≈ 6e-5) plus the stated bias.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "materials/bsdf.h"
#include "sampling/rng.h"

namespace glint::render {
namespace {

Vec3 direction(float thetaDeg, float phiDeg) {
    const float t = thetaDeg * kPi / 180.0f, p = phiDeg * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

Bsdf glass(float roughness, float ior, const Vec3& tint = {1.0f, 1.0f, 1.0f}) {
    detail::Material m;
    m.type = detail::MaterialType::Dielectric;
    m.ior = ior;
    m.roughness = roughness;
    return Bsdf::fromMaterial(m, tint);
}

/// A direction uniform on the whole sphere.
Vec3 sphereDirection(Rng& rng) {
    const float z = 2.0f * rng.uniform() - 1.0f;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * rng.uniform();
    return normalize(Vec3{r * std::cos(phi), r * std::sin(phi), z});
}

/// What a BSDF sample carries, summed: the energy reflected, and the energy transmitted (the
/// radiance weight times (η_wi / η_wo)², which undoes the 1/η² radiance scaling), each with its
/// standard error.
struct Split {
    double reflected = 0, transmitted = 0, sigmaR = 0, sigmaT = 0;
    double total() const { return reflected + transmitted; }
};

Split energySplit(const Bsdf& bsdf, const Vec3& wo, float ior, std::uint64_t seed, int n = 200000) {
    Rng rng(seed, 0, 0);
    double sum[2] = {}, sum2[2] = {};
    for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s)) continue;
        const bool refracted = (s.wi.z > 0.0f) != (wo.z > 0.0f);
        const float eta = wo.z > 0.0f ? ior : 1.0f / ior;  // η_wi / η_wo when refracted
        const double w = double(s.weight.y) * (refracted ? double(eta) * eta : 1.0);
        sum[refracted] += w;
        sum2[refracted] += w * w;
    }
    Split r;
    const double m0 = sum[0] / n, m1 = sum[1] / n;
    r.reflected = m0;
    r.transmitted = m1;
    r.sigmaR = std::sqrt(std::max(0.0, sum2[0] / n - m0 * m0) / n);
    r.sigmaT = std::sqrt(std::max(0.0, sum2[1] / n - m1 * m1) / n);
    return r;
}

TEST(RoughDielectric, SmoothLimitIsTheSmoothDielectric) {
    // Roughness 0 (today's scenes) and any alpha below kMinGgxAlpha: a delta BSDF whose samples
    // are dielectricSample's, bit for bit.
    for (const float roughness : {0.0f, 0.03f}) {
        const Bsdf rough = glass(roughness, 1.5f, {0.9f, 0.8f, 0.7f});
        ASSERT_LT(rough.alpha, kMinGgxAlpha);
        EXPECT_TRUE(rough.isSpecular());
        EXPECT_TRUE(rough.transmits());
        EXPECT_FALSE(rough.readsDirectionPair());
        EXPECT_TRUE(rough.readsComponentNumber());
        Rng rng(3, 0, 0);
        for (int i = 0; i < 1000; ++i) {
            const Vec3 wo = sphereDirection(rng);
            const float uc = rng.uniform();
            BsdfSample a, b;
            const bool okA = rough.sample(wo, {rng.uniform(), rng.uniform()}, uc, a);
            const bool okB = dielectricSample(rough, wo, uc, b);
            ASSERT_EQ(okA, okB);
            if (!okA) continue;
            EXPECT_EQ(a.wi.x, b.wi.x);
            EXPECT_EQ(a.wi.y, b.wi.y);
            EXPECT_EQ(a.wi.z, b.wi.z);
            EXPECT_EQ(a.weight.x, b.weight.x);
            EXPECT_EQ(a.weight.z, b.weight.z);
            EXPECT_EQ(a.pdf, 0.0f);
            EXPECT_TRUE(a.specular);
            EXPECT_TRUE(isBlack(rough.eval(wo, a.wi)));
            EXPECT_EQ(rough.pdf(wo, a.wi), 0.0f);
        }
    }
    // Above the threshold the BSDF is a sampled one that reads both numbers.
    const Bsdf rough = glass(0.2f, 1.5f);
    EXPECT_FALSE(rough.isSpecular());
    EXPECT_TRUE(rough.readsDirectionPair());
    EXPECT_TRUE(rough.readsComponentNumber());
}

/// Pairs across the whole sphere, and pairs near the mirror and the refracted direction of wo
/// (where a narrow lobe lives).
std::vector<std::pair<Vec3, Vec3>> directionPairs(float ior, std::uint64_t seed) {
    Rng rng(seed, 0, 0);
    std::vector<std::pair<Vec3, Vec3>> pairs;
    for (int i = 0; i < 400; ++i) {
        const Vec3 wo = sphereDirection(rng);
        pairs.push_back({wo, sphereDirection(rng)});
        const Vec3 tilt{0.1f * (2.0f * rng.uniform() - 1.0f), 0.1f * (2.0f * rng.uniform() - 1.0f),
                        0.0f};
        pairs.push_back({wo, normalize(Vec3{-wo.x, -wo.y, wo.z} + tilt)});
        Vec3 t;
        const Vec3 n{0.0f, 0.0f, wo.z > 0.0f ? 1.0f : -1.0f};
        if (refractThrough(wo * n.z, {0, 0, 1}, wo.z > 0.0f ? ior : 1.0f / ior, t))
            pairs.push_back({wo, normalize(t * n.z + tilt)});
    }
    return pairs;
}

/// f(wo, wi) / η_wo² = f(wi, wo) / η_wi² (Veach 1997, eq. 5.14): reflection is symmetric, a
/// refraction pair scaled by the squared ratio of the indices. Relative 2e-3 for the rounding
/// of the half vector where a narrow lobe is steep.
void expectReciprocal(const Bsdf& bsdf, float ior, const std::string& what) {
    int checked = 0;
    for (const auto& [wo, wi] : directionPairs(ior, 17)) {
        const Vec3 f = bsdf.eval(wo, wi), g = bsdf.eval(wi, wo);
        const float etaO = wo.z > 0.0f ? 1.0f : ior, etaI = wi.z > 0.0f ? 1.0f : ior;
        for (int c = 0; c < 3; ++c) {
            const float a = f[c] / (etaO * etaO), b = g[c] / (etaI * etaI);
            EXPECT_NEAR(a, b, 2e-3f * std::max(a, b) + 1e-7f)
                << what << " wo " << wo.x << " " << wo.y << " " << wo.z << " wi " << wi.x << " "
                << wi.y << " " << wi.z;
        }
        if (::testing::Test::HasFailure()) return;
        if (f.y > 0.0f && (wo.z > 0.0f) != (wi.z > 0.0f)) ++checked;
    }
    EXPECT_GT(checked, 100) << what << ": too few refraction pairs with f > 0";
}

TEST(RoughDielectric, EvalObeysTheReciprocityOfRefraction) {
    for (const float ior : {1.5f, 2.4f})
        for (const float roughness : {0.1f, 0.3f, 0.7f})
            expectReciprocal(
                glass(roughness, ior, {0.9f, 0.7f, 0.5f}), ior,
                "glass ior " + std::to_string(ior) + " roughness " + std::to_string(roughness));
}

TEST(RoughDielectric, NarrowLobesSampleAsPdfAndEvalSay) {
    // The chi-square grid cannot resolve roughness 0.05 (alpha 0.0025); check every sample's
    // density and weight instead, from both sides, past the critical angle included.
    for (const float roughness : {0.05f, 0.1f, 0.3f}) {
        const Bsdf bsdf = glass(roughness, 1.5f, {0.9f, 0.7f, 0.5f});
        for (const Vec3& wo : {direction(0, 0), direction(50, 30), direction(89, 30),
                               -direction(20, 70), -direction(60, 70)}) {
            Rng rng(9, 0, 0);
            int valid = 0;
            for (int i = 0; i < 2000; ++i) {
                BsdfSample s;
                if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s)) continue;
                ++valid;
                ASSERT_FALSE(s.specular);
                EXPECT_NEAR(length(s.wi), 1.0f, 1e-5f);
                const float pdf = bsdf.pdf(wo, s.wi);
                EXPECT_NEAR(s.pdf, pdf, 1e-5f * pdf);
                const Vec3 expect = bsdf.eval(wo, s.wi) * (std::abs(s.wi.z) / pdf);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0.0f);
                    EXPECT_NEAR(s.weight[c], expect[c], 1e-4f * (1.0f + expect[c]));
                }
                if (::testing::Test::HasFailure()) return;
            }
            EXPECT_GT(valid, 1000) << "roughness " << roughness << " wo.z " << wo.z;
        }
    }
}

TEST(RoughDielectric, WhiteFurnaceConservesAtMostAllEnergy) {
    // Single scattering loses what the microfacets mask (G2 < G1), never gains: reflected plus
    // transmitted energy <= 1 from both sides, and close to 1 when smooth.
    for (const float roughness : {0.05f, 0.3f, 0.6f, 1.0f})
        for (const Vec3& wo :
             {direction(10, 0), direction(70, 0), -direction(30, 0), -direction(70, 0)}) {
            const Split e = energySplit(glass(roughness, 1.5f), wo, 1.5f, 21);
            const double sigma = e.sigmaR + e.sigmaT;
            EXPECT_LE(e.total(), 1.0 + 4.0 * sigma)
                << "roughness " << roughness << " wo.z " << wo.z;
            if (roughness <= 0.3f) {
                EXPECT_GT(e.total(), 0.9) << "roughness " << roughness;
            }
        }
}

TEST(RoughDielectric, NearlySmoothGlassSplitsEnergyAsFresnelSays) {
    // Roughness 0.05 (alpha 0.0025) against the smooth dielectric's Fresnel reflectance F(cosθ):
    // microfacets within a few alpha of the normal change F by less than 0.005 at these angles,
    // 6° or more from the critical angle (stated bias), and masking loses less than that.
    for (const float ior : {1.5f, 1.33f})
        for (const Vec3& wo : {direction(0, 0), direction(45, 0), direction(75, 0),
                               -direction(20, 0), -direction(35, 0), -direction(70, 0)}) {
            const float eta = wo.z > 0.0f ? ior : 1.0f / ior;
            const double fresnel = fresnelDielectric(std::abs(wo.z), eta);
            const Split e = energySplit(glass(0.05f, ior), wo, ior, 33);
            EXPECT_NEAR(e.reflected, fresnel, 4.0 * e.sigmaR + 5e-3)
                << "ior " << ior << " wo.z " << wo.z;
            EXPECT_NEAR(e.transmitted, 1.0 - fresnel, 4.0 * e.sigmaT + 5e-3)
                << "ior " << ior << " wo.z " << wo.z;
        }
}

// The metallic-roughness material with KHR_materials_transmission.

const Vec3 kBase{0.8f, 0.6f, 0.4f};

TEST(MetallicRoughnessTransmission, TransmitsBothWaysAndStaysOneSidedWithout) {
    const Bsdf t = Bsdf::metallicRoughness(kBase, 0.0f, 0.3f, 1.5f, 0.7f);
    EXPECT_TRUE(t.transmits());
    EXPECT_FALSE(t.isSpecular());
    EXPECT_TRUE(t.readsDirectionPair());
    EXPECT_FALSE(t.readsComponentNumber());
    // Light passes: a refraction pair from outside and from inside.
    EXPECT_FALSE(isBlack(t.eval(direction(30, 0), -direction(20, 0))));
    EXPECT_FALSE(isBlack(t.eval(-direction(20, 0), direction(30, 0))));
    EXPECT_GT(t.pdf(direction(30, 0), -direction(20, 0)), 0.0f);
    // Metal does not transmit.
    const Bsdf metal = Bsdf::metallicRoughness(kBase, 1.0f, 0.3f, 1.5f, 0.7f);
    EXPECT_TRUE(isBlack(metal.eval(direction(30, 0), -direction(20, 0))));
    // Without transmission the material is opaque as before.
    EXPECT_FALSE(Bsdf::metallicRoughness(kBase, 0.0f, 0.3f).transmits());
}

TEST(MetallicRoughnessTransmission, LambertLobeIsWeightedByOneMinusTransmission) {
    // On a reflection pair f(T) = layer + (1 − T) · base: linear in T, and at T = 1 what the
    // black base reflects (only the GGX layer), whatever the base colour.
    Rng rng(5, 0, 0);
    for (int i = 0; i < 200; ++i) {
        const Vec3 wo =
            normalize(Vec3{sphereDirection(rng).x, sphereDirection(rng).y, 0.05f + rng.uniform()});
        const Vec3 wi =
            normalize(Vec3{sphereDirection(rng).x, sphereDirection(rng).y, 0.05f + rng.uniform()});
        for (const float metallic : {0.0f, 0.4f}) {
            auto f = [&](const Vec3& base, float transmission) {
                return Bsdf::metallicRoughness(base, metallic, 0.4f, 1.5f, transmission)
                    .eval(wo, wi);
            };
            const Vec3 f0 = f(kBase, 0.0f), f1 = f(kBase, 1.0f), fh = f(kBase, 0.5f);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(fh[c], 0.5f * (f0[c] + f1[c]), 1e-5f * (1.0f + f0[c]));
            if (metallic == 0.0f) {
                const Vec3 layer = f({0.0f, 0.0f, 0.0f}, 0.0f);
                for (int c = 0; c < 3; ++c) EXPECT_NEAR(f1[c], layer[c], 1e-6f * (1 + layer[c]));
            }
        }
    }
}

TEST(MetallicRoughnessTransmission, EvalObeysTheReciprocityOfRefraction) {
    for (const float roughness : {0.1f, 0.4f, 1.0f})
        for (const float transmission : {0.5f, 1.0f})
            expectReciprocal(Bsdf::metallicRoughness(kBase, 0.2f, roughness, 1.5f, transmission),
                             1.5f,
                             "metallicRoughness roughness " + std::to_string(roughness) +
                                 " transmission " + std::to_string(transmission));
}

TEST(MetallicRoughnessTransmission, SampleAgreesWithPdfAndEvalDownToRoughnessZero) {
    for (const float roughness : {0.0f, 0.05f, 0.3f, 1.0f})
        for (const float metallic : {0.0f, 0.5f}) {
            const Bsdf bsdf = Bsdf::metallicRoughness(kBase, metallic, roughness, 1.5f, 0.8f);
            for (const Vec3& wo : {direction(0, 0), direction(60, 30), direction(88, 30),
                                   -direction(25, 70), -direction(65, 70)}) {
                Rng rng(13, 0, 0);
                int valid = 0;
                for (int i = 0; i < 2000; ++i) {
                    BsdfSample s;
                    if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s))
                        continue;
                    ++valid;
                    const float pdf = bsdf.pdf(wo, s.wi);
                    EXPECT_NEAR(s.pdf, pdf, 1e-5f * pdf);
                    const Vec3 expect = bsdf.eval(wo, s.wi) * (std::abs(s.wi.z) / pdf);
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0.0f);
                        EXPECT_NEAR(s.weight[c], expect[c], 1e-4f * (1.0f + expect[c]));
                    }
                    if (::testing::Test::HasFailure()) return;
                }
                EXPECT_GT(valid, 1000) << "roughness " << roughness << " wo.z " << wo.z;
            }
        }
}

TEST(MetallicRoughnessTransmission, ClearGlassSplitsEnergyAsSchlickSays) {
    // White base, metallic 0, transmission 1, roughness 0 (alpha clamped to 1e-3): reflected
    // F(cosθ) and transmitted 1 − F (Schlick's F with f0 = 0.04 from outside, at the refracted
    // angle from inside and 1 past the critical angle): a solid glass surface that conserves
    // energy. Bias from the lobe's width below 5e-3.
    const float ior = 1.5f, f0 = 0.04f;
    const Bsdf bsdf = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 0.0f, 0.0f, ior, 1.0f);
    for (const Vec3& wo : {direction(0, 0), direction(45, 0), direction(80, 0), -direction(20, 0),
                           -direction(40, 0), -direction(60, 0)}) {
        float cosOutside = std::abs(wo.z);
        double fresnel = 1.0;
        if (wo.z < 0.0f) {
            const float sin2T = (1.0f - wo.z * wo.z) * ior * ior;
            cosOutside = sin2T < 1.0f ? std::sqrt(1.0f - sin2T) : -1.0f;
        }
        if (cosOutside >= 0.0f) fresnel = f0 + (1.0f - f0) * std::pow(1.0f - cosOutside, 5.0f);
        const Split e = energySplit(bsdf, wo, ior, 41);
        EXPECT_NEAR(e.reflected, fresnel, 4.0 * e.sigmaR + 5e-3) << "wo.z " << wo.z;
        EXPECT_NEAR(e.transmitted, 1.0 - fresnel, 4.0 * e.sigmaT + 5e-3) << "wo.z " << wo.z;
    }
}

TEST(MetallicRoughnessTransmission, WhiteFurnaceBound) {
    // A white transmitting base reflects and transmits at most all energy where the opaque one
    // does (up to 45°: the specified Fresnel mix over-counts at grazing angles, see
    // metallic_roughness_test.cpp), for any transmission.
    for (const float roughness : {0.1f, 0.5f, 1.0f})
        for (const float transmission : {0.3f, 1.0f})
            for (const Vec3& wo : {direction(10, 0), direction(45, 0), -direction(30, 0)}) {
                const Bsdf bsdf = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 0.0f, roughness, 1.5f,
                                                          transmission);
                const Split e = energySplit(bsdf, wo, 1.5f, 51);
                EXPECT_LE(e.total(), 1.0 + 4.0 * (e.sigmaR + e.sigmaT) + 1e-2)
                    << "roughness " << roughness << " transmission " << transmission << " wo.z "
                    << wo.z;
            }
}

}  // namespace
}  // namespace glint::render
