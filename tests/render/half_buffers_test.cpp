// Half buffers (Settings::halfBuffers, docs/renderer.md "Half buffers"): the renderer splits each
// pixel's samples into two halves with independent scrambles and writes half B's statistics;
// the halves add up to the whole, are independent, merge across shards, stay deterministic,
// and bad combinations are refused naming the setting.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/image/shard.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

Scene cornell(int width, int height) {
    const std::string json = R"({
      "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
      "film": {"width": )" + std::to_string(width) +
                             R"(, "height": )" + std::to_string(height) + R"(},
      "shapes": [{"obj": "cornell_box.obj"}],
      "render": {"spp": 8, "maxDepth": 4}
    })";
    return parseScene(json, std::string(GLINT_SOURCE_DIR) + "/scenes/cornell/scene.json");
}

Settings halfSettings(int spp, SamplerKind sampler = SamplerKind::Sobol) {
    Settings s;
    s.spp = spp;
    s.seed = 5;
    s.sampler = sampler;
    s.maxDepth = 4;
    s.threads = 2;
    s.tileSize = 8;
    s.halfBuffers = true;
    return s;
}

TEST(HalfBuffers, TheHalvesAddUpToTheWhole) {
    Renderer renderer(cornell(20, 16));
    const FrameBuffers f = renderer.render(halfSettings(9)).frame;
    for (Layer l : {Layer::HalfColor, Layer::HalfVariance, Layer::HalfAlbedo,
                    Layer::HalfAlbedoVariance, Layer::HalfNormal, Layer::HalfNormalVariance,
                    Layer::HalfDepth, Layer::HalfDepthVariance, Layer::HalfSampleCount})
        EXPECT_TRUE(f.has(l)) << layerDisplayName(l);
    EXPECT_EQ(f.metadata().extra.at("halfBuffers"), "true");
    const auto [a, b] = splitHalves(f);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 20; ++x) {
            const float n = f.layer(Layer::SampleCount)(x, y, 0);
            ASSERT_EQ(n, 9.0f);  // no non-finite samples in this scene
            EXPECT_EQ(f.layer(Layer::HalfSampleCount)(x, y, 0), 4.0f);
            for (int c = 0; c < 3; ++c) {
                const double whole = f.color()(x, y, c);
                const double sum = (5.0 * a.color()(x, y, c) + 4.0 * b.color()(x, y, c)) / 9.0;
                EXPECT_NEAR(sum, whole, 1e-6 * std::max(1.0, std::abs(whole)));
                EXPECT_GE(a.layer(Layer::Variance)(x, y, c), 0.0f);
            }
        }
    // Without half buffers the frame has no half layers.
    Settings plain = halfSettings(9);
    plain.halfBuffers = false;
    const FrameBuffers p = renderer.render(plain).frame;
    for (int l = 0; l < kLayerCount; ++l) EXPECT_FALSE(isHalfLayer(Layer(l)) && p.has(Layer(l)));
}

TEST(HalfBuffers, IndependentSamplerGivesTheSameWholeWithOrWithout) {
    // Every sample of the independent sampler has its own stream: splitting only adds layers.
    Renderer renderer(cornell(20, 16));
    Settings s = halfSettings(6, SamplerKind::Independent);
    const FrameBuffers with = renderer.render(s).frame;
    s.halfBuffers = false;
    const FrameBuffers without = renderer.render(s).frame;
    for (Layer l : {Layer::Color, Layer::Variance, Layer::Albedo, Layer::Depth, Layer::SampleCount})
        EXPECT_TRUE(test::sameLayer(with, without, l)) << layerDisplayName(l);
}

TEST(HalfBuffers, HalvesAreIndependentSoTheirDifferenceEstimatesTheError) {
    // A sphere on a floor under a white sky: bounded radiance, so second moments are stable
    // (the Cornell box's fireflies would dominate any sum of squares). Against a 4096-spp
    // reference (independent sampler, another seed), the errors of the two Sobol halves are
    // uncorrelated, and (A − B)²/4 (n_A = n_B) estimates the whole's squared error without
    // bias — unlike the variance layer's sample variance / n, which overstates a
    // low-discrepancy sampler's error. Over 40·30·3 = 3600 values, the correlation of
    // independent errors has a standard deviation of about 1/√3600 = 0.017: we allow 0.07 per
    // seed; the ratio of the estimate to the true squared error (whose reference part is 8/4096
    // of it) spreads by about 5 % per seed (measured, seeds 1-4: 0.92-1.05), so its mean over
    // four seeds has a standard error of about 2.5 %: we allow [0.85, 1.15].
    test::TempDir dir("halves");
    dir.write("quad.obj", test::quadObj());
    dir.write("sphere.obj", test::sphereObj(1.0f));
    const auto scenePath = dir.write("scene.json", R"({
      "camera": {"position": [0, 2.2, 3], "lookAt": [0, 0.3, 0], "fovY": 40},
      "film": {"width": 40, "height": 30},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                    "ball": {"type": "diffuse", "albedo": [0.8, 0.3, 0.2]}},
      "shapes": [{"obj": "quad.obj", "material": "floor", "transform": {"scale": 3}},
                 {"obj": "sphere.obj", "material": "ball",
                  "transform": {"translate": [0, 0.6, 0], "scale": 0.6}}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": 8, "maxDepth": 3}
    })");
    Renderer renderer(loadScene(scenePath));
    Settings refSettings = halfSettings(4096, SamplerKind::Independent);
    refSettings.maxDepth = 3;
    refSettings.halfBuffers = false;
    refSettings.seed = 99;
    const Image ref = renderer.render(refSettings).frame.color();
    Settings settings = halfSettings(8);
    settings.maxDepth = 3;
    double ratioSum = 0.0;
    for (std::uint64_t seed : {1, 2, 3, 4}) {
        settings.seed = seed;
        const FrameBuffers f = renderer.render(settings).frame;
        const auto [a, b] = splitHalves(f);
        double saa = 0, sbb = 0, sab = 0, estimate = 0, truth = 0, layer = 0;
        for (std::size_t i = 0; i < ref.data().size(); ++i) {
            const double ea = double(a.color().data()[i]) - ref.data()[i];
            const double eb = double(b.color().data()[i]) - ref.data()[i];
            const double ec = double(f.color().data()[i]) - ref.data()[i];
            saa += ea * ea, sbb += eb * eb, sab += ea * eb;
            const double d = double(a.color().data()[i]) - b.color().data()[i];
            estimate += 0.25 * d * d;
            truth += ec * ec;
            layer += f.layer(Layer::Variance).data()[i];
        }
        const double rho = sab / std::sqrt(saa * sbb);
        std::printf(
            "seed %d: correlation of the halves' errors %.4f; estimated / true squared "
            "error %.3f (variance layer / true %.3f)\n",
            int(seed), rho, estimate / truth, layer / truth);
        EXPECT_LT(std::abs(rho), 0.07);
        ratioSum += estimate / truth;
    }
    EXPECT_GT(ratioSum / 4.0, 0.85);
    EXPECT_LT(ratioSum / 4.0, 1.15);
}

