// Cut-outs and stochastic transparency (glTF alphaMode MASK and BLEND, embree/alpha_filter.cpp):
// a black quad in front of a white sky hides it where it is there and shows it where it is not,
// for camera rays and shadow rays alike, from the material's opacity and its texture's alpha.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

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

double mean(const Image& image, int x0 = 0, int x1 = -1) {
    if (x1 < 0) x1 = image.width();
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = x0; x < x1; ++x) sum += image(x, y, 0);
    return sum / (double(x1 - x0) * image.height());
}

}  // namespace

TEST(Alpha, AMaskCutsOutBelowItsCutoff) {
    test::TempDir dir("mask");
    EXPECT_EQ(mean(render(quadScene(dir, [](auto&, auto&) {})).color()), 0.0);
    auto mask = [](float opacity) {
        return [opacity](detail::SceneData&, detail::Material& m) {
            m.alphaMode = AlphaMode::Mask;
            m.opacity = opacity;
            m.alphaCutoff = 0.5f;
        };
    };
    EXPECT_EQ(mean(render(quadScene(dir, mask(0.3f))).color()), 1.0);
    EXPECT_EQ(mean(render(quadScene(dir, mask(0.7f))).color()), 0.0);
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
    EXPECT_EQ(mean(c, 0, 4), 1.0);
    EXPECT_EQ(mean(c, 12, 16), 0.0);
}

TEST(Alpha, BlendLetsTheSkyThroughWithProbabilityOneMinusOpacity) {
    // 16 × 16 pixels × 64 samples, each a Bernoulli(0.75) draw: σ of the mean 0.0034; within
    // 5σ (a 6e-7 chance of failing by accident).
    test::TempDir dir("blend");
    const double m = mean(render(quadScene(dir,
                                           [](auto&, detail::Material& mat) {
                                               mat.alphaMode = AlphaMode::Blend;
                                               mat.opacity = 0.25f;
                                           }),
                                 64)
                              .color());
    EXPECT_NEAR(m, 0.75, 5 * 0.0034);
    // The same seed gives the same bits (the decision hashes the ray, not a thread's state).
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
    dir.write("floor.obj", "v -9 -9 -1\nv 9 -9 -1\nv 9 9 -1\nv -9 9 -1\nf 1 2 3\nf 1 3 4\n");
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
    EXPECT_NEAR(mean(render(scene(AlphaMode::Mask), 4).color()), 1.0, 1e-5);
    EXPECT_EQ(mean(render(scene(AlphaMode::Opaque), 4).color()), 0.0);
}

}  // namespace glint::render
