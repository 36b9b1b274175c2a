// Tests of the glTF metallic-roughness BSDF (materials/metallic_roughness.cpp) beyond the
// chi-square tests of its sampling (sampling_chi2_test.cpp, roughness >= 0.2): sample() agrees
// with pdf() and eval() down to the clamped roughness 0, eval is reciprocal, the closed-form
// limits (black dielectric = Schlick conductor with f0, metal = Schlick conductor with the base
// colour, linear in metallic, Lambert × (1 − F) base), and white-furnace bounds. Fixed seeds;
// Monte Carlo bounds allow 4 standard errors (each fails by chance with p ≈ 3e-5).
#include <gtest/gtest.h>

#include <string>

#include "materials/bsdf.h"
#include "sampling/rng.h"

namespace glint::render {
namespace {

constexpr float kMetallics[] = {0.0f, 0.5f, 1.0f};
/// 0 is clamped to alpha = kMinGgxAlpha; 0.05 is alpha 0.0025.
constexpr float kRoughnesses[] = {0.0f, 0.05f, 0.3f, 0.7f, 1.0f};
constexpr float kThetaOs[] = {0.0f, 30.0f, 60.0f, 85.0f, 89.5f};
const Vec3 kBaseColor{0.8f, 0.5f, 0.2f};

Vec3 direction(float thetaDeg, float phiDeg) {
    const float t = thetaDeg * kPi / 180.0f, p = phiDeg * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

std::string label(float metallic, float roughness, float thetaO = -1.0f) {
    std::string s =
        "metallic " + std::to_string(metallic) + " roughness " + std::to_string(roughness);
    if (thetaO >= 0.0f) s += " θo " + std::to_string(thetaO);
    return s;
}

/// Schlick's Fresnel with reflectance f0 at normal incidence.
float schlick(float f0, float cosTheta) {
    return f0 + (1.0f - f0) * std::pow(1.0f - cosTheta, 5.0f);
}

/// A Monte Carlo estimate of the directional albedo ∫ f(wo, wi) cosθi dωi from sample()'s
/// weights, and its standard error, per channel.
struct Albedo {
    Vec3 mean, sigma;
};

Albedo directionalAlbedo(const Bsdf& bsdf, const Vec3& wo, std::uint64_t seed, int n = 200000) {
    Rng rng(seed, 0, 0);
    double sum[3] = {}, sum2[3] = {};
    for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s)) continue;
        for (int c = 0; c < 3; ++c) {
            sum[c] += s.weight[c];
            sum2[c] += double(s.weight[c]) * s.weight[c];
        }
    }
    Albedo a;
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / n;
        a.mean[c] = float(mean);
        a.sigma[c] = float(std::sqrt(std::max(0.0, sum2[c] / n - mean * mean) / n));
    }
    return a;
}

/// A random direction on the upper hemisphere (uniform in solid angle).
Vec3 upperDirection(Rng& rng) {
    const float z = rng.uniform();
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * rng.uniform();
    return {r * std::cos(phi), r * std::sin(phi), std::max(z, 1e-4f)};
}

/// Pairs (wo, wi) for pointwise checks: uniform pairs and pairs near the mirror direction
/// (where a narrow lobe is large), both in the upper hemisphere.
std::vector<std::pair<Vec3, Vec3>> directionPairs(float alpha, std::uint64_t seed) {
    Rng rng(seed, 0, 0);
    std::vector<std::pair<Vec3, Vec3>> pairs;
    for (int i = 0; i < 500; ++i) {
        const Vec3 wo = normalize(upperDirection(rng));
        pairs.push_back({wo, normalize(upperDirection(rng))});
        // Mirror direction tilted by about alpha.
        const Vec3 tilt{alpha * (2.0f * rng.uniform() - 1.0f),
                        alpha * (2.0f * rng.uniform() - 1.0f), 0.0f};
        const Vec3 wi = normalize(Vec3{-wo.x, -wo.y, wo.z} + tilt);
        if (wi.z > 0.0f) pairs.push_back({wo, wi});
    }
    return pairs;
}

