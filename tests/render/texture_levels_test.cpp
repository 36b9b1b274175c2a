// Glint's filter over a tiled texture's MIP levels (TextureLevels): which levels are held in
// memory, lookups that agree with OpenImageIO's filter, single levels that average to it, texels
// read through the cache's tiles, the level a footprint picks, wrap modes, the memory taken from
// the tile cache, and renders that read no tile when all they need is resident.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/texture_levels.h"
#include "scene/texture_store.h"
#include "test_util.h"
#include "tiled_texture.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::kResidentTextureSize;
using detail::TexFootprint;
using detail::TextureLevels;
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

/// A store holding texture file `file` (index 0) and the file's levels.
struct Opened {
    TextureStore store;
    TextureLevels levels;
    explicit Opened(const fs::path& file)
        : levels(TextureLevels::read(store, store.open(file, "", ""))) {}
    Vec4 lookup(float s, float t, const TexFootprint& fp, TextureWrap wrapS = TextureWrap::Repeat,
                TextureWrap wrapT = TextureWrap::Repeat) const {
        return levels.lookup(store, 0, s, t, fp, wrapS, wrapT);
    }
};

/// An isotropic footprint `texels` texels of a `size`-texel level wide.
TexFootprint isotropic(float texels, int size) {
    const float w = texels / float(size);
    return {{w, 0.0f}, {0.0f, w}};
}

TEST(TextureLevels, HoldTheLevelsOfAtMostTheResidentSizeInMemory) {
    test::TempDir dir("levels_held");
    writeGradientTexture(dir.path() / "big.exr", 1024, 1024);
    writeGradientTexture(dir.path() / "odd.exr", 300, 200);
    const Opened big(dir.path() / "big.exr");
    // 512², 256², ..., 1²: 8 bytes a texel (half RGBA); 1024² stays in the tiles.
    std::size_t expected = 0;
    for (int s = kResidentTextureSize; s >= 1; s /= 2) expected += std::size_t(s) * s * 8;
    EXPECT_EQ(big.levels.residentBytes(), expected);
    // A file no larger than the resident size is held whole, its own size first.
    const Opened odd(dir.path() / "odd.exr");
    EXPECT_GE(odd.levels.residentBytes(), std::size_t(300) * 200 * 8);
    EXPECT_LT(odd.levels.residentBytes(), std::size_t(300) * 200 * 8 * 4 / 3 + 64);
    // The mean of a linear ramp is its value at the centre.
    const Vec4 m = big.levels.mean();
    EXPECT_NEAR(m.x, 0.5f, 2e-3f);
    EXPECT_NEAR(m.y, 0.5f, 2e-3f);
    EXPECT_EQ(m.w, 1.0f);
}

TEST(TextureLevels, AgreeWithOpenImageIosFilter) {
    // On a linear ramp any filter symmetric about its centre gives the value there, so Glint's
    // and OIIO's differ only by rounding (half floats in memory: 3 significant digits) wherever
    // the footprint falls: below a texel, in the tiles, in the resident levels, anisotropic.
    test::TempDir dir("levels_agree");
    writeGradientTexture(dir.path() / "ramp.exr", 2048, 1024);
    const Opened ramp(dir.path() / "ramp.exr");
    const TexFootprint footprints[] = {
        {},                                                          // bilinear at the finest level
        isotropic(0.4f, 2048),                                       // smaller than a texel
        isotropic(1.5f, 2048),                                       // the tiles: 2048² and 1024²
        isotropic(1.0f, 512),                                        // the finest resident level
        isotropic(2.5f, 512),                                        // between two resident levels
        isotropic(40.0f, 512),                                       // coarse
        {{4.0f / 2048, 1.0f / 2048}, {-0.25f / 2048, 1.0f / 2048}},  // 4:1, in the tiles
        {{0.0f, 30.0f / 512}, {1.0f / 512, 0.0f}},                   // 30:1, widened
    };
    for (const TexFootprint& fp : footprints)
        for (float s : {0.3f, 0.5f, 0.61f})
            for (float t : {0.35f, 0.5f, 0.7f}) {
                const Vec4 ours = ramp.lookup(s, t, fp, TextureWrap::Clamp, TextureWrap::Clamp);
                const Vec4 oiio =
                    ramp.store.lookup(0, s, t, fp, TextureWrap::Clamp, TextureWrap::Clamp, false);
                EXPECT_NEAR(ours.x, oiio.x, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.y, oiio.y, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.z, oiio.z, 4e-3f) << s << ", " << t << " fp " << fp.dx.x;
                EXPECT_NEAR(ours.x, s, 4e-3f);
            }
    // Off a ramp the two agree where both are bilinear: at the finest level (float texels read
    // from the tiles), to float rounding.
    test::writeCheckerTexture(dir.path() / "checker.exr", 1024, 3);
    const Opened checker(dir.path() / "checker.exr");
    for (float s : {0.1f, 0.2345f, 0.777f})
        for (float t : {0.01f, 0.5f, 0.9999f}) {
            const Vec4 ours = checker.lookup(s, t, {});
            const Vec4 oiio =
                checker.store.lookup(0, s, t, {}, TextureWrap::Repeat, TextureWrap::Repeat, false);
            EXPECT_NEAR(ours.x, oiio.x, 1e-5f) << s << ", " << t;
        }
}

