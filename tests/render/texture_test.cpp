// Textures: bilinear lookup with repeat wrapping, and sRGB 8-bit images linearised on load.
#include <gtest/gtest.h>

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
    const FrameBuffers f = renderer.render(renderer.scene().settings());
    for (float v : f.layer(Layer::Albedo).data()) EXPECT_NEAR(v, 0.2158605f, 2e-3f);
}

}  // namespace
}  // namespace glint::render
