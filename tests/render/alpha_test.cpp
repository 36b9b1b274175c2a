// Cut-outs and stochastic transparency (glTF alphaMode MASK and BLEND, embree/alpha_filter.cpp):
// a black quad in front of a white sky hides it where it is there and shows it where it is not,
// for camera rays and shadow rays alike, from the material's opacity and its texture's alpha;
// shadow rays through BLEND surfaces carry the product of their 1 − alpha; camera and bounce
// rays choose at a BLEND surface with the bounce's component number (PathIntegrator::meetsBlend),
// unbiased for the path tracer's strategies and Metropolis, and stratified.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "embree/embree_scene.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

using detail::AlphaMode;

constexpr const char* kQuad =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

/// A black quad filling the view of a 16 × 16 film in front of a sky of radiance 1; `edit`
/// changes the quad's material (and may add textures).
template <class Edit>
Scene quadScene(const test::TempDir& dir, Edit edit) {
    dir.write("quad.obj", kQuad);
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, 3], "lookAt": [0, 0, 0], "fovY": 30},
            "film": {"width": 16, "height": 16},
            "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
            "shapes": [{"obj": "quad.obj", "material": "black"}],
            "environment": {"color": [1, 1, 1]}})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    edit(*data, data->materials[0]);
    return Scene(std::move(data));
}

FrameBuffers render(Scene scene, int spp = 16) {
    Renderer renderer(std::move(scene));
    Settings s = renderer.scene().settings();
    s.spp = spp;
    s.maxDepth = 2;
    s.threads = 2;
    return renderer.render(s).frame;
}

}  // namespace

TEST(Alpha, AMaskCutsOutBelowItsCutoff) {
    test::TempDir dir("mask");
    EXPECT_EQ(test::columnsMean(render(quadScene(dir, [](auto&, auto&) {})).color()), 0.0);
    auto mask = [](float opacity) {
        return [opacity](detail::SceneData&, detail::Material& m) {
            m.alphaMode = AlphaMode::Mask;
            m.opacity = opacity;
            m.alphaCutoff = 0.5f;
        };
    };
    EXPECT_EQ(test::columnsMean(render(quadScene(dir, mask(0.3f))).color()), 1.0);
    EXPECT_EQ(test::columnsMean(render(quadScene(dir, mask(0.7f))).color()), 0.0);
}

TEST(Alpha, TheBaseColourTexturesAlphaCutsPerTexel) {
    // A 2 × 1 texture: alpha 0 on the left half of the quad, 1 on the right.
    test::TempDir dir("texture");
    const Image c = render(quadScene(dir, [](detail::SceneData& d, detail::Material& m) {
                        detail::Texture t;
                        t.path = "alpha";
                        t.wrapS = t.wrapT = detail::TextureWrap::Clamp;
                        t.image = Image(2, 1, 4, 0.0f);
                        t.image(1, 0, 3) = 1.0f;
                        d.textures.push_back(std::move(t));
                        m.texture = int(d.textures.size()) - 1;
                        m.textureTimesFactor = true;
                        m.alphaMode = AlphaMode::Mask;
                    })).color();
    // The quad fills the film (u runs from about 0.1 to 0.9 across it); the columns clear of
    // the texels' blend: sky at the far left, quad at the far right.
    EXPECT_EQ(test::columnsMean(c, 0, 4), 1.0);
    EXPECT_EQ(test::columnsMean(c, 12, 16), 0.0);
}

TEST(Alpha, AVertexColoursAlphaCutsAMaskAcrossTheQuad) {
    // glTF's COLOR_0 alpha multiplies the material's: 0 at the left corners (x = −1), 1 at the
    // right ones, so that alpha = (x + 1) / 2 falls below the cut-off 0.5 on the left half.
    test::TempDir dir("vertex_alpha");
    const Image c = render(quadScene(dir, [](detail::SceneData& d, detail::Material& m) {
                        detail::Mesh& mesh = d.meshes[0];
                        ASSERT_EQ(mesh.vertexCount(), 4u);
                        for (const Vec3& p : mesh.positions)
                            mesh.colors.push_back({1, 1, 1, p.x < 0.0f ? 0.0f : 1.0f});
                        m.textureTimesFactor = true;  // a glTF material
                        m.alphaMode = AlphaMode::Mask;
                    })).color();
    // Sky on the left, the quad on the right, clear of the middle columns.
    EXPECT_EQ(test::columnsMean(c, 0, 6), 1.0);
    EXPECT_EQ(test::columnsMean(c, 10, 16), 0.0);
    // A material that is not glTF's ignores the colours: the quad everywhere.
    const Image opaque = render(quadScene(dir, [](detail::SceneData& d, detail::Material& m) {
                             for (int v = 0; v < 4; ++v) d.meshes[0].colors.push_back({1, 1, 1, 0});
                             m.alphaMode = AlphaMode::Mask;
                         })).color();
    EXPECT_EQ(test::columnsMean(opaque), 0.0);
}