void expectNearVec(const Vec3& a, const Vec3& b, float relative, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(a[c], b[c], relative * std::max(std::abs(a[c]), std::abs(b[c])) + 1e-7f)
            << what << " channel " << c;
}

TEST(MetallicRoughness, SampleAgreesWithPdfAndEval) {
    // Every sample: wi unit and above the surface, pdf == pdf(wo, wi), weight == f cos / pdf,
    // finite and non-negative; and most samples succeed (the GGX lobe loses only what it
    // reflects below the horizon).
    for (const float metallic : kMetallics)
        for (const float roughness : kRoughnesses) {
            const Bsdf bsdf = Bsdf::metallicRoughness(kBaseColor, metallic, roughness);
            for (const float thetaO : kThetaOs) {
                SCOPED_TRACE(label(metallic, roughness, thetaO));
                const Vec3 wo = direction(thetaO, 25.0f);
                Rng rng(7, 0, 0);
                int failures = 0, valid = 0;
                const int n = 2000;
                for (int i = 0; i < n; ++i) {
                    BsdfSample s;
                    if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s))
                        continue;
                    ++valid;
                    EXPECT_FALSE(s.specular);
                    EXPECT_GT(s.wi.z, 0.0f);
                    EXPECT_NEAR(length(s.wi), 1.0f, 1e-5f);
                    const float pdf = bsdf.pdf(wo, s.wi);
                    EXPECT_NEAR(s.pdf, pdf, 1e-5f * pdf);
                    const Vec3 expect = bsdf.eval(wo, s.wi) * (s.wi.z / pdf);
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_TRUE(std::isfinite(s.weight[c]) && s.weight[c] >= 0.0f);
                        EXPECT_NEAR(s.weight[c], expect[c], 1e-5f * (1.0f + expect[c]));
                    }
                    if (::testing::Test::HasFailure() && ++failures > 3) return;
                }
                // At 89.5° a rough lobe reflects up to half of its samples below the horizon.
                EXPECT_GT(valid, n / 3);
            }
        }
}

TEST(MetallicRoughness, EvalIsReciprocal) {
    // f(wo, wi) = f(wi, wo): D, G2 and |v·h| = |l·h| are symmetric; allow float rounding of the
    // half vector (relative 1e-3 where a narrow lobe is steep).
    for (const float metallic : kMetallics)
        for (const float roughness : kRoughnesses) {
            SCOPED_TRACE(label(metallic, roughness));
            const Bsdf bsdf = Bsdf::metallicRoughness(kBaseColor, metallic, roughness);
            int checked = 0;
            for (const auto& [wo, wi] : directionPairs(bsdf.alpha, 11)) {
                expectNearVec(bsdf.eval(wo, wi), bsdf.eval(wi, wo), 1e-3f, "f");
                if (::testing::Test::HasFailure()) return;
                ++checked;
            }
            EXPECT_GT(checked, 900);
        }
}

TEST(MetallicRoughness, OpaqueAndOneSided) {
    // Without transmission nothing passes the surface, and wo below it (the integrator flips the
    // frame first) samples nothing.
    const Bsdf bsdf = Bsdf::metallicRoughness(kBaseColor, 0.3f, 0.5f);
    const Vec3 wo = direction(40, 10);
    EXPECT_FALSE(bsdf.isSpecular());
    EXPECT_TRUE(bsdf.readsDirectionPair());
    EXPECT_FALSE(bsdf.readsComponentNumber());
    EXPECT_TRUE(isBlack(bsdf.eval(wo, direction(130, 200))));
    EXPECT_EQ(bsdf.pdf(wo, direction(130, 200)), 0.0f);
    EXPECT_TRUE(isBlack(bsdf.eval(direction(100, 0), direction(40, 200))));
    BsdfSample s;
    EXPECT_FALSE(bsdf.sample(direction(100, 0), {0.3f, 0.4f}, 0.5f, s));
    // fromMaterial reads the factors of an untextured material.
    detail::Material m;
    m.type = detail::MaterialType::MetallicRoughness;
    m.metallic = 0.3f;
    m.roughness = 0.5f;
    m.ior = 1.5f;
    const Bsdf fromMaterial = Bsdf::fromMaterial(m, kBaseColor);
    EXPECT_EQ(fromMaterial.alpha, 0.25f);
    EXPECT_EQ(fromMaterial.metallic, 0.3f);
    const Vec3 wi = direction(20, 150);
    expectNearVec(fromMaterial.eval(wo, wi), bsdf.eval(wo, wi), 0.0f, "fromMaterial");
    // Roughness 0 is clamped to a sampled lobe, not a delta.
    EXPECT_EQ(Bsdf::metallicRoughness(kBaseColor, 1.0f, 0.0f).alpha, kMinGgxAlpha);
}

