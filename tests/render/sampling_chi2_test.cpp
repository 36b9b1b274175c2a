// Chi-square goodness-of-fit of every BSDF's sampling routine and of environment-map sampling
// against its own pdf (the Mitsuba approach): directions are binned on a (cos θ, φ) grid of
// equal-solid-angle cells and compared with the pdf integrated numerically over each cell.
// Fixed seeds; each test rejects at the Šidák-corrected level for a family-wise α = 0.01 over
// all kChi2Tests tests below (rough glass and transmitting metallic-roughness sample both
// hemispheres). Delta BSDFs (mirror, smooth dielectric) are tested by their exact
// directions and a two-cell chi-square of the Fresnel reflect/refract choice.
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "lights/environment.h"
#include "lights/spherical_triangle.h"
#include "materials/bsdf.h"
#include "sampling/rng.h"
#include "test_util.h"

namespace glint::render {
namespace {

constexpr int kChi2Tests = 76;  // number of chi-square tests in this file
const double kAlpha = test::sidak(0.01, kChi2Tests);

constexpr int kThetaBins = 20, kPhiBins = 40, kSamples = 400000;

int cellOf(const Vec3& w) {
    const float z = std::clamp(w.z, -1.0f, 1.0f);
    float phi = std::atan2(w.y, w.x);
    if (phi < 0.0f) phi += 2.0f * kPi;
    const int t = std::clamp(int((z + 1.0f) * 0.5f * kThetaBins), 0, kThetaBins - 1);
    const int p = std::clamp(int(phi / (2.0f * kPi) * kPhiBins), 0, kPhiBins - 1);
    return t * kPhiBins + p;
}

/// Expected probability per cell of a solid-angle pdf (midpoint rule on a fine sub-grid), plus
/// a last cell holding the missing mass (samples the routine rejects).
std::vector<double> expectedCells(const std::function<float(const Vec3&)>& pdf, int sub) {
    std::vector<double> cells(kThetaBins * kPhiBins + 1, 0.0);
    const double dz = 2.0 / (kThetaBins * sub), dphi = 2.0 * kPi / (kPhiBins * sub);
    double total = 0.0;
    for (int i = 0; i < kThetaBins * sub; ++i) {
        const double z = -1.0 + (i + 0.5) * dz;
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        for (int j = 0; j < kPhiBins * sub; ++j) {
            const double phi = (j + 0.5) * dphi;
            const Vec3 w{float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)};
            // dω = dz dφ.
            const double p = double(pdf(w)) * dz * dphi;
            cells[(i / sub) * kPhiBins + j / sub] += p;
            total += p;
        }
    }
    cells.back() = std::max(0.0, 1.0 - total);
    return cells;
}

/// Runs the chi-square test of `sample` (returns false when it rejects) against `pdf`.
test::Chi2 runChi2(const std::function<bool(Rng&, Vec3&)>& sample,
                   const std::function<float(const Vec3&)>& pdf, std::uint64_t seed, int sub = 12) {
    std::vector<double> observed(kThetaBins * kPhiBins + 1, 0.0);
    Rng rng(seed, 0, 0);
    for (int i = 0; i < kSamples; ++i) {
        Vec3 w;
        if (sample(rng, w))
            ++observed[cellOf(w)];
        else
            ++observed.back();
    }
    std::vector<double> expected = expectedCells(pdf, sub);
    for (double& e : expected) e *= kSamples;
    return test::chi2Test(observed, expected);
}

Vec3 direction(float thetaDeg, float phiDeg) {
    const float t = thetaDeg * kPi / 180.0f, p = phiDeg * kPi / 180.0f;
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

void checkBsdf(const Bsdf& bsdf, const Vec3& wo, std::uint64_t seed, int sub = 12) {
    const test::Chi2 r = runChi2(
        [&](Rng& rng, Vec3& w) {
            BsdfSample s;
            if (!bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s)) return false;
            // The sample's pdf and weight agree with pdf() and eval().
            EXPECT_NEAR(s.pdf, bsdf.pdf(wo, s.wi), 1e-3f * s.pdf);
            const Vec3 expect = bsdf.eval(wo, s.wi) * (std::abs(s.wi.z) / s.pdf);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(s.weight[c], expect[c], 2e-3f * (1 + expect[c]));
            w = s.wi;
            return true;
        },
        [&](const Vec3& w) { return bsdf.pdf(wo, w); }, seed, sub);
    EXPECT_GT(r.pValue, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

TEST(BsdfChi2, Diffuse) {
    detail::Material m;
    m.type = detail::MaterialType::Diffuse;
    const Bsdf bsdf = Bsdf::fromMaterial(m, {0.5f, 0.6f, 0.7f});
    checkBsdf(bsdf, direction(30, 10), 1);
    checkBsdf(bsdf, direction(80, 200), 2);
}

TEST(BsdfChi2, ConductorSchlick) {
    detail::Material m;
    m.type = detail::MaterialType::Conductor;
    m.specular = {0.9f, 0.6f, 0.3f};
    for (const float roughness : {0.3f, 0.6f, 1.0f}) {
        m.roughness = roughness;
        const Bsdf bsdf = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
        checkBsdf(bsdf, direction(20, 30), 10 + std::uint64_t(roughness * 10));
        checkBsdf(bsdf, direction(70, 250), 20 + std::uint64_t(roughness * 10));
    }
}

TEST(BsdfChi2, ConductorComplexIor) {
    detail::Material m;
    m.type = detail::MaterialType::Conductor;
    m.roughness = 0.5f;
    m.hasEtaK = true;
    m.eta = {0.2f, 0.9f, 1.1f};  // gold-like
    m.k = {3.9f, 2.4f, 1.9f};
    const Bsdf bsdf = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
    checkBsdf(bsdf, direction(45, 90), 30);
}

/// The glTF metallic-roughness BSDF (a Lambert + GGX mixture) over wo ∈ {10°, 50°, 85°} and
/// roughness ∈ {0.2, 0.3, 0.7, 1} at one metallic value: 12 chi-square tests. The narrow lobes
/// of roughness 0.2 and 0.3 need a finer sub-grid for the expected counts (48² per cell: at 12²
/// the midpoint rule's error alone fails the test, and 32² fails at roughness 0.2); lower
/// roughness puts the whole lobe in a cell or two, and metallic_roughness_test.cpp covers it.
void checkMetallicRoughness(float metallic, std::uint64_t seed) {
    for (const float roughness : {0.2f, 0.3f, 0.7f, 1.0f}) {
        const Bsdf bsdf = Bsdf::metallicRoughness({0.8f, 0.5f, 0.2f}, metallic, roughness);
        for (const float thetaO : {10.0f, 50.0f, 85.0f}) {
            SCOPED_TRACE("roughness " + std::to_string(roughness) + " θo " +
                         std::to_string(thetaO));
            checkBsdf(bsdf, direction(thetaO, 40), seed++, roughness < 0.5f ? 48 : 12);
        }
    }
}

TEST(BsdfChi2, MetallicRoughnessDielectricBase) {
    checkMetallicRoughness(0.0f, 100);
}

TEST(BsdfChi2, MetallicRoughnessHalfMetal) {
    checkMetallicRoughness(0.5f, 200);
}

TEST(BsdfChi2, MetallicRoughnessMetal) {
    checkMetallicRoughness(1.0f, 300);
}

/// Rough glass over roughness ∈ {0.3, 0.6, 1} and wo from outside (20°, 70°) and inside (30°;
/// 60°, past the critical angle) at ior 1.5, and a diamond-like ior 2.4: 14 chi-square tests.
/// Samples land on both hemispheres; the missing-mass cell holds reflections below the surface
/// and refractions above it. The pdf jumps where wo·h or wi·h changes sign: even broad lobes
/// need the 48² sub-grid (at 12², roughness 1 at 70° fails on the midpoint rule's error).
TEST(BsdfChi2, RoughDielectric) {
    detail::Material m;
    m.type = detail::MaterialType::Dielectric;
    std::uint64_t seed = 400;
    m.ior = 1.5f;
    for (const float roughness : {0.3f, 0.6f, 1.0f}) {
        m.roughness = roughness;
        const Bsdf bsdf = Bsdf::fromMaterial(m, {0.9f, 0.8f, 0.7f});
        for (const Vec3& wo :
             {direction(20, 40), direction(70, 40), -direction(30, 40), -direction(60, 40)}) {
            SCOPED_TRACE("roughness " + std::to_string(roughness) + " wo.z " +
                         std::to_string(wo.z));
            checkBsdf(bsdf, wo, seed++, 48);
        }
    }
    m.ior = 2.4f;
    m.roughness = 0.5f;
    const Bsdf diamond = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
    for (const Vec3& wo : {direction(45, 100), -direction(20, 100)}) {
        SCOPED_TRACE("ior 2.4 wo.z " + std::to_string(wo.z));
        checkBsdf(diamond, wo, seed++, 48);
    }
}

/// The metallic-roughness material with transmission (GGX reflection, GGX refraction and
/// Lambert) over roughness ∈ {0.3, 0.7}, transmission ∈ {0.5, 1} and wo from outside (30°, 80°)
/// and inside (40°): 12 chi-square tests.
TEST(BsdfChi2, MetallicRoughnessTransmission) {
    std::uint64_t seed = 500;
    for (const float roughness : {0.3f, 0.7f})
        for (const float transmission : {0.5f, 1.0f}) {
            const Bsdf bsdf =
                Bsdf::metallicRoughness({0.8f, 0.5f, 0.2f}, 0.2f, roughness, 1.5f, transmission);
            for (const Vec3& wo : {direction(30, 40), direction(80, 40), -direction(40, 40)}) {
                SCOPED_TRACE("roughness " + std::to_string(roughness) + " transmission " +
                             std::to_string(transmission) + " wo.z " + std::to_string(wo.z));
                checkBsdf(bsdf, wo, seed++, roughness < 0.5f ? 48 : 12);
            }
        }
}

TEST(BsdfSampling, ConductorWhiteFurnaceBound) {
    // A white GGX conductor (F = 1) reflects at most all energy: E[weight] <= 1 and close to 1
    // for low roughness (single scattering loses a few percent at most at alpha 0.09).
    detail::Material m;
    m.type = detail::MaterialType::Conductor;
    m.roughness = 0.3f;
    const Bsdf bsdf = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
    Rng rng(5, 0, 0);
    double sum = 0.0;
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        BsdfSample s;
        if (bsdf.sample(direction(30, 0), {rng.uniform(), rng.uniform()}, rng.uniform(), s))
            sum += s.weight.x;
    }
    EXPECT_LE(sum / n, 1.0 + 1e-3);
    EXPECT_GT(sum / n, 0.95);
}

TEST(BsdfSampling, MirrorReflectsExactly) {
    detail::Material m;
    m.type = detail::MaterialType::Mirror;
    const Bsdf bsdf = Bsdf::fromMaterial(m, {0.9f, 0.8f, 0.7f});
    const Vec3 wo = direction(40, 75);
    BsdfSample s;
    ASSERT_TRUE(bsdf.sample(wo, {0.3f, 0.6f}, 0.5f, s));
    EXPECT_TRUE(s.specular);
    EXPECT_NEAR(s.wi.x, -wo.x, 1e-6);
    EXPECT_NEAR(s.wi.y, -wo.y, 1e-6);
    EXPECT_NEAR(s.wi.z, wo.z, 1e-6);
    EXPECT_FLOAT_EQ(s.weight.y, 0.8f);
    EXPECT_TRUE(isBlack(bsdf.eval(wo, s.wi)));
}

TEST(BsdfChi2, DielectricChoosesByFresnel) {
    detail::Material m;
    m.type = detail::MaterialType::Dielectric;
    m.ior = 1.5f;
    const Bsdf bsdf = Bsdf::fromMaterial(m, {1.0f, 1.0f, 1.0f});
    // From outside at 60° and from inside at 30° (below the critical angle of 41.8°).
    const Vec3 wos[2] = {direction(60, 20), -direction(30, 20)};
    for (int k = 0; k < 2; ++k) {
        const Vec3 wo = wos[k];
        const float eta = wo.z > 0 ? 1.5f : 1.0f / 1.5f;
        const float fresnel = fresnelDielectric(std::abs(wo.z), eta);
        Rng rng(40 + k, 0, 0);
        std::vector<double> observed(2, 0.0);
        const int n = 100000;
        for (int i = 0; i < n; ++i) {
            BsdfSample s;
            ASSERT_TRUE(bsdf.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), s));
            const bool reflected = (s.wi.z > 0) == (wo.z > 0);
            ++observed[reflected ? 0 : 1];
            if (!reflected) {
                // Snell's law: sin θi = eta sin θt, in the plane of incidence.
                const float sinI = std::sqrt(wo.x * wo.x + wo.y * wo.y);
                const float sinT = std::sqrt(s.wi.x * s.wi.x + s.wi.y * s.wi.y);
                EXPECT_NEAR(sinI, eta * sinT, 1e-5);
                EXPECT_LT(dot(Vec3{wo.x, wo.y, 0}, Vec3{s.wi.x, s.wi.y, 0}), 0.0f);
            }
        }
        const test::Chi2 r = test::chi2Test(observed, {fresnel * n, (1 - fresnel) * n});
        EXPECT_GT(r.pValue, kAlpha) << "F " << fresnel << " observed " << observed[0] / n;
    }
    // Total internal reflection beyond the critical angle.
    BsdfSample s;
    ASSERT_TRUE(bsdf.sample(-direction(60, 0), {0.5f, 0.5f}, 0.999f, s));
    EXPECT_LT(s.wi.z, 0.0f);
}