TEST(TextureLevels, OneLevelAveragesToTheTrilinearFilter) {
    // The render's lookups read one of the filter's two MIP levels, picked by a number u. Over u
    // stratified in [0, 1) (u_i = (i + 1/2) / 4096, no randomness) they average to lookup()'s
    // value: the share of the u below the blend weight is off it by at most 1 / 4096 of the two
    // levels' difference (at most 1 here), so the means agree to 1e-3. On a 3-texel checker
    // the levels differ, so the single values spread where the filter does not.
    test::TempDir dir("levels_one_tap");
    test::writeCheckerTexture(dir.path() / "checker.exr", 2048, 3);
    const Opened checker(dir.path() / "checker.exr");
    const TexFootprint footprints[] = {
        {},                                                          // bilinear at the finest
        isotropic(1.5f, 2048),                                       // blended, in the tiles
        isotropic(2.5f, 512),                                        // blended, resident
        {{4.0f / 2048, 1.0f / 2048}, {-0.25f / 2048, 1.0f / 2048}},  // 4:1, in the tiles
        {{3.0f / 2048, 6.0f / 2048}, {1.5f / 2048, 0.0f}},           // 2:1 at a slant
        {{0.0f, 30.0f / 512}, {1.0f / 512, 0.0f}},                   // 30:1, widened
    };
    constexpr int kNumbers = 4096;
    float widestSpread = 0.0f;
    for (const TexFootprint& fp : footprints)
        for (float s : {0.3f, 0.5123f})
            for (float t : {0.35f, 0.77f}) {
                const Vec4 whole = checker.levels.lookup(checker.store, 0, s, t, fp,
                                                         TextureWrap::Repeat, TextureWrap::Repeat);
                double sum[4] = {0.0, 0.0, 0.0, 0.0};
                float lo = 1.0f, hi = 0.0f;
                for (int i = 0; i < kNumbers; ++i) {
                    const float u = (float(i) + 0.5f) / float(kNumbers);
                    const Vec4 v = checker.levels.lookupOneLevel(
                        checker.store, 0, s, t, fp, TextureWrap::Repeat, TextureWrap::Repeat, u);
                    sum[0] += v.x, sum[1] += v.y, sum[2] += v.z, sum[3] += v.w;
                    lo = std::min(lo, v.x), hi = std::max(hi, v.x);
                }
                EXPECT_NEAR(sum[0] / kNumbers, whole.x, 1e-3) << s << ", " << t << " " << fp.dx.x;
                EXPECT_NEAR(sum[1] / kNumbers, whole.y, 1e-3) << s << ", " << t << " " << fp.dx.x;
                EXPECT_NEAR(sum[2] / kNumbers, whole.z, 1e-3) << s << ", " << t << " " << fp.dx.x;
                EXPECT_NEAR(sum[3] / kNumbers, 1.0, 1e-6);
                widestSpread = std::max(widestSpread, hi - lo);
            }
    EXPECT_GT(widestSpread, 0.2f);
    // u at and beyond the ends picks one of the two levels.
    for (float u : {0.0f, 0.9999999f, 1.0f, -3.0f, 7.0f})
        EXPECT_TRUE(std::isfinite(checker.levels
                                      .lookupOneLevel(checker.store, 0, 0.5f, 0.5f, footprints[3],
                                                      TextureWrap::Repeat, TextureWrap::Repeat, u)
                                      .x));
}

