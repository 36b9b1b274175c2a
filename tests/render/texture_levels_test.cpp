// A file texture's resident MIP levels (ResidentLevels): which levels are held, lookups that
// agree with the TextureSystem's where they cover the footprint, the cover threshold, the
// memory they take from the tile cache, and renders that read no tiles when all is resident.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "scene/scene_data.h"
#include "scene/texture_levels.h"
#include "scene/texture_store.h"
#include "test_util.h"
#include "tiled_texture.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::kResidentTextureSize;
using detail::ResidentLevels;
using detail::TexFootprint;
using detail::TextureStore;
using detail::TextureWrap;

/// A `width` × `height` RGB texture whose value is linear in s and t (red = s, green = t, blue
/// = 1 - s): any filter symmetric about its centre gives the value at the centre.
void writeGradientTexture(const fs::path& file, int width, int height) {
    OIIO::ImageBuf image(OIIO::ImageSpec(width, height, 3, OIIO::TypeDesc::FLOAT));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float s = (float(x) + 0.5f) / float(width), t = (float(y) + 0.5f) / float(height);
            const float rgb[3] = {s, t, 1.0f - s};
            image.setpixel(x, y, rgb);
        }
    test::writeTiledTexture(image, file);
}

/// The resident levels of texture file `file`, read through a store of their own.
ResidentLevels residentOf(const fs::path& file) {
    TextureStore store;
    return ResidentLevels::read(store, store.open(file, "", ""));
}

/// An isotropic footprint `texels` texels of a `size`-texel level wide.
TexFootprint isotropic(float texels, int size) {
    const float w = texels / float(size);
    return {{w, 0.0f}, {0.0f, w}};
}

TEST(ResidentLevels, HoldsTheLevelsOfAtMostTheResidentSize) {
    test::TempDir dir("levels_held");
    writeGradientTexture(dir.path() / "big.exr", 1024, 1024);
    writeGradientTexture(dir.path() / "odd.exr", 300, 200);
    TextureStore store;
    const ResidentLevels big =
        ResidentLevels::read(store, store.open(dir.path() / "big.exr", "", ""));
    // 512², 256², ..., 1²: 8 bytes a texel (half RGBA).
    std::size_t expected = 0;
    for (int s = kResidentTextureSize; s >= 1; s /= 2) expected += std::size_t(s) * s * 8;
    EXPECT_EQ(big.bytes(), expected);
    // A file no larger than the resident size is held whole, its own size first.
    const ResidentLevels odd =
        ResidentLevels::read(store, store.open(dir.path() / "odd.exr", "", ""));
    EXPECT_GE(odd.bytes(), std::size_t(300) * 200 * 8);
    EXPECT_LT(odd.bytes(), std::size_t(300) * 200 * 8 * 4 / 3 + 64);
    // The mean of a linear ramp is its value at the centre.
    const Vec4 m = big.mean();
    EXPECT_NEAR(m.x, 0.5f, 2e-3f);
    EXPECT_NEAR(m.y, 0.5f, 2e-3f);
    EXPECT_NEAR(m.w, 1.0f, 0.0f);
}

TEST(ResidentLevels, AgreesWithTheTextureSystemWhereItCovers) {
    // On a linear ramp both filters give the value at the footprint's centre: they differ by
    // half-float rounding (3 significant digits) and OIIO's own, not by a level or a texel.
    test::TempDir dir("levels_agree");
    writeGradientTexture(dir.path() / "ramp.exr", 2048, 1024);
    auto store = std::make_shared<TextureStore>();
    const int file = store->open(dir.path() / "ramp.exr", "", "");
    const ResidentLevels resident = ResidentLevels::read(*store, file);
    const TexFootprint footprints[] = {
        isotropic(1.0f, 512),
        isotropic(2.5f, 512),
        isotropic(40.0f, 512),
        {{4.0f / 512, 1.0f / 512}, {-0.25f / 512, 1.0f / 512}},  // anisotropic, 4:1
        {{0.0f, 30.0f / 512}, {1.0f / 512, 0.0f}},               // 30:1, widened
    };
    for (const TexFootprint& fp : footprints) {
        ASSERT_TRUE(resident.covers(fp));
        for (float s : {0.3f, 0.5f, 0.61f})
            for (float t : {0.35f, 0.5f, 0.7f}) {
                const Vec4 ours = resident.lookup(s, t, fp, TextureWrap::Clamp, TextureWrap::Clamp);
                const Vec4 oiio =
                    store->lookup(file, s, t, fp, TextureWrap::Clamp, TextureWrap::Clamp, false);
                EXPECT_NEAR(ours.x, oiio.x, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.y, oiio.y, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.z, oiio.z, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.x, s, 4e-3f);
            }
    }
}

