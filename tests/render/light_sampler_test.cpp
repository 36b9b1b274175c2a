// Light sampling: a triangle light is sampled by solid angle where it subtends enough of the view
// and by area elsewhere; the pdf sample() reports must be the pdf pdfArea() gives the same point
// (MIS depends on it), and both measures must estimate the same irradiance.
#include <gtest/gtest.h>

#include <cmath>

#include "glint/render/scene.h"
#include "lights/light_sampler.h"
#include "lights/spherical_triangle.h"
#include "sampling/rng.h"
#include "scene/scene_access.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// One triangle lamp of side 2 at height 1 above the origin, facing down (triangle 0).
Scene lampScene(const test::TempDir& dir) {
    dir.write("lamp.obj", "v -1 1 -1\nv 1 1 -1\nv 0 1 1\nf 1 3 2\n");
    return parseScene(R"({"film": {"width": 4, "height": 4},
      "materials": {"lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [1, 1, 1]}},
      "shapes": [{"obj": "lamp.obj", "material": "lamp"}]})",
                      dir.path() / "scene.json");
}

TEST(LightSampler, ThePdfOfASampleIsThePdfOfItsPoint) {
    test::TempDir dir("lights");
    const Scene scene = lampScene(dir);
    const LightSampler lights(detail::sceneData(scene));
    // Close (Ω ≈ 1.5 sr: solid angle), far (Ω ≈ 2e-4 sr: area) and grazing points.
    for (const Vec3 p :
         {Vec3{0.1f, 0.0f, 0.0f}, Vec3{0.0f, -140.0f, 0.0f}, Vec3{3.0f, 0.9f, 0.0f}}) {
        const double omega = triangleSolidAngle(p, {-1, 1, -1}, {1, 1, -1}, {0, 1, 1});
        Rng rng(5, 0, 0);
        int ok = 0;
        for (int i = 0; i < 2000; ++i) {
            LightSample s;
            if (!lights.sample(p, rng.uniform(), {rng.uniform(), rng.uniform()}, s)) continue;
            ++ok;
            EXPECT_NEAR(s.point.y, 1.0f, 1e-4f);
            const float pdf = lights.pdfArea({0, 0}, p, s.point, s.normal);
            ASSERT_NEAR(s.pdf, pdf, 1e-3f * pdf) << "p.y " << p.y << " Ω " << omega;
            const Vec3 d = s.point - p;
            EXPECT_NEAR(length(d), s.distance, 1e-4f * s.distance);
        }
        EXPECT_GT(ok, 1900);
    }
}

TEST(LightSampler, SolidAngleAndAreaSamplingEstimateTheSameIrradiance) {
    // Irradiance at a point 0.3 below the lamp (Ω ≈ 2.9 sr): E = ∫ L cos θ dω, by solid-angle
    // samples (what sample() does there) and by area samples of the same triangle (pdf r² /
    // (A cos θ_l)). 200 000 samples each; the two means must agree within 4 combined standard
    // errors (a 6e-5 chance of failing by accident).
    test::TempDir dir("irradiance");
    const Scene scene = lampScene(dir);
    const LightSampler lights(detail::sceneData(scene));
    const Vec3 p{0.0f, 0.7f, 0.0f};
    const Vec3 up{0.0f, 1.0f, 0.0f};
    auto stats = [](double sum, double sum2, int n) {
        const double mean = sum / n;
        return std::pair{mean, (sum2 / n - mean * mean) / n};
    };
    double s1 = 0, s1q = 0, s2 = 0, s2q = 0;
    const int n = 200000;
    Rng rng(9, 0, 0);
    const Vec3 v0{-1, 1, -1}, v1{1, 1, -1}, v2{0, 1, 1};
    const float area = 2.0f;  // base 2, height 2
    for (int i = 0; i < n; ++i) {
        LightSample s;
        double f = 0.0;
        if (lights.sample(p, rng.uniform(), {rng.uniform(), rng.uniform()}, s))
            f = std::max(0.0f, dot(s.wi, up)) / s.pdf;
        s1 += f, s1q += f * f;
        // Area sampling by hand.
        const float su = std::sqrt(rng.uniform()), w = rng.uniform();
        const Vec3 q = v0 * (1.0f - su) + v1 * (su * (1.0f - w)) + v2 * (su * w);
        const Vec3 d = q - p;
        const float r2 = dot(d, d);
        const Vec3 wi = d / std::sqrt(r2);
        const double g = std::max(0.0f, dot(wi, up)) * std::abs(wi.y) / r2 * area;
        s2 += g, s2q += g * g;
    }
    const auto [m1, v1Mean] = stats(s1, s1q, n);
    const auto [m2, v2Mean] = stats(s2, s2q, n);
    EXPECT_NEAR(m1, m2, 4.0 * std::sqrt(v1Mean + v2Mean));
    // And solid-angle sampling is the better estimator this close: lower variance.
    EXPECT_LT(v1Mean, v2Mean);
}

}  // namespace
}  // namespace glint::render