TEST(Alpha, BlendLetsTheSkyThroughWithProbabilityOneMinusOpacity) {
    // 16 × 16 pixels × 64 samples; were each an independent Bernoulli(1 − alpha) draw, σ of
    // the mean would be at most 0.0039 (alpha 0.5); within 5σ of 1 − alpha. (The choice reads
    // a Sobol dimension, which makes the error far smaller: see the next test.)
    test::TempDir dir("blend");
    for (float alpha : {0.25f, 0.5f}) {
        const auto blend = [alpha](auto&, detail::Material& mat) {
            mat.alphaMode = AlphaMode::Blend;
            mat.opacity = alpha;
        };
        const double m = test::columnsMean(render(quadScene(dir, blend), 64).color());
        EXPECT_NEAR(m, 1.0 - alpha, 5 * std::sqrt(alpha * (1.0 - alpha) / (256.0 * 64.0))) << alpha;
    }
    // The same seed gives the same bits (the choice reads the pixel's sampler, not a thread's).
    const auto again = [&](int threads) {
        Renderer renderer(quadScene(dir, [](auto&, detail::Material& mat) {
            mat.alphaMode = AlphaMode::Blend;
            mat.opacity = 0.25f;
        }));
        Settings s = renderer.scene().settings();
        s.spp = 8;
        s.threads = threads;
        return renderer.render(s).frame.color();
    };
    const Image one = again(1), two = again(2);
    for (std::size_t i = 0; i < one.data().size(); ++i) ASSERT_EQ(one.data()[i], two.data()[i]);
}

TEST(Alpha, ShadowRaysPassWhereTheSurfaceIsNotThere) {
    // A white floor under a sun straight above, shaded by a quad 1 above it that is masked out:
    // the floor is lit as if the quad were not there (ρ/π · E = 1 for ρ = 1, E = π); opaque,
    // it is dark.
    test::TempDir dir("shadow");
    dir.write("quad.obj", kQuad);
    dir.write("floor.obj", test::floorObj(-1));
    auto scene = [&](AlphaMode mode) {
        const Scene parsed = parseScene(
            R"({"camera": {"position": [0.2, 0.3, 6], "lookAt": [0.2, 0.3, 0], "fovY": 2},
                "film": {"width": 8, "height": 8},
                "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]},
                              "white": {"type": "diffuse", "albedo": [1, 1, 1]}},
                "shapes": [{"obj": "quad.obj", "material": "black"},
                           {"obj": "floor.obj", "material": "white"}]})",
            dir.path() / "scene.json");
        auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
        data->materials[0].alphaMode = mode;
        data->materials[0].opacity = 0.0f;
        detail::PunctualLight sun;
        sun.kind = detail::PunctualLight::Kind::Directional;
        sun.direction = {0, 0, -1};
        sun.intensity = {kPi, kPi, kPi};
        data->punctualLights.push_back(sun);
        return Scene(std::move(data));
    };
    EXPECT_NEAR(test::columnsMean(render(scene(AlphaMode::Mask), 4).color()), 1.0, 1e-5);
    EXPECT_EQ(test::columnsMean(render(scene(AlphaMode::Opaque), 4).color()), 0.0);
}

namespace {

/// `count` copies of the quad stacked 0.5 apart along z (instances of one shared mesh), BLEND
/// of opacity `opacity`.
detail::SceneData stackedQuads(const test::TempDir& dir, int count, float opacity) {
    dir.write("quad.obj", kQuad);
    std::string shapes;
    for (int i = 0; i < count; ++i)
        shapes += std::string(i ? ", " : "") +
                  R"({"obj": "quad.obj", "material": "black", "transform": {"translate": [0, 0, )" +
                  std::to_string(0.5 * i) + "]}}";
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, 30], "lookAt": [0, 0, 0], "fovY": 30},
            "film": {"width": 4, "height": 4},
            "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]}},
            "shapes": [)" +
            shapes + "]}",
        dir.path() / "scene.json");
    detail::SceneData data = detail::sceneData(parsed);
    data.materials[0].alphaMode = AlphaMode::Blend;
    data.materials[0].opacity = opacity;
    return data;
}