TEST(MetallicRoughness, BaseIsLambertTimesOneMinusFresnel) {
    // With metallic 0, f(base c) − f(base 0) = c (1 − F(v·h)) / π, F Schlick with
    // f0 = ((ior − 1) / (ior + 1))² (0.04 at 1.5, 1/9 at 2).
    for (const float ior : {1.5f, 2.0f})
        for (const float roughness : kRoughnesses) {
            SCOPED_TRACE(label(0.0f, roughness) + " ior " + std::to_string(ior));
            const Bsdf coloured = Bsdf::metallicRoughness(kBaseColor, 0.0f, roughness, ior);
            const Bsdf black = Bsdf::metallicRoughness({}, 0.0f, roughness, ior);
            const float f0 = ior == 1.5f ? 0.04f : 1.0f / 9.0f;
            for (const auto& [wo, wi] : directionPairs(black.alpha, 12)) {
                const float vh = dot(wo, normalize(wo + wi));
                const Vec3 expect = kBaseColor * ((1.0f - schlick(f0, vh)) / kPi);
                // The difference cancels the layer, which near the peak of a narrow lobe is
                // 1e5 times larger: allow its float rounding.
                const Vec3 f = coloured.eval(wo, wi);
                const Vec3 base = f - black.eval(wo, wi);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(base[c], expect[c], 1e-4f * expect[c] + 1e-6f * f[c]);
                if (::testing::Test::HasFailure()) return;
            }
        }
}

TEST(MetallicRoughness, LimitsAreSchlickConductors) {
    // Base colour 0 and metallic 0: the specular layer alone, a GGX conductor with Schlick f0;
    // metallic 1: a GGX conductor with Schlick F0 = base colour. eval and pdf both agree (the
    // mixture picks the GGX lobe always when the base reflects nothing).
    for (const float roughness : {0.05f, 0.3f, 0.7f, 1.0f}) {
        SCOPED_TRACE(label(-1.0f, roughness));
        detail::Material m;
        m.type = detail::MaterialType::Conductor;
        m.roughness = roughness;
        struct Limit {
            Bsdf mr;
            Vec3 specular;
        };
        const Limit limits[] = {
            {Bsdf::metallicRoughness({}, 0.0f, roughness, 1.5f), {0.04f, 0.04f, 0.04f}},
            {Bsdf::metallicRoughness({}, 0.0f, roughness, 1.8f),
             Vec3{1.0f, 1.0f, 1.0f} * (0.8f * 0.8f / (2.8f * 2.8f))},
            {Bsdf::metallicRoughness(kBaseColor, 1.0f, roughness), kBaseColor},
            {Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 1.0f, roughness), {1.0f, 1.0f, 1.0f}}};
        for (const Limit& limit : limits) {
            m.specular = limit.specular;
            const Bsdf conductor = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
            for (const auto& [wo, wi] : directionPairs(conductor.alpha, 13)) {
                expectNearVec(limit.mr.eval(wo, wi), conductor.eval(wo, wi), 1e-4f, "f");
                EXPECT_NEAR(limit.mr.pdf(wo, wi), conductor.pdf(wo, wi),
                            1e-4f * conductor.pdf(wo, wi));
                if (::testing::Test::HasFailure()) return;
            }
        }
    }
}

