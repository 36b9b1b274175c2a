// Adaptive sampling (Settings::adaptive, docs/renderer.md "Adaptive sampling"): after a uniform
// start, passes go only to the pixels whose estimated error (times an importance map's weight)
// is above the noise threshold. The converged mean is the uniform render's, the sample counts
// follow the noise and the map, every pixel continues its own sample sequence, the output is
// the same for any thread count, and bad settings and maps are refused naming the problem.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/render/importance_map.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// A diffuse sphere on a floor under a white sky (bounded radiance, no fireflies), and the sky
/// alone in the top rows: noise on the objects, none in the sky.
class AdaptiveScene : public ::testing::Test {
  protected:
    AdaptiveScene() : m_dir("adaptive") {
        m_dir.write("quad.obj", test::quadObj());
        m_dir.write("sphere.obj", test::sphereObj(1.0f));
        m_scene = m_dir.write("scene.json", R"({
          "camera": {"position": [0, 1.2, 3], "lookAt": [0, 0.5, 0], "fovY": 40},
          "film": {"width": 24, "height": 18},
          "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                        "ball": {"type": "diffuse", "albedo": [0.8, 0.3, 0.2]}},
          "shapes": [{"obj": "quad.obj", "material": "floor", "transform": {"scale": 3}},
                     {"obj": "sphere.obj", "material": "ball",
                      "transform": {"translate": [0, 0.5, 0], "scale": 0.5}}],
          "environment": {"color": [1, 1, 1]},
          "render": {"spp": 8, "maxDepth": 3}
        })");
    }

    static Settings adaptiveSettings() {
        Settings s;
        s.spp = 64;
        s.seed = 7;
        s.maxDepth = 3;
        s.threads = 2;
        s.tileSize = 8;
        s.adaptive = true;
        s.minSpp = 8;
        s.noiseThreshold = 0.01;
        return s;
    }

    test::TempDir m_dir;
    std::filesystem::path m_scene;
};

/// The Cornell box, small and square (the box fills the frame: every pixel is noisy).
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

/// The sum of channel c of `layer` and the count of its pixels, over the frame.
double layerSum(const FrameBuffers& f, Layer layer, int c) {
    double sum = 0.0;
    const Image& image = f.layer(layer);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) sum += image(x, y, c);
    return sum;
}

TEST_F(AdaptiveScene, TheConvergedMeanIsTheUniformRendersWithinTheNoise) {
    // The image mean of adaptive renders (the even half never steers, and every sample)
    // against a 1024-spp uniform render of another seed, per channel: |difference| below 4
    // combined standard errors, from the variance layers (pixels independent; Sobol's layers
    // overstate the error, so the test is conservative). Six comparisons at 4 sigma: a false
    // failure about once in 2600 runs; the seeds are fixed.
    Renderer renderer(loadScene(m_scene));
    Settings uniform = adaptiveSettings();
    uniform.adaptive = false;
    uniform.spp = 1024;
    uniform.seed = 99;
    const FrameBuffers ref = renderer.render(uniform).frame;
    const double pixels = double(ref.width() * ref.height());
    for (AdaptiveError from : {AdaptiveError::Half, AdaptiveError::Whole}) {
        Settings s = adaptiveSettings();
        s.spp = 256;
        s.adaptiveError = from;
        const FrameBuffers f = renderer.render(s).frame;
        for (int c = 0; c < 3; ++c) {
            const double diff =
                (layerSum(f, Layer::Color, c) - layerSum(ref, Layer::Color, c)) / pixels;
            const double sigma =
                std::sqrt(layerSum(f, Layer::Variance, c) + layerSum(ref, Layer::Variance, c)) /
                pixels;
            std::printf("%s, channel %d: difference %.3g, %.2f sigma\n", adaptiveErrorName(from), c,
                        diff, diff / sigma);
            EXPECT_LT(std::abs(diff), 4.0 * sigma) << adaptiveErrorName(from) << " channel " << c;
        }
    }
}