/// Shadow segments straight down through the stack from a grid of points inside the quad
/// (clear of its diagonal), one per ray.
std::vector<ShadowRay> downwardRays(int perSide) {
    std::vector<ShadowRay> rays;
    for (int j = 0; j < perSide; ++j)
        for (int i = 0; i < perSide; ++i) {
            const float x = -0.9f + 1.8f * (float(i) + 0.5f) / float(perSide);
            const float y = -0.9f + 1.8f * (float(j) + 0.3f) / float(perSide);
            rays.push_back({{x, y, 20.0f}, {0, 0, -1}, 40.0f, 0.0f});
        }
    return rays;
}

/// visibilityMany of `rays` (packets).
std::vector<float> visibilities(const EmbreeScene& embree, const std::vector<ShadowRay>& rays) {
    std::vector<const ShadowRay*> pointers;
    for (const ShadowRay& r : rays) pointers.push_back(&r);
    std::vector<float> visible(rays.size());
    embree.visibilityMany(rays.size(), pointers.data(), visible.data());
    return visible;
}

}  // namespace

TEST(Alpha, AShadowRayCarriesTheProductOfOneMinusAlpha) {
    test::TempDir dir("blend_shadow");
    for (const auto& [count, expected] : {std::pair{1, 0.5f}, std::pair{2, 0.25f}}) {
        const detail::SceneData data = stackedQuads(dir, count, 0.5f);
        const EmbreeScene embree(data);
        // Exactly, every ray, single or in packets: each triangle counts once however often
        // Embree reports it.
        EXPECT_EQ(embree.visibility({0.3f, -0.2f, 20.0f}, {0, 0, -1}, 40.0f), expected) << count;
        const std::vector<ShadowRay> rays = downwardRays(7);
        for (float v : visibilities(embree, rays)) ASSERT_EQ(v, expected) << count;
        // A segment that stops short of the stack, and one that misses it, are clear.
        EXPECT_EQ(embree.visibility({0.3f, -0.2f, 20.0f}, {0, 0, -1}, 15.0f), 1.0f);
        EXPECT_EQ(embree.visibility({5.0f, 0.0f, 20.0f}, {0, 0, -1}, 40.0f), 1.0f);
    }
    // Opacity 1 blocks.
    const detail::SceneData opaque = stackedQuads(dir, 2, 1.0f);
    EXPECT_EQ(EmbreeScene(opaque).visibility({0.3f, -0.2f, 20.0f}, {0, 0, -1}, 40.0f), 0.0f);
}

TEST(Alpha, PastSixteenSurfacesAShadowRayFallsBackToTheStochasticChoice) {
    // 20 quads of opacity 0.5: 16 are counted (2^-16), the other 4 let a ray through with
    // probability 2^-4 each way; 64² rays, a Bernoulli(1/16) fraction: σ 0.0038, within 5σ.
    test::TempDir dir("blend_shadow_many");
    const detail::SceneData data = stackedQuads(dir, 20, 0.5f);
    const EmbreeScene embree(data);
    int through = 0;
    const std::vector<float> visible = visibilities(embree, downwardRays(64));
    for (float v : visible) {
        ASSERT_TRUE(v == 0.0f || v == 0x1p-16f) << v;
        through += v > 0.0f;
    }
    EXPECT_NEAR(double(through) / double(visible.size()), 1.0 / 16.0, 5 * 0.0038);
}

