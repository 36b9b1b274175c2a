// Textures: bilinear lookup with repeat wrapping, and sRGB 8-bit images linearised on load.
#include <gtest/gtest.h>

#include <limits>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

TEST(Texture, BilinearLookupWithRepeat) {
    detail::Texture tex;
    tex.image = Image(2, 1, 3);
    for (int c = 0; c < 3; ++c) tex.image(0, 0, c) = 0.0f, tex.image(1, 0, c) = 1.0f;
    // Texel centres at u = 0.25 (value 0) and u = 0.75 (value 1); halfway between is 0.5 and the
    // wrap-around midpoint u = 0 blends texel 1 and texel 0 equally.
    EXPECT_NEAR(tex.lookup({0.25f, 0.5f}).x, 0.0f, 1e-6);
    EXPECT_NEAR(tex.lookup({0.75f, 0.5f}).x, 1.0f, 1e-6);
    EXPECT_NEAR(tex.lookup({0.5f, 0.5f}).x, 0.5f, 1e-6);
    EXPECT_NEAR(tex.lookup({0.0f, 0.5f}).x, 0.5f, 1e-6);
    EXPECT_NEAR(tex.lookup({1.25f, 0.5f}).x, 0.0f, 1e-6);
}

TEST(Texture, HugeOrNonFiniteUvStaysInsideTheImage) {
    detail::Texture tex;
    tex.image = Image(4, 1, 3);
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) tex.image(x, 0, c) = float(x + 1);
    // 1e30 is an integer in float, so repeat wrapping puts it at u = 0: the midpoint of the last
    // and first texels, (4 + 1) / 2. NaN coordinates fall back to u = 0 instead of converting a
    // NaN to an integer (undefined behaviour).
    EXPECT_NEAR(tex.lookup({1e30f, 0.5f}).x, 2.5f, 1e-6);
    EXPECT_NEAR(tex.lookup({-1e30f, 0.5f}).x, 2.5f, 1e-6);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NEAR(tex.lookup({nan, nan}).x, 2.5f, 1e-6);
}

TEST(Texture, NonFiniteTexelIsRejectedNamingTheFile) {
    test::TempDir dir("texture-nan");
    Image img(4, 4, 3, 0.5f);
    img(2, 1, 1) = std::numeric_limits<float>::quiet_NaN();
    writeImage(img, dir.path() / "bad.exr");
    dir.write("quad.obj", test::quadObj());
    const auto scenePath = dir.write("scene.json", R"({
      "film": {"width": 4, "height": 4},
      "materials": {"floor": {"type": "diffuse", "texture": "bad.exr"}},
      "shapes": [{"obj": "quad.obj", "material": "floor"}]
    })");
    try {
        loadScene(scenePath);
        ADD_FAILURE() << "a NaN texel was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
        EXPECT_NE(e.file().find("bad.exr"), std::string::npos) << e.what();
        EXPECT_EQ(e.where(), "/materials/floor/texture") << e.what();
        EXPECT_NE(e.message().find("(2, 1)"), std::string::npos) << e.what();
    }
}

TEST(Texture, SrgbPngIsLinearisedIntoTheAlbedoLayer) {
    test::TempDir dir("texture");
    // 8-bit sRGB grey 128/255 decodes to linear ≈ 0.2158.
    Image img(4, 4, 3, 0.2158605f);
    writePng(img, dir.path() / "grey.png", DisplayOptions{});
    dir.write("quad.obj", test::quadObj());
    const auto scenePath = dir.write("scene.json", R"({
      "camera": {"position": [0, 3, 0.01], "lookAt": [0, 0, 0], "fovY": 20},
      "film": {"width": 4, "height": 4},
      "materials": {"floor": {"type": "diffuse", "texture": "grey.png"}},
      "shapes": [{"obj": "quad.obj", "material": "floor"}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": 2, "maxDepth": 2}
    })");
    Renderer renderer(loadScene(scenePath));
    const FrameBuffers f = renderer.render(renderer.scene().settings()).frame;
    for (float v : f.layer(Layer::Albedo).data()) EXPECT_NEAR(v, 0.2158605f, 2e-3f);
}

}  // namespace
}  // namespace glint::render