TEST(TextureLevels, ReadTheTexelsOfAnUntiledFileThroughTheCachesTiles) {
    // A scanline EXR, 300 × 200: the cache cuts it into 64² tiles of its own.
    test::TempDir dir("levels_untiled");
    Image image(300, 200, 3);
    for (int y = 0; y < 200; ++y)
        for (int x = 0; x < 300; ++x)
            for (int c = 0; c < 3; ++c) image(x, y, c) = float(x + 1000 * y + 7 * c);
    writeImage(image, dir.path() / "scan.exr");
    const Opened scan(dir.path() / "scan.exr");
    // One pin across all the quads, as a lookup's taps share it: each quad reads its own tiles
    // (a quad at x = 63 or y = 127 straddles two or four).
    detail::TilePin pin;
    for (int x : {0, 63, 64, 130, 299})
        for (int y : {0, 1, 64, 127, 199}) {
            const int x1 = std::min(x + 1, 299), y1 = std::min(y + 1, 199);
            Vec4 q[4];
            ASSERT_TRUE(scan.store.texelQuad(0, 0, x, x1, y, y1, q, pin));
            EXPECT_EQ(q[0].x, float(x + 1000 * y)) << x << ", " << y;
            EXPECT_EQ(q[0].z, float(x + 1000 * y + 14)) << x << ", " << y;
            EXPECT_EQ(q[0].w, 1.0f);
            EXPECT_EQ(q[1].x, float(x1 + 1000 * y)) << x << ", " << y;
            EXPECT_EQ(q[2].x, float(x + 1000 * y1)) << x << ", " << y;
            EXPECT_EQ(q[3].x, float(x1 + 1000 * y1)) << x << ", " << y;
        }
    EXPECT_NE(pin.tile, nullptr);
    scan.store.release(pin);
    EXPECT_EQ(pin.tile, nullptr);
}

TEST(TextureLevels, AFootprintOfATexelOfTheFinestResidentLevelReadsOnlyResidentOnes) {
    test::TempDir dir("levels_cover");
    writeGradientTexture(dir.path() / "ramp.exr", 2048, 2048);
    const Opened ramp(dir.path() / "ramp.exr");
    const TextureLevels& levels = ramp.levels;
    EXPECT_FALSE(levels.resident({}));  // zero: bilinear at the finest level, in the tiles
    EXPECT_FALSE(levels.resident(isotropic(0.9f, kResidentTextureSize)));
    EXPECT_TRUE(levels.resident(isotropic(1.0f, kResidentTextureSize)));
    // Long and thin: 8 taps as wide as an eighth of the length.
    EXPECT_FALSE(levels.resident({{7.0f / kResidentTextureSize, 0.0f}, {0.0f, 1e-6f}}));
    EXPECT_TRUE(levels.resident({{9.0f / kResidentTextureSize, 0.0f}, {0.0f, 1e-6f}}));
    // A needle: its ratio is beyond any int (8 taps, widened to an eighth of its length).
    EXPECT_TRUE(levels.resident({{1.0f, 0.0f}, {0.0f, 1e-30f}}));
    EXPECT_NEAR(ramp.lookup(0.4f, 0.5f, {{0.5f, 0.0f}, {0.0f, 1e-30f}}, TextureWrap::Clamp,
                            TextureWrap::Clamp)
                    .y,
                0.5f, 4e-3f);
    // Non-finite axes count as zero.
    EXPECT_FALSE(levels.resident({{NAN, 0.0f}, {0.0f, INFINITY}}));
    EXPECT_TRUE(TextureLevels{}.empty());
    EXPECT_FALSE(TextureLevels{}.resident(isotropic(64.0f, 1)));
}