namespace {

/// A white floor at z = -1 seen from just above it (below a 2 × 2 BLEND quad of opacity 0.5 at
/// z = 0), lit by a sun straight above (irradiance π) or by a white sky.
Scene floorUnderGlass(const test::TempDir& dir, bool sun) {
    dir.write("quad.obj", kQuad);
    dir.write("floor.obj", test::floorObj(-1));
    const Scene parsed = parseScene(
        std::string(R"({"camera": {"position": [0, 0, -0.5], "lookAt": [0, 0, -1], "fovY": 0.5},
                        "film": {"width": 8, "height": 8},
                        "materials": {"black": {"type": "diffuse", "albedo": [0, 0, 0]},
                                      "white": {"type": "diffuse", "albedo": [1, 1, 1]}},
                        "shapes": [{"obj": "quad.obj", "material": "black"},
                                   {"obj": "floor.obj", "material": "white"}])") +
            (sun ? "}" : R"(, "environment": {"color": [1, 1, 1]}})"),
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    data->materials[0].alphaMode = AlphaMode::Blend;
    data->materials[0].opacity = 0.5f;
    if (sun) {
        detail::PunctualLight light;
        light.kind = detail::PunctualLight::Kind::Directional;
        light.direction = {0, 0, -1};
        light.intensity = {kPi, kPi, kPi};
        data->punctualLights.push_back(light);
    }
    return Scene(std::move(data));
}

FrameBuffers renderSeeded(Scene scene, int spp, int threads) {
    Renderer renderer(std::move(scene));
    Settings s = renderer.scene().settings();
    s.spp = spp;
    s.maxDepth = 2;
    s.threads = threads;
    s.seed = 11;
    return renderer.render(s).frame;
}

}  // namespace

TEST(Alpha, ShadowsThroughBlendAreExactNotSampled) {
    // Under the sun every shadow ray carries exactly 0.5 (ρ/π · E · 0.5): the mean is 0.5 and
    // the variance layer 0. A stochastic choice gave each sample 0 or 1 (variance of the mean
    // 0.25 / spp per pixel).
    test::TempDir dir("blend_sun");
    const FrameBuffers sun = renderSeeded(floorUnderGlass(dir, true), 16, 2);
    EXPECT_NEAR(test::columnsMean(sun.color()), 0.5, 1e-5);
    EXPECT_LT(test::columnsMean(sun.layer(Layer::Variance)), 1e-3 * 0.25 / 16);

    // Under the sky the floor below the middle of the quad sees it over a cosine-weighted
    // fraction F = (4 / (π√2)) atan(1/√2) of its hemisphere (differential area to a parallel
    // rectangle, four corners): L = 1 − 0.5 F. Within 5σ of the mean (σ from the variance
    // layer) plus 1e-3 for the pixels' footprint off the middle; seed 11.
    const double f = 4.0 / (kPi * std::sqrt(2.0)) * std::atan(1.0 / std::sqrt(2.0));
    const FrameBuffers sky = renderSeeded(floorUnderGlass(dir, false), 64, 2);
    const auto [skyMean, sigma] = test::meanAndError(sky);
    EXPECT_NEAR(skyMean, 1.0 - 0.5 * f, 5 * sigma + 1e-3);
    // Any thread count gives the same bits.
    const FrameBuffers one = renderSeeded(floorUnderGlass(dir, false), 8, 1),
                       two = renderSeeded(floorUnderGlass(dir, false), 8, 2);
    for (std::size_t i = 0; i < one.color().data().size(); ++i)
        ASSERT_EQ(one.color().data()[i], two.color().data()[i]);
    std::printf("sky: mean %.5f (expected %.5f), sigma %.3g\n", skyMean, 1.0 - 0.5 * f, sigma);
}

namespace {

/// Variance across the pixels of a film's mean (every pixel has the same expectation).
double pixelVariance(const Image& image) {
    const double m = test::columnsMean(image);
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) sum += (image(x, y, 0) - m) * (image(x, y, 0) - m);
    return sum / double(image.pixelCount() - 1);
}

}  // namespace

TEST(Alpha, TheBlendChoiceIsStratified) {
    // 16 × 16 pixels at 4 spp behind a pane of opacity 0.3. A hashed choice made each sample
    // an independent Bernoulli(0.7) draw: variance of a pixel's mean 0.21 / 4 = 0.0525. With
    // the Sobol component number a pixel's four numbers fall one in each quarter of [0, 1):
    // three or four pass, variance 0.01 (a factor 5.25). The independent sampler stands for
    // the hash. Across 256 pixels a variance is estimated within ~9 % (σ); we require the
    // factor above 2.5 and the independent sampler's variance within 30 % of 0.0525, seed 1.
    test::TempDir dir("blend_strata");
    const auto pane = [&](SamplerKind sampler) {
        Renderer renderer(quadScene(dir, [](auto&, detail::Material& mat) {
            mat.alphaMode = AlphaMode::Blend;
            mat.opacity = 0.3f;
        }));
        Settings s = renderer.scene().settings();
        s.spp = 4;
        s.maxDepth = 2;
        s.sampler = sampler;
        return pixelVariance(renderer.render(s).frame.color());
    };
    const double sobol = pane(SamplerKind::Sobol), independent = pane(SamplerKind::Independent);
    std::printf(
        "variance of a pixel behind opacity 0.3 at 4 spp: sobol %.4f, independent %.4f "
        "(Bernoulli 0.0525), factor %.1f\n",
        sobol, independent, independent / sobol);
    EXPECT_NEAR(independent, 0.0525, 0.3 * 0.0525);
    EXPECT_GT(independent / sobol, 2.5);
}