TEST(ResidentLevels, CoversFootprintsOfATexelOfTheFinestResidentLevelOrMore) {
    test::TempDir dir("levels_cover");
    writeGradientTexture(dir.path() / "ramp.exr", 2048, 2048);
    const ResidentLevels resident = residentOf(dir.path() / "ramp.exr");
    EXPECT_FALSE(resident.covers({}));  // zero: bilinear at the finest level, in the store
    EXPECT_FALSE(resident.covers(isotropic(0.9f, kResidentTextureSize)));
    EXPECT_TRUE(resident.covers(isotropic(1.0f, kResidentTextureSize)));
    // Long and thin: 8 taps as wide as an eighth of the length.
    EXPECT_FALSE(resident.covers({{7.0f / kResidentTextureSize, 0.0f}, {0.0f, 1e-6f}}));
    EXPECT_TRUE(resident.covers({{9.0f / kResidentTextureSize, 0.0f}, {0.0f, 1e-6f}}));
    // Non-finite axes count as zero.
    EXPECT_FALSE(resident.covers({{NAN, 0.0f}, {0.0f, INFINITY}}));
    EXPECT_TRUE(ResidentLevels{}.empty());
    EXPECT_FALSE(ResidentLevels{}.covers(isotropic(64.0f, 1)));
}

TEST(ResidentLevels, FilterACheckerToGreyAndWrapAtTheEdges) {
    test::TempDir dir("levels_checker");
    test::writeCheckerTexture(dir.path() / "checker.exr", 1024, 1);
    const ResidentLevels resident = residentOf(dir.path() / "checker.exr");
    // Single-texel squares: every level from 512² down is 0.5 (box-filtered).
    for (float texels : {1.0f, 3.0f, 100.0f})
        for (TextureWrap wrap : {TextureWrap::Repeat, TextureWrap::Clamp, TextureWrap::Mirror})
            for (float s : {-0.3f, 0.0f, 0.999f, 1.7f}) {
                const Vec4 v =
                    resident.lookup(s, 0.5f, isotropic(texels, kResidentTextureSize), wrap, wrap);
                EXPECT_NEAR(v.x, 0.5f, 1e-3f) << texels << " texels at s " << s;
                EXPECT_EQ(v.w, 1.0f);
            }
}

TEST(ResidentLevels, PickTheLevelTheFootprintSpans) {
    // 8-texel squares at 1024²: 4 texels at the resident 512², half a texel at 64² (grey).
    test::TempDir dir("levels_pick");
    test::writeCheckerTexture(dir.path() / "checker.exr", 1024, 8);
    const ResidentLevels resident = residentOf(dir.path() / "checker.exr");
    for (int k = 0; k < 16; ++k) {
        // The centre of square (k, 3): white when k + 3 is even.
        const float s = (8.0f * float(k) + 4.0f) / 1024.0f, t = 28.0f / 1024.0f;
        const float expected = (k + 3) % 2 == 0 ? 1.0f : 0.0f;
        const auto at = [&](float texels) {
            return resident
                .lookup(s, t, isotropic(texels, kResidentTextureSize), TextureWrap::Repeat,
                        TextureWrap::Repeat)
                .x;
        };
        EXPECT_NEAR(at(1.0f), expected, 1e-3f) << k;  // the 512² level, at a texel centre
        EXPECT_NEAR(at(2.0f), expected, 0.3f) << k;   // 256²: squares of two texels
        EXPECT_NEAR(at(16.0f), 0.5f, 1e-3f) << k;     // 32²: grey
    }
}

TEST(ResidentLevels, CountAgainstTheCacheSize) {
    TextureStore store(8);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 8.0f);
    store.addResidentBytes(std::size_t(3) << 20);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 5.0f);
    store.addResidentBytes(std::size_t(10) << 20);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 2.0f);  // never below a quarter
    store.setCacheMb(100);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 87.0f);
}

TEST(ResidentLevels, ARenderOfAResidentTextureReadsNoTiles) {
    // 512² over a 256² film: every camera hit spans two texels, every bounce more; all of it is
    // resident, read at load, and the render adds no tile to the cache.
    test::TempDir dir("levels_render");
    test::writeCheckerTexture(dir.path() / "checker.exr", 512, 8);
    dir.write("quad.obj", test::quadObj());
    const fs::path scene = dir.write("scene.json", R"({
      "camera": {"position": [0, 3, 0.001], "lookAt": [0, 0, 0], "fovY": 30},
      "film": {"width": 256, "height": 256},
      "materials": {"floor": {"type": "diffuse", "texture": "checker.exr"}},
      "shapes": [{"obj": "quad.obj", "material": "floor"}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": 2, "maxDepth": 3}
    })");
    Renderer renderer(loadScene(scene));
    const detail::TextureStore& textures = *renderer.scene().data().textureStore;
    ASSERT_FALSE(renderer.scene().data().textures.front().resident.empty());
    const std::uint64_t loaded = textures.cacheBytesUsed();
    Settings s = renderer.scene().settings();
    s.threads = 2;
    const FrameBuffers frame = renderer.render(s).frame;
    EXPECT_EQ(textures.cacheBytesUsed(), loaded);
    // And the albedo shows the 8-texel squares: dark and light pixels both.
    const Image& albedo = frame.layer(Layer::Albedo);
    float lo = 1.0f, hi = 0.0f;
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            lo = std::min(lo, albedo(x, y, 0)), hi = std::max(hi, albedo(x, y, 0));
    EXPECT_LT(lo, 0.1f);
    EXPECT_GT(hi, 0.9f);
}

}  // namespace
}  // namespace glint::render