TEST(TextureLevels, FilterACheckerToGreyAndWrapAtTheEdges) {
    test::TempDir dir("levels_checker");
    test::writeCheckerTexture(dir.path() / "checker.exr", 1024, 1);
    const Opened resident(dir.path() / "checker.exr");
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

TEST(TextureLevels, PickTheLevelTheFootprintSpans) {
    // 8-texel squares at 1024²: 4 texels at the resident 512², half a texel at 64² (grey).
    test::TempDir dir("levels_pick");
    test::writeCheckerTexture(dir.path() / "checker.exr", 1024, 8);
    const Opened resident(dir.path() / "checker.exr");
    for (int k = 0; k < 16; ++k) {
        // The centre of square (k, 3): white when k + 3 is even.
        const float s = (8.0f * float(k) + 4.0f) / 1024.0f, t = 28.0f / 1024.0f;
        const float expected = (k + 3) % 2 == 0 ? 1.0f : 0.0f;
        const auto at = [&](float texels) {
            return resident.lookup(s, t, isotropic(texels, kResidentTextureSize)).x;
        };
        EXPECT_NEAR(at(1.0f), expected, 1e-3f) << k;  // the 512² level, at a texel centre
        EXPECT_NEAR(at(2.0f), expected, 0.3f) << k;   // 256²: squares of two texels
        EXPECT_NEAR(at(16.0f), 0.5f, 1e-3f) << k;     // 32²: grey
    }
}

TEST(TextureLevels, ANearlyRoundFootprintTakesOneTapAsWideAsItsLongAxis) {
    // Up to 1.25:1 a footprint is filtered as the round one of its long axis (one tap, a level
    // chosen by the long axis): exactly the same value. Past it, two taps along the long axis,
    // each as wide as the short one, which on a 3-texel checker differs somewhere.
    test::TempDir dir("levels_round");
    test::writeCheckerTexture(dir.path() / "checker.exr", 2048, 3);
    const Opened checker(dir.path() / "checker.exr");
    const float a = 2.0f / 2048;  // the short axis: two texels of the finest level
    const auto at = [&](float s, float t, const TexFootprint& fp) {
        return checker.levels.lookup(checker.store, 0, s, t, fp, TextureWrap::Repeat,
                                     TextureWrap::Repeat);
    };
    float widestGap = 0.0f;
    for (float s : {0.3f, 0.5123f, 0.61f})
        for (float t : {0.35f, 0.77f, 0.9f}) {
            const Vec4 oval = at(s, t, {{1.2f * a, 0.0f}, {0.0f, a}});
            const Vec4 round = at(s, t, {{1.2f * a, 0.0f}, {0.0f, 1.2f * a}});
            EXPECT_EQ(oval.x, round.x) << s << ", " << t;
            EXPECT_EQ(oval.y, round.y) << s << ", " << t;
            const Vec4 longer = at(s, t, {{1.6f * a, 0.0f}, {0.0f, a}});
            const Vec4 longerRound = at(s, t, {{1.6f * a, 0.0f}, {0.0f, 1.6f * a}});
            widestGap = std::max(widestGap, std::abs(longer.x - longerRound.x));
        }
    EXPECT_GT(widestGap, 0.01f);
}

TEST(TextureLevels, CountAgainstTheCacheSize) {
    TextureStore store(8);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 8.0f);
    store.addResidentBytes(std::size_t(3) << 20);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 5.0f);
    store.addResidentBytes(std::size_t(10) << 20);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 2.0f);  // never below a quarter
    store.setCacheMb(100);
    EXPECT_FLOAT_EQ(store.tileCacheMb(), 87.0f);
}

TEST(TextureLevels, ARenderOfAResidentTextureReadsNoTiles) {
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
    const detail::TextureStore& textures = *detail::sceneData(renderer.scene()).textureStore;
    ASSERT_FALSE(detail::sceneData(renderer.scene()).textures.front().levels.empty());
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