TEST_F(AdaptiveScene, SamplesGoToTheNoisyPixelsAndNoneToTheNoiselessSky) {
    Renderer renderer(loadScene(m_scene));
    const FrameBuffers f = renderer.render(adaptiveSettings()).frame;
    const Image& count = f.layer(Layer::SampleCount);
    // The top row sees only the constant sky (no variance): it converges at the start. The
    // sphere's centre is noisy: it takes more.
    for (int x = 0; x < 24; ++x) EXPECT_EQ(count(x, 0, 0), 8.0f) << x;
    EXPECT_GT(count(12, 12, 0), 8.0f);
    double total = 0.0;
    for (float n : count.data()) {
        EXPECT_GE(n, 8.0f);
        EXPECT_LE(n, 64.0f);
        total += n;
    }
    // The metadata: adaptive recorded, spp the most a pixel took.
    EXPECT_EQ(f.metadata().extra.at("adaptive"), "true");
    EXPECT_EQ(f.metadata().extra.at("noiseThreshold"), "0.01");
    EXPECT_LE(f.metadata().spp, 64);
    EXPECT_LT(total, 64.0 * double(count.pixelCount()));
}

TEST_F(AdaptiveScene, SampleCountFollowsTheImportanceMap) {
    // Weight 0 in the left half: those pixels keep the start even where they are noisy; weight
    // 1 on the right with a threshold no pixel reaches: every pixel there takes spp (the
    // Cornell box has no noiseless pixel).
    Renderer renderer(cornell(24, 24));
    auto weights = std::make_shared<Image>(24, 24, 1, 1.0f);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 12; ++x) (*weights)(x, y, 0) = 0.0f;
    Settings s = adaptiveSettings();
    s.noiseThreshold = 1e-9;
    s.importance = weights;
    const FrameBuffers f = renderer.render(s).frame;
    const Image& count = f.layer(Layer::SampleCount);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            EXPECT_EQ(count(x, y, 0), x < 12 ? 8.0f : 64.0f) << x << ", " << y;
        }
}

TEST_F(AdaptiveScene, AMapTheCallbackReturnsSteersEveryPassAfterIt) {
    // No map at first and a threshold no pixel reaches: every pixel takes the first adaptive
    // pass. Before the second, the callback returns weight 0 in the left half: those pixels
    // keep the count they had then, the right half goes on to spp. Empty answers keep the map.
    Renderer renderer(cornell(24, 24));
    Settings s = adaptiveSettings();
    s.noiseThreshold = 1e-9;
    Callbacks callbacks;
    int calls = 0;
    Image countAtRefresh;
    callbacks.importance = [&](int, const FrameBuffers& frame) -> std::shared_ptr<const Image> {
        if (++calls != 2) return nullptr;
        countAtRefresh = frame.layer(Layer::SampleCount);
        auto weights = std::make_shared<Image>(24, 24, 1, 1.0f);
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 12; ++x) (*weights)(x, y, 0) = 0.0f;
        return weights;
    };
    const FrameBuffers f = renderer.render(s, callbacks).frame;
    EXPECT_GT(calls, 2);
    const Image& count = f.layer(Layer::SampleCount);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            // The first adaptive pass doubled every pixel's count (8 + 8, passes double).
            EXPECT_EQ(countAtRefresh(x, y, 0), 16.0f) << x << ", " << y;
            EXPECT_EQ(count(x, y, 0), x < 12 ? 16.0f : 64.0f) << x << ", " << y;
        }
    // A bad map from the callback is refused as a bad Settings::importance is.
    callbacks.importance = [](int, const FrameBuffers&) {
        return std::make_shared<const Image>(24, 24, 1, 0.0f);
    };
    EXPECT_NE(test::errorOf([&] { renderer.render(s, callbacks); }).find("every weight is 0"),
              std::string::npos);
}

