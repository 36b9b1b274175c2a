// White-furnace tests through the public API: energy is conserved exactly in two closed-form
// configurations, so every pixel must converge to a known value.
#include <gtest/gtest.h>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// Checks every pixel against `expected`: |mean - L| <= 5 σ + 1e-3 L, σ² the pixel's variance of
/// the mean (a 5σ two-sided bound fails by chance with p ≈ 6e-7 per pixel and channel for a
/// normal mean; only used where the per-sample distribution is light-tailed), and the image mean
/// within `imageTolerance` (relative).
void expectFlat(const FrameBuffers& frame, float expected, bool perPixel = true,
                double imageTolerance = 0.01) {
    const Image& color = frame.color();
    const Image& variance = frame.layer(Layer::Variance);
    double sum = 0.0;
    int outliers = 0;
    for (int y = 0; y < color.height(); ++y)
        for (int x = 0; x < color.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float sigma = std::sqrt(variance(x, y, c));
                sum += color(x, y, c);
                if (perPixel &&
                    std::abs(color(x, y, c) - expected) > 5.0f * sigma + 1e-3f * expected) {
                    if (++outliers < 5)
                        ADD_FAILURE() << "pixel (" << x << ", " << y << ") channel " << c << ": "
                                      << color(x, y, c) << " vs " << expected << " ± 5 × " << sigma;
                }
            }
    EXPECT_EQ(outliers, 0);
    EXPECT_NEAR(sum / (3.0 * color.pixelCount()), expected, imageTolerance * expected);
}

TEST(WhiteFurnace, DiffuseSphereInConstantEnvironment) {
    // An albedo-1 Lambertian sphere under constant radiance L reflects exactly L: each bounce
    // leaves the convex (flat-faceted) sphere, so the path throughput stays 1.
    test::TempDir dir("furnace");
    dir.write("sphere.obj", test::sphereObj(1.0f));
    const auto scenePath = dir.write("scene.json", R"({
      "camera": {"position": [0, 0, 4], "lookAt": [0, 0, 0], "fovY": 40},
      "film": {"width": 32, "height": 32},
      "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
      "shapes": [{"obj": "sphere.obj", "material": "white"}],
      "environment": {"color": [0.8, 0.8, 0.8], "scale": 1.5},
      "render": {"spp": 16, "maxDepth": 8, "seed": 3}
    })");
    Renderer renderer(loadScene(scenePath));
    Settings s = renderer.scene().settings();
    const FrameBuffers power = renderer.render(s).frame;
    expectFlat(power, 1.2f);
    EXPECT_EQ(power.metadata().nonFiniteSamples, 0);
    // BSDF sampling alone has zero variance here: every path scores exactly L.
    s.mis = MisHeuristic::None;
    s.strategy = Strategy::Bsdf;
    const FrameBuffers bsdf = renderer.render(s).frame;
    for (float v : bsdf.color().data()) ASSERT_NEAR(v, 1.2f, 1e-5f);
    // Light sampling alone (uniform sphere directions, half of them below the surface) is
    // heavy-tailed at low spp: check only the image mean, 64 spp × 1024 px, per-sample σ ≈ 1.55,
    // so σ(image mean) ≈ 0.006 and 3 % is 5σ.
    s.strategy = Strategy::Light;
    s.spp = 64;
    expectFlat(renderer.render(s).frame, 1.2f, false, 0.03);
}

TEST(WhiteFurnace, ClosedEmissiveSphereSeenFromInside) {
    // Inside a closed diffuse enclosure of albedo ρ = 0.5 emitting Le = 0.5 everywhere,
    // L = Le + ρ L, so L = Le / (1 - ρ) = 1 in every direction.
    test::TempDir dir("closed");
    dir.write("sphere.obj", test::sphereObj(2.0f, 12, 24));
    const auto scenePath = dir.write("scene.json", R"({
      "camera": {"position": [0.3, -0.2, 0.1], "lookAt": [1, 0, 0], "fovY": 70},
      "film": {"width": 24, "height": 24},
      "materials": {"glow": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5],
                             "emission": [0.5, 0.5, 0.5]}},
      "shapes": [{"obj": "sphere.obj", "material": "glow"}],
      "render": {"spp": 32, "maxDepth": 64, "rrDepth": 64, "seed": 5}
    })");
    Renderer renderer(loadScene(scenePath));
    // Without Russian roulette (rrDepth = maxDepth; truncation bias 0.5^64) per-sample values
    // are light-tailed and the per-pixel 5σ test applies.
    Settings s = renderer.scene().settings();
    expectFlat(renderer.render(s).frame, 1.0f);
    // With Russian roulette after 3 bounces the estimator stays unbiased but heavy-tailed:
    // check the image mean (24² px × 64 spp) within 3 %.
    s.rrDepth = 3;
    s.spp = 64;
    expectFlat(renderer.render(s).frame, 1.0f, false, 0.03);
}

TEST(WhiteFurnace, ClosedAlbedoOneEnclosureReturnsTheEmissionOncePerBounce) {
    // Inside a closed enclosure of albedo exactly 1 emitting Le everywhere, nothing is absorbed:
    // a path of at most D bounces collects Le at every vertex, L_D = (D + 1) Le (the infinite
    // sum diverges, which is why maxDepth bounds it). BSDF sampling alone scores exactly that on
    // every sample; MIS adds light samples but no bias.
    test::TempDir dir("closed1");
    dir.write("sphere.obj", test::sphereObj(2.0f, 12, 24));
    const auto scenePath = dir.write("scene.json", R"({
      "camera": {"position": [0.3, -0.2, 0.1], "lookAt": [1, 0, 0], "fovY": 70},
      "film": {"width": 16, "height": 16},
      "materials": {"glow": {"type": "diffuse", "albedo": [1, 1, 1], "emission": [0.5, 0.5, 0.5]}},
      "shapes": [{"obj": "sphere.obj", "material": "glow"}]})");
    Renderer renderer(loadScene(scenePath));
    for (int depth : {1, 4, 16}) {
        SCOPED_TRACE("maxDepth " + std::to_string(depth));
        Settings s = renderer.scene().settings();
        s.maxDepth = depth;
        s.rrDepth = depth;  // no Russian roulette: the truncated sum is exact
        s.spp = 16;
        s.mis = MisHeuristic::None;
        s.strategy = Strategy::Bsdf;
        const float expected = 0.5f * float(depth + 1);
        const FrameBuffers bsdf = renderer.render(s).frame;
        for (float v : bsdf.color().data()) ASSERT_NEAR(v, expected, 1e-5f * expected);
        // Power-heuristic MIS: light-tailed here, so the per-pixel 5σ test applies.
        s.mis = MisHeuristic::Power;
        s.spp = 64;
        expectFlat(renderer.render(s).frame, expected);
    }
}

}  // namespace
}  // namespace glint::render