namespace {

/// The sky (radiance 1) seen straight down through `count` BLEND quads of opacity `alpha`,
/// `gap` apart (instances of one shared mesh), on an 8 × 8 film.
Scene paneStack(const test::TempDir& dir, int count, float alpha, float gap) {
    dir.write("quad.obj", kQuad);
    std::string shapes;
    for (int i = 0; i < count; ++i)
        shapes += std::string(i ? ", " : "") +
                  R"({"obj": "quad.obj", "material": "pane", "transform": {"translate": [0, 0, )" +
                  std::to_string(-gap * float(i)) + "]}}";
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, 30], "lookAt": [0, 0, 0], "fovY": 2},
            "film": {"width": 8, "height": 8},
            "materials": {"pane": {"type": "diffuse", "albedo": [0, 0, 0]}},
            "environment": {"color": [1, 1, 1]},
            "shapes": [)" +
            shapes + "]}",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    data->materials[0].alphaMode = AlphaMode::Blend;
    data->materials[0].opacity = alpha;
    return Scene(std::move(data));
}

}  // namespace

TEST(Alpha, AStackOfPanesPassesTheProductOfOneMinusAlpha) {
    // Three panes of opacity 0.5: 0.125 of the sky. 64 pixels × 256 samples; σ of independent
    // draws 0.0026, within 5σ. 80 panes of opacity 0.02 (0.98^80 = 0.199): past 64 passes the
    // hash decides (PathIntegrator::meetsBlend), unbiased too; σ 0.0031, within 5σ.
    test::TempDir dir("blend_stack");
    const double three = test::columnsMean(render(paneStack(dir, 3, 0.5f, 0.5f), 256).color());
    EXPECT_NEAR(three, 0.125, 5 * 0.0026);
    const double many = test::columnsMean(render(paneStack(dir, 80, 0.02f, 0.05f), 256).color());
    EXPECT_NEAR(many, std::pow(0.98, 80), 5 * 0.0031);
    std::printf("three panes %.5f (0.125), 80 panes %.5f (%.5f)\n", three, many,
                std::pow(0.98, 80));
}

namespace {

/// A white floor at z = -1 under a 2 × 2 light of radiance 1 at z = 0, seen from z = -0.5
/// through nothing; a BLEND pane of opacity 0.5 (black, 18 × 18) at z = -0.25 between floor
/// and light. Direct light only comes through the pane: L = 0.5 F with F the floor's form
/// factor to the light (as in floorUnderGlass).
Scene lightBehindGlass(const test::TempDir& dir) {
    dir.write("quad.obj", kQuad);
    dir.write("floor.obj", test::floorObj(-1));
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, -0.5], "lookAt": [0, 0, -1], "fovY": 0.5},
            "film": {"width": 8, "height": 8},
            "materials": {"pane": {"type": "diffuse", "albedo": [0, 0, 0]},
                          "white": {"type": "diffuse", "albedo": [1, 1, 1]},
                          "light": {"type": "diffuse", "albedo": [0, 0, 0],
                                    "emission": [1, 1, 1]}},
            "shapes": [{"obj": "quad.obj", "material": "light"},
                       {"obj": "quad.obj", "material": "pane",
                        "transform": {"scale": 9, "translate": [0, 0, -0.25]}},
                       {"obj": "floor.obj", "material": "white"}]})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    for (detail::Material& m : data->materials)
        if (m.name == "pane") {
            m.alphaMode = AlphaMode::Blend;
            m.opacity = 0.5f;
        }
    return Scene(std::move(data));
}

/// The floor's radiance under lightBehindGlass: 0.5 F.
double behindGlassRadiance() {
    return 0.5 * 4.0 / (kPi * std::sqrt(2.0)) * std::atan(1.0 / std::sqrt(2.0));
}

}  // namespace