TEST(EnvironmentChi2, ImageSamplingMatchesPdf) {
    detail::EnvironmentDesc desc;
    desc.kind = detail::EnvironmentDesc::Kind::Image;
    desc.rotateDeg = 30.0f;
    desc.image = Image(32, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            // A smooth gradient plus a bright "sun" texel block and a black band.
            const float base = 0.1f + 0.05f * float(x % 7) + (y == 12 ? -0.1f : 0.0f);
            const float sun = (x >= 20 && x < 22 && y >= 4 && y < 6) ? 40.0f : 0.0f;
            for (int c = 0; c < 3; ++c) desc.image(x, y, c) = std::max(0.0f, base + sun * (c + 1));
        }
    const Environment env(desc);
    const test::Chi2 r = runChi2(
        [&](Rng& rng, Vec3& w) {
            float pdf = 0.0f;
            if (!env.sample({rng.uniform(), rng.uniform()}, w, pdf)) return false;
            // Away from texel edges (where float round-off may pick the neighbour) the pdfs agree.
            // (The environment is rotated by 30° about +y: world u = env u - 30/360.)
            const Vec2 uv = Environment::dirToUv(w);
            const float ue = uv.x + 30.0f / 360.0f;
            const float fx = ue * 32.0f - std::floor(ue * 32.0f);
            const float fy = uv.y * 16.0f - std::floor(uv.y * 16.0f);
            if (fx > 1e-3f && fx < 0.999f && fy > 1e-3f && fy < 0.999f && uv.y > 0.01f &&
                uv.y < 0.99f) {
                EXPECT_NEAR(pdf, env.pdf(w), 1e-2f * pdf);
            }
            return true;
        },
        // The pdf jumps at texel edges: integrate on a finer sub-grid.
        [&](const Vec3& w) { return env.pdf(w); }, 50, 64);
    EXPECT_GT(r.pValue, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof;
}

/// Chi-square of solid-angle sampling of the spherical triangle (a, b, c): uniform inside.
void checkSphericalTriangle(const DVec3& a0, const DVec3& b0, const DVec3& c0, std::uint64_t seed) {
    const DVec3 a = normalizeOrZero(a0), b = normalizeOrZero(b0), c = normalizeOrZero(c0);
    const double omega = sphericalTriangleSolidAngle(a, b, c);
    // Inside: on the side of each edge's great circle that holds the opposite vertex.
    auto inside = [&](const DVec3& w) {
        auto side = [&](const DVec3& p, const DVec3& q, const DVec3& r) {
            const DVec3 n = cross(p, q);
            return (dot(w, n) > 0.0) == (dot(r, n) > 0.0);
        };
        return side(a, b, c) && side(b, c, a) && side(c, a, b);
    };
    const test::Chi2 r = runChi2(
        [&](Rng& rng, Vec3& w) {
            DVec3 d;
            if (!sampleSphericalTriangle(a, b, c, omega, {rng.uniform(), rng.uniform()}, d))
                return false;
            w = {float(d.x), float(d.y), float(d.z)};
            return true;
        },
        [&](const Vec3& w) { return inside(toDouble(w)) ? float(1.0 / omega) : 0.0f; }, seed, 48);
    EXPECT_GT(r.pValue, kAlpha) << "chi2 " << r.statistic << " dof " << r.dof << " Ω " << omega;
}

TEST(SphericalTriangleChi2, LargeTriangleIsUniformInSolidAngle) {
    checkSphericalTriangle({1.0, 0.2, 0.3}, {-0.3, 1.0, 0.1}, {0.1, -0.2, 1.0}, 11);
}

TEST(SphericalTriangleChi2, ObtuseTriangleBeyondAHemisphereIsUniform) {
    // A triangle wider than a hemisphere (Ω > 2π would be the plane): Ω ≈ 4.4 sr.
    checkSphericalTriangle({1.0, 0.0, -0.2}, {-0.5, 0.87, -0.2}, {-0.5, -0.87, -0.2}, 12);
}

TEST(SphericalTriangle, SolidAnglesOfKnownTriangles) {
    // An octant is an eighth of the sphere.
    EXPECT_NEAR(sphericalTriangleSolidAngle(DVec3{1, 0, 0}, DVec3{0, 1, 0}, DVec3{0, 0, 1}),
                M_PI / 2.0, 1e-12);
    // A small far triangle: area × cos θ / r².
    const Vec3 p{0.0f, 0.0f, 0.0f};
    const double omega = triangleSolidAngle(p, {0, 0, 100}, {1, 0, 100}, {0, 1, 100});
    EXPECT_NEAR(omega, 0.5 / 1e4, 0.5 / 1e4 * 1e-3);
    // Degenerate triangles have no solid angle and cannot be sampled.
    DVec3 w;
    EXPECT_FALSE(sampleSphericalTriangle(DVec3{1, 0, 0}, DVec3{1, 0, 0}, DVec3{0, 1, 0}, 0.0,
                                         Vec2{0.5f, 0.5f}, w));
}

TEST(Environment, ConventionUHalfLooksDownMinusZ) {
    const Vec3 d = Environment::uvToDir({0.5f, 0.5f});
    EXPECT_NEAR(d.z, -1.0f, 1e-6);
    const Vec2 uv = Environment::dirToUv({1.0f, 0.0f, 0.0f});
    EXPECT_NEAR(uv.x, 0.75f, 1e-6);
    EXPECT_NEAR(uv.y, 0.5f, 1e-6);
    EXPECT_NEAR(Environment::dirToUv({0.0f, 1.0f, 0.0f}).y, 0.0f, 1e-6);
}

}  // namespace
}  // namespace glint::render