TEST_F(AdaptiveScene, TheConvergedCallbackLowersTheThresholdAndTheRenderGoesOn) {
    // A threshold every pixel meets early ends the render well below spp. A converged callback
    // that doubles the weights (halves the threshold) up to 4 times keeps sampling: more
    // samples, and the render ends at the callback's empty answer. One that never opens a pixel
    // (weights of the same scale) is asked kMaxConvergedRetries times, then the render ends.
    Renderer renderer(cornell(24, 24));
    Settings s = adaptiveSettings();
    s.spp = 1024;
    s.noiseThreshold = 0.05;
    const FrameBuffers early = renderer.render(s).frame;
    Callbacks callbacks;
    int calls = 0;
    float scale = 1.0f;
    callbacks.converged = [&](int, const FrameBuffers&) -> std::shared_ptr<const Image> {
        if (++calls > 4) return nullptr;
        scale *= 2.0f;
        return std::make_shared<const Image>(24, 24, 1, scale);
    };
    const FrameBuffers later = renderer.render(s, callbacks).frame;
    EXPECT_EQ(calls, 5);
    auto total = [](const FrameBuffers& f) {
        double sum = 0.0;
        for (float n : f.layer(Layer::SampleCount).data()) sum += n;
        return sum;
    };
    EXPECT_GT(total(later), 2.0 * total(early));
    EXPECT_LT(total(early), 1024.0 * 24 * 24 / 4);
    calls = 0;
    callbacks.converged = [&](int, const FrameBuffers&) {
        ++calls;
        return std::make_shared<const Image>(24, 24, 1, 1.0f);
    };
    test::expectSameFrames(early, renderer.render(s, callbacks).frame);
    EXPECT_EQ(calls, kMaxConvergedRetries);
}

TEST_F(AdaptiveScene, EveryPixelContinuesItsOwnSequenceSoAllPixelsOpenIsTheUniformRender) {
    // With every pixel taking every pass, the adaptive passes (sizes 16, cut at spp) add each
    // pixel's samples 8 … 63 in order, as the uniform passes do: the same bits.
    Renderer renderer(cornell(16, 16));
    for (SamplerKind sampler : {SamplerKind::Sobol, SamplerKind::Independent}) {
        Settings s = adaptiveSettings();
        s.sampler = sampler;
        s.noiseThreshold = 1e-9;
        s.halfBuffers = true;
        const FrameBuffers a = renderer.render(s).frame;
        s.adaptive = false;
        const FrameBuffers u = renderer.render(s).frame;
        for (Layer l : {Layer::Color, Layer::Variance, Layer::HalfColor, Layer::HalfVariance,
                        Layer::Albedo, Layer::SampleCount, Layer::HalfSampleCount})
            EXPECT_TRUE(test::sameLayer(a, u, l))
                << layerDisplayName(l) << ", " << samplerName(sampler);
    }
}

TEST_F(AdaptiveScene, APassOverFewOpenPixelsTakesLargerStepsSoItsFixedCostIsShared) {
    // Four open pixels of 576 (the map's weight 0 elsewhere): a pass of 16 samples each would be
    // 64 samples, its fixed cost (the plan, the tiles, the threads meeting) many times theirs.
    // The passes double as uniform ones do, up to a step of 256 (the film's 2 spp need 288):
    // 8 passes to spp instead of 64 (the callback asks once more, before the plan that ends the
    // render), and the others keep the start.
    Renderer renderer(cornell(24, 24));
    Settings s = adaptiveSettings();
    s.spp = 1024;
    s.noiseThreshold = 1e-9;
    auto weights = std::make_shared<Image>(24, 24, 1, 0.0f);
    for (int y = 5; y < 7; ++y)
        for (int x = 5; x < 7; ++x) (*weights)(x, y, 0) = 1.0f;
    s.importance = weights;
    std::vector<float> before;  // pixel (5, 5)'s count before each adaptive pass
    Callbacks callbacks;
    callbacks.importance = [&](int, const FrameBuffers& frame) {
        before.push_back(frame.layer(Layer::SampleCount)(5, 5, 0));
        return std::shared_ptr<const Image>();
    };
    const FrameBuffers f = renderer.render(s, callbacks).frame;
    EXPECT_EQ(before, (std::vector<float>{8, 16, 32, 64, 128, 256, 512, 768, 1024}));
    const Image& count = f.layer(Layer::SampleCount);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x)
            EXPECT_EQ(count(x, y, 0), (*weights)(x, y, 0) > 0.0f ? 1024.0f : 8.0f)
                << x << ", " << y;
}