TEST(Alpha, MisStrategiesAgreeThroughAPane) {
    // Next-event estimation multiplies the pane's 0.5 exactly; BSDF sampling reaches the light
    // through it half the time. Power, balance, light only and BSDF only: each within 5σ (σ
    // from the variance layer, 64 pixels × 256 samples, seed 11) plus 1e-3 for the pixels'
    // footprint off the middle of the floor, of 0.5 F.
    test::TempDir dir("blend_mis");
    const double expected = behindGlassRadiance();
    for (const auto& [name, mis, strategy] : test::kMisModes) {
        Renderer renderer(lightBehindGlass(dir));
        Settings s = renderer.scene().settings();
        s.spp = 256;
        s.maxDepth = 2;
        s.seed = 11;
        s.mis = mis;
        s.strategy = strategy;
        const auto [m, sigma] = test::meanAndError(renderer.render(s).frame);
        std::printf("%s: %.5f (expected %.5f), sigma %.2g\n", name, m, expected, sigma);
        EXPECT_NEAR(m, expected, 5 * sigma + 1e-3) << name;
    }
    // The same bits for any thread count.
    const FrameBuffers one = renderSeeded(lightBehindGlass(dir), 8, 1),
                       two = renderSeeded(lightBehindGlass(dir), 8, 2);
    for (std::size_t i = 0; i < one.color().data().size(); ++i)
        ASSERT_EQ(one.color().data()[i], two.color().data()[i]);
}

TEST(Alpha, MetropolisAgreesThroughAPane) {
    // Metropolis' primary-sample coordinates make the same choice. Its image mean's relative
    // standard error (mltMeanRelStdErr: b's and the chains') is reported: within 5 of them plus
    // 1e-3 of 0.5 F (seed 1, 2^16 bootstrap paths).
    test::TempDir dir("blend_mlt");
    Renderer renderer(lightBehindGlass(dir));
    Settings s = renderer.scene().settings();
    s.integrator = Integrator::Mlt;
    s.spp = 64;
    s.maxDepth = 2;
    s.mlt.chains = 64;
    s.mlt.groups = 16;
    s.mlt.bootstrap = 1 << 16;
    s.mlt.featureSpp = 1;
    const FrameBuffers f = renderer.render(s).frame;
    const double rel = std::stod(f.metadata().extra.at("mltMeanRelStdErr"));
    const double expected = behindGlassRadiance(), m = test::columnsMean(f.color());
    std::printf("mlt: %.5f (expected %.5f), mean relative standard error %.3g\n", m, expected, rel);
    EXPECT_NEAR(m, expected, 5 * rel * expected + 1e-3);
}

TEST(Alpha, AShadedPaneIsTheFeatureHitAPassedOneIsNot) {
    // A grey pane (albedo 0.2, opacity 0.5) in front of the white floor (floorUnderGlass's
    // geometry seen from above): the albedo layer is the first surface the camera ray meets,
    // 0.5 · 0.2 + 0.5 · 1 = 0.6 in expectation; 64 pixels × 64 samples, σ of independent
    // choices 0.0063 (depth 0.0079), within 5σ.
    test::TempDir dir("blend_features");
    dir.write("quad.obj", kQuad);
    dir.write("floor.obj", test::floorObj(-1));
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, 3], "lookAt": [0, 0, 0], "fovY": 5},
            "film": {"width": 8, "height": 8},
            "materials": {"pane": {"type": "diffuse", "albedo": [0.2, 0.2, 0.2]},
                          "white": {"type": "diffuse", "albedo": [1, 1, 1]}},
            "shapes": [{"obj": "quad.obj", "material": "pane"},
                       {"obj": "floor.obj", "material": "white"}],
            "environment": {"color": [1, 1, 1]}})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    data->materials[0].alphaMode = AlphaMode::Blend;
    data->materials[0].opacity = 0.5f;
    const FrameBuffers f = render(Scene(std::move(data)), 64);
    EXPECT_NEAR(test::columnsMean(f.layer(Layer::Albedo)), 0.6, 5 * 0.0063);
    // Depth likewise: the pane at 3, the floor at 4.
    EXPECT_NEAR(test::columnsMean(f.layer(Layer::Depth)), 3.5, 5 * 0.0079);
}

}  // namespace glint::render