TEST(MetallicRoughness, LinearInMetallic) {
    // material = mix(dielectric, metal, metallic) (glTF 2.0, Appendix B.3.6).
    for (const float roughness : kRoughnesses) {
        SCOPED_TRACE(label(0.5f, roughness));
        const Bsdf half = Bsdf::metallicRoughness(kBaseColor, 0.25f, roughness);
        const Bsdf dielectric = Bsdf::metallicRoughness(kBaseColor, 0.0f, roughness);
        const Bsdf metal = Bsdf::metallicRoughness(kBaseColor, 1.0f, roughness);
        for (const auto& [wo, wi] : directionPairs(half.alpha, 14)) {
            const Vec3 expect = dielectric.eval(wo, wi) * 0.75f + metal.eval(wo, wi) * 0.25f;
            expectNearVec(half.eval(wo, wi), expect, 1e-4f, "f");
            if (::testing::Test::HasFailure()) return;
        }
    }
}

TEST(MetallicRoughnessFurnace, WhiteMetalReflectsAtMostAllLight) {
    // Base colour 1, metallic 1: F = 1, single-scattering GGX loses energy to masking but never
    // gains: E(wo) <= 1 + 4σ for every roughness and wo, and a smooth one (alpha <= 0.0025)
    // reflects everything up to 60° (E >= 0.999).
    for (const float roughness : kRoughnesses) {
        const Bsdf bsdf = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 1.0f, roughness);
        for (const float thetaO : kThetaOs) {
            SCOPED_TRACE(label(1.0f, roughness, thetaO));
            const Albedo a = directionalAlbedo(bsdf, direction(thetaO, 0), 21, 50000);
            EXPECT_LE(a.mean.x, 1.0f + 4.0f * a.sigma.x + 1e-5f);
            if (roughness <= 0.05f && thetaO <= 60.0f) {
                EXPECT_GE(a.mean.x, 0.999f);
            }
        }
    }
}

TEST(MetallicRoughnessFurnace, WhiteDielectricBaseUpTo45Degrees) {
    // Base colour 1, metallic 0 (Fresnel-weighted GGX layer over Lambert): E(wo) <= 1 + 4σ for
    // every roughness with θo <= 45°. Beyond, the glTF BRDF itself reflects more than it
    // receives (see DielectricBaseIsTheLayerPlusTheWeightedLambert).
    for (const float roughness : kRoughnesses) {
        const Bsdf bsdf = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 0.0f, roughness);
        for (const float thetaO : {0.0f, 15.0f, 30.0f, 45.0f}) {
            SCOPED_TRACE(label(0.0f, roughness, thetaO));
            const Albedo a = directionalAlbedo(bsdf, direction(thetaO, 0), 22, 50000);
            EXPECT_LE(a.mean.x, 1.0f + 4.0f * a.sigma.x);
        }
    }
    // A smooth white dielectric at normal incidence: the layer reflects f0 = 0.04 (v·h ≈ 1,
    // G2 ≈ 1) and the base (1 − F(v·h)) with v·h = cos(θi / 2) >= cos 45°, so
    // 1 − F ∈ [1 − F(0.707), 1 − f0] = [0.9579, 0.96]: E ∈ [0.9979, 1.0].
    const Bsdf smooth = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 0.0f, 0.05f);
    const Albedo a = directionalAlbedo(smooth, direction(0, 0), 23);
    EXPECT_GE(a.mean.x, 0.9979f - 4.0f * a.sigma.x);
    EXPECT_LE(a.mean.x, 1.0f + 4.0f * a.sigma.x);
}