TEST_F(AdaptiveScene, TheSameSeedGivesTheSameBitsForAnyThreadCount) {
    Renderer renderer(cornell(32, 32));
    Settings s = adaptiveSettings();
    s.noiseThreshold = 0.05;
    s.threads = 1;
    s.tileSize = 16;
    const FrameBuffers one = renderer.render(s).frame;
    // The pixels took different counts (else this would test only uniform passes).
    const auto counts = one.layer(Layer::SampleCount).data();
    EXPECT_LT(*std::min_element(counts.begin(), counts.end()),
              *std::max_element(counts.begin(), counts.end()));
    s.threads = 2;
    s.tileSize = 8;
    const FrameBuffers two = renderer.render(s).frame;
    test::expectSameFrames(one, two);
    s.seed = 8;
    EXPECT_FALSE(test::sameLayer(one, renderer.render(s).frame, Layer::Color));
}

TEST_F(AdaptiveScene, BadSettingsAndMapsAreRefusedNamingTheProblem) {
    Renderer renderer(loadScene(m_scene));
    auto refused = [&](const Settings& s, const std::string& expected) {
        const std::string message = test::errorOf([&] { renderer.render(s); });
        EXPECT_NE(message.find(expected), std::string::npos)
            << "expected \"" << expected << "\" in \"" << message << "\"";
    };
    for (double t : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), 2e6}) {
        Settings s = adaptiveSettings();
        s.noiseThreshold = t;
        refused(s, "noiseThreshold must be a number in (0, 1e6]");
    }
    Settings s = adaptiveSettings();
    s.spp = 4;
    refused(s, "is below minSpp (8");
    s = adaptiveSettings();
    s.integrator = Integrator::Mlt;
    refused(s, "path integrator only");
    s = adaptiveSettings();
    s.sampler = SamplerKind::Stratified;
    refused(s, "needs the sobol, zsobol or independent sampler");
    s = adaptiveSettings();
    s.shard = Shard{0, 2};
    refused(s, "render adaptively on one machine");
    s = adaptiveSettings();
    s.adaptive = false;
    s.importance = std::make_shared<Image>(24, 18, 1, 1.0f);
    refused(s, "needs adaptive sampling on");
    // Maps: the wrong size, NaN, negative, all zero.
    s = adaptiveSettings();
    s.importance = std::make_shared<Image>(23, 18, 1, 1.0f);
    refused(s, "the importance map is 23x18, the scene renders 24x18");
    auto map = std::make_shared<Image>(24, 18, 1, 1.0f);
    (*map)(3, 4, 0) = std::numeric_limits<float>::quiet_NaN();
    s.importance = map;
    refused(s, "pixel (3, 4)");
    (*map)(3, 4, 0) = -0.5f;
    refused(s, "expected a finite weight >= 0");
    map->fill(0.0f);
    refused(s, "every weight is 0");
}

TEST_F(AdaptiveScene, AnAutomaticStartFollowsCyclesAndStopsAtSpp) {
    Settings s;
    s.noiseThreshold = 0.01;
    s.spp = 0;
    EXPECT_EQ(adaptiveStartSpp(s), 64);
    s.noiseThreshold = 0.1;
    EXPECT_EQ(adaptiveStartSpp(s), 32);
    s.noiseThreshold = 0.001;
    EXPECT_EQ(adaptiveStartSpp(s), 128);
    s.spp = 16;
    EXPECT_EQ(adaptiveStartSpp(s), 16);
    s.minSpp = 5;
    EXPECT_EQ(adaptiveStartSpp(s), 5);
}

}  // namespace
}  // namespace glint::render