TEST(HalfBuffers, SameBitsForAnyThreadCount) {
    Renderer renderer(cornell(20, 16));
    Settings s = halfSettings(5);
    s.threads = 1;
    const FrameBuffers one = renderer.render(s).frame;
    s.threads = 2;
    s.tileSize = 5;
    test::expectSameFrames(one, renderer.render(s).frame);
}

TEST(HalfBuffers, ShardsMergeIntoTheWholeRendersHalves) {
    Renderer renderer(cornell(20, 16));
    const Settings settings = halfSettings(11);
    const FrameBuffers whole = renderer.render(settings).frame;
    std::vector<ShardFrame> shards;
    for (int i = 0; i < 3; ++i) {
        Settings s = settings;
        s.shard = Shard{i, 3};
        shards.push_back({"shard" + std::to_string(i) + ".exr", renderer.render(s).frame});
    }
    const FrameBuffers merged = mergeShards(shards);
    EXPECT_TRUE(test::sameLayer(merged, whole, Layer::HalfSampleCount));
    // The tolerance of docs/distributed.md: means within 4 ulps of the largest shard mean,
    // variances within 16 ulps plus 8 ulps of that mean times the standard deviation.
    constexpr double eps = 0x1p-24;
    for (Layer mean : {Layer::HalfColor, Layer::HalfAlbedo, Layer::HalfNormal, Layer::HalfDepth}) {
        const Layer var = *varianceLayer(mean);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 20; ++x)
                for (int c = 0; c < layerInfo(mean).channels; ++c) {
                    double m = 0.0;
                    for (const ShardFrame& s : shards)
                        m = std::max(m, std::abs(double(s.frame.layer(mean)(x, y, c))));
                    const double vw = whole.layer(var)(x, y, c);
                    ASSERT_NEAR(merged.layer(mean)(x, y, c), whole.layer(mean)(x, y, c),
                                4.0 * eps * m)
                        << layerDisplayName(mean) << " " << x << "," << y << "," << c;
                    ASSERT_NEAR(merged.layer(var)(x, y, c), vw,
                                16.0 * eps * vw + 8.0 * eps * m * std::sqrt(vw))
                        << layerDisplayName(var) << " " << x << "," << y << "," << c;
                }
    }
}

TEST(HalfBuffers, RefusedWithMetropolisOrTheStratifiedSamplerAndNamedInSceneJson) {
    auto expectRefused = [](Settings s, const std::string& words) {
        try {
            validate(s);
            FAIL() << "no error";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "halfBuffers");
            EXPECT_NE(e.message().find(words), std::string::npos) << e.what();
        }
    };
    Settings s = halfSettings(4, SamplerKind::Stratified);
    expectRefused(s, "sobol or independent");
    s = halfSettings(4);
    s.integrator = Integrator::Mlt;
    expectRefused(s, "path integrator");

    const std::string base = std::string(GLINT_SOURCE_DIR) + "/scenes/cornell/scene.json";
    const std::string json = R"({
      "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
      "film": {"width": 8, "height": 8},
      "shapes": [{"obj": "cornell_box.obj"}],
      "render": {"halfBuffers": HB}
    })";
    auto with = [&](const std::string& value) {
        std::string text = json;
        text.replace(text.find("HB"), 2, value);
        return text;
    };
    EXPECT_TRUE(parseScene(with("true"), base).settings().halfBuffers);
    try {
        parseScene(with("\"yes\""), base);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(e.where().find("/render/halfBuffers"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("true or false"), std::string::npos) << e.what();
    }
}

TEST(HalfBuffers, MemoryEstimateCountsTheSecondFilmAndLayers) {
    Renderer renderer(cornell(64, 48));
    Settings s = halfSettings(4);
    const std::uint64_t with = renderer.estimateMemory(s);
    s.halfBuffers = false;
    const std::uint64_t without = renderer.estimateMemory(s);
    EXPECT_GT(with, without + 64u * 48u * 100u);
}

}  // namespace
}  // namespace glint::render