TEST(MetallicRoughnessFurnace, DielectricBaseIsTheLayerPlusTheWeightedLambert) {
    // For every wo, E(white) − E(black) is the base's share ∫ (1 − F(v·h)) cosθi / π dωi, which
    // lies in [1 − F(v·h_min), 1 − f0]: the Lambert base is weighted by (1 − F) (not added at
    // full strength). v·h >= √((1 − sinθo) / 2) over the upper hemisphere. At grazing angles the
    // sum exceeds 1: the glTF BRDF weights the base by the Fresnel of v·h of the base's own
    // direction pair, not by what the layer reflects (glTF 2.0, Appendix B.3.5).
    for (const float roughness : kRoughnesses) {
        const Bsdf white = Bsdf::metallicRoughness({1.0f, 1.0f, 1.0f}, 0.0f, roughness);
        const Bsdf black = Bsdf::metallicRoughness({}, 0.0f, roughness);
        for (const float thetaO : kThetaOs) {
            SCOPED_TRACE(label(0.0f, roughness, thetaO));
            const Vec3 wo = direction(thetaO, 0);
            const Albedo w = directionalAlbedo(white, wo, 24, 50000);
            const Albedo b = directionalAlbedo(black, wo, 25, 50000);
            const float base = w.mean.x - b.mean.x;
            const float sigma = std::sqrt(w.sigma.x * w.sigma.x + b.sigma.x * b.sigma.x);
            const float vhMin =
                std::sqrt(std::max(0.0f, (1.0f - std::sin(thetaO * kPi / 180)) / 2));
            EXPECT_LE(base, 1.0f - 0.04f + 4.0f * sigma);
            EXPECT_GE(base, 1.0f - schlick(0.04f, vhMin) - 4.0f * sigma);
        }
    }
}

TEST(MetallicRoughnessFurnace, SmoothBlackDielectricReflectsSchlickFresnel) {
    // Base colour 0, metallic 0, roughness 0.05: a near-mirror with Schlick's F at cosθo
    // (v·h ≈ cosθo, G2 ≈ 1): E(wo) = F(cosθo) within 1 % where masking is negligible.
    const Bsdf bsdf = Bsdf::metallicRoughness({}, 0.0f, 0.05f);
    for (const float thetaO : {0.0f, 30.0f, 60.0f, 75.0f}) {
        SCOPED_TRACE(label(0.0f, 0.05f, thetaO));
        const Albedo a = directionalAlbedo(bsdf, direction(thetaO, 0), 26, 20000);
        const float f = schlick(0.04f, std::cos(thetaO * kPi / 180));
        EXPECT_NEAR(a.mean.x, f, 0.01f * f + 4.0f * a.sigma.x);
    }
}

TEST(MetallicRoughnessFurnace, RoughDielectricAtNormalIncidenceIsMostlyLambert) {
    // Metallic 0, roughness 1, wo = n: E(c) = c · B + E(0), B = ∫ (1 − F(cos(θi/2))) cosθi / π dωi
    // = 2 ∫ (1 − F(cos(θ/2))) cosθ sinθ dθ (Simpson's rule below), and the layer's E(0) small.
    double integral = 0.0;
    const int n = 2000;  // even
    for (int i = 0; i <= n; ++i) {
        const double theta = 0.5 * M_PI * i / n;
        const double g =
            (1.0 - schlick(0.04f, float(std::cos(theta / 2)))) * std::cos(theta) * std::sin(theta);
        integral += g * (i == 0 || i == n ? 1.0 : (i % 2 ? 4.0 : 2.0));
    }
    const double baseShare = 2.0 * integral * (0.5 * M_PI / n) / 3.0;
    // Between 1 − F(cos 45°) and 1 − f0 (0.9599).
    EXPECT_GT(baseShare, 1.0 - schlick(0.04f, std::sqrt(0.5f)));
    EXPECT_LT(baseShare, 0.96);
    const Vec3 wo{0.0f, 0.0f, 1.0f};
    const Albedo layer = directionalAlbedo(Bsdf::metallicRoughness({}, 0.0f, 1.0f), wo, 27);
    EXPECT_LT(layer.mean.x, 0.02f);
    const Albedo a = directionalAlbedo(Bsdf::metallicRoughness(kBaseColor, 0.0f, 1.0f), wo, 28);
    for (int c = 0; c < 3; ++c) {
        const float expect = kBaseColor[c] * float(baseShare) + layer.mean[c];
        EXPECT_NEAR(a.mean[c], expect, 4.0f * (a.sigma[c] + layer.sigma[c])) << "channel " << c;
    }
}

}  // namespace
}  // namespace glint::render
