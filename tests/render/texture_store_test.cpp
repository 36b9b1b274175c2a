// Texture files through the scene's TextureStore (OpenImageIO's TextureSystem): tiled MIP-mapped
// EXRs read as they are, a cache smaller than the textures giving the same render, wrap modes,
// filtering over the ray footprint, sRGB decoded after filtering, and a damaged tile reported.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/texture_store.h"
#include "test_util.h"
#include "tiled_texture.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::TextureStore;
using detail::TextureWrap;

/// A texture of `store` file `file` as the loader makes one.
detail::Texture fileTexture(const std::shared_ptr<TextureStore>& store, int file,
                            TextureWrap wrap = TextureWrap::Repeat, bool srgb = false) {
    detail::Texture t;
    t.store = store;
    t.file = file;
    t.wrapS = t.wrapT = wrap;
    t.decodeSrgb = srgb;
    t.readLevels();
    return t;
}

/// Mean and variance of channel 0 of `count` lookups along a row of the texture with an
/// isotropic footprint of `width` (in uv).
std::pair<double, double> rowStatistics(const detail::Texture& t, float width, int count = 997) {
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < count; ++i) {
        const float u = (float(i) + 0.5f) / float(count);
        const double v = t.lookup({u, 0.37f}, {{width, 0.0f}, {0.0f, width}}).x;
        sum += v, sum2 += v * v;
    }
    const double mean = sum / count;
    return {mean, sum2 / count - mean * mean};
}

/// The scene of a quad (the unit square [-1, 1]² of the xz-plane, uv over [0, uvSpan]² of the
/// texture) seen from above filling a film of `pixels`², textured by `texture`.
fs::path quadScene(const test::TempDir& dir, const std::string& texture, int pixels,
                   float uvSpan = 1.0f) {
    const std::string span = std::to_string(uvSpan);
    dir.write("quad.obj", "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt " + span + " 0\nvt " +
                              span + " " + span + "\nvt 0 " + span + "\nf 1/1 4/4 3/3 2/2\n");
    return dir.write("scene.json", R"({
      "camera": {"position": [0, 3, 0.001], "lookAt": [0, 0, 0], "fovY": 30},
      "film": {"width": )" + std::to_string(pixels) +
                                       R"(, "height": )" + std::to_string(pixels) + R"(},
      "materials": {"floor": {"type": "diffuse", "texture": ")" +
                                       texture + R"("}},
      "shapes": [{"obj": "quad.obj", "material": "floor"}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": 16, "maxDepth": 2}
    })");
}

TEST(TextureStore, ReadsATiledMipmappedExrAsItIs) {
    test::TempDir dir("tex_tiled");
    test::writeCheckerTexture(dir.path() / "checker.exr", 256, 1);
    auto store = std::make_shared<TextureStore>();
    const int file = store->open(dir.path() / "checker.exr", "scene.json", "/materials/m");
    EXPECT_EQ(store->open(dir.path() / "checker.exr", "scene.json", "/materials/m"), file);
    const detail::TextureFileInfo& info = store->info(file);
    EXPECT_TRUE(info.tiled);
    EXPECT_TRUE(info.mipmapped);
    EXPECT_EQ(info.width, 256);
    EXPECT_EQ(info.channels, 3);
    EXPECT_FALSE(info.srgb);
    // At texel centres a zero footprint gives the texels themselves: (x + y) odd is black.
    const detail::Texture t = fileTexture(store, file);
    for (int x : {0, 1, 7, 200})
        for (int y : {0, 3, 128}) {
            // Glint's v runs up from the bottom row.
            const Vec2 uv{(float(x) + 0.5f) / 256.0f, 1.0f - (float(y) + 0.5f) / 256.0f};
            const Vec4 v = t.lookup(uv);
            EXPECT_EQ(v.x, (x + y) % 2 == 0 ? 1.0f : 0.0f) << x << ", " << y;
            EXPECT_EQ(v.w, 1.0f);  // no alpha in the file
        }
}

TEST(TextureStore, WrapModesRepeatClampAndMirror) {
    // Two texels, 0 and 1, sampled at their centres 0.25 and 0.75 and beyond the image.
    test::TempDir dir("tex_wrap");
    Image two(2, 1, 3, 0.0f);
    for (int c = 0; c < 3; ++c) two(1, 0, c) = 1.0f;
    writeImage(two, dir.path() / "two.exr");
    auto store = std::make_shared<TextureStore>();
    const int file = store->open(dir.path() / "two.exr", "scene.json", "/m");
    EXPECT_FALSE(store->info(file).tiled);
    auto at = [&](TextureWrap wrap, float u) {
        return fileTexture(store, file, wrap).lookup({u, 0.5f}).x;
    };
    EXPECT_NEAR(at(TextureWrap::Repeat, 1.25f), 0.0f, 1e-6);
    EXPECT_NEAR(at(TextureWrap::Repeat, -0.25f), 1.0f, 1e-6);
    EXPECT_NEAR(at(TextureWrap::Repeat, 1e30f), 0.5f, 1e-6);  // u = 0: halfway across the seam
    EXPECT_NEAR(at(TextureWrap::Clamp, 1.25f), 1.0f, 1e-6);
    EXPECT_NEAR(at(TextureWrap::Clamp, -0.25f), 0.0f, 1e-6);
    EXPECT_NEAR(at(TextureWrap::Mirror, 1.25f), 1.0f, 1e-6);   // mirrored to 0.75
    EXPECT_NEAR(at(TextureWrap::Mirror, -0.25f), 0.0f, 1e-6);  // mirrored to 0.25
}

TEST(TextureStore, AWiderFootprintBlursACheckerboardTowardsItsMean) {
    test::TempDir dir("tex_blur");
    test::writeCheckerTexture(dir.path() / "checker.exr", 512, 8);
    auto store = std::make_shared<TextureStore>();
    const detail::Texture t =
        fileTexture(store, store->open(dir.path() / "checker.exr", "scene.json", "/m"));
    // Zero footprint: sharp (squares of 8 texels, so most lookups see one square: variance
    // near that of a fair coin, 0.25). Footprints of 2, 4, 8 and 32 texels blur ever more,
    // until the squares are gone (a box-filtered MIP level of 8-texel squares is flat grey).
    const auto [sharpMean, sharpVariance] = rowStatistics(t, 0.0f);
    EXPECT_NEAR(sharpMean, 0.5, 0.05);
    EXPECT_GT(sharpVariance, 0.2);
    double previous = sharpVariance;
    for (float texels : {2.0f, 4.0f, 8.0f, 32.0f}) {
        const auto [mean, variance] = rowStatistics(t, texels / 512.0f);
        EXPECT_NEAR(mean, 0.5, 0.02) << texels;
        if (previous > 0.0) {
            EXPECT_LT(variance, previous) << texels;
        }
        previous = variance;
    }
    EXPECT_LT(previous, 1e-3);
    // A grazing footprint (long along u only) blurs too: OIIO's anisotropic filter.
    double sum2 = 0.0;
    for (int i = 0; i < 500; ++i) {
        const float v = (float(i) + 0.5f) / 500.0f;
        const double x = t.lookup({0.3f, v}, {{64.0f / 512.0f, 0.0f}, {0.0f, 1.0f / 512.0f}}).x;
        sum2 += (x - 0.5) * (x - 0.5);
    }
    EXPECT_LT(sum2 / 500.0, 0.01);
}

TEST(TextureStore, SrgbIsDecodedAfterFiltering) {
    // Encoded 0 and 255 side by side: halfway between them the filtered code value is 0.5, which
    // decodes to 0.214 (decoding first would give 0.5).
    test::TempDir dir("tex_srgb");
    Image two(2, 1, 3, 0.0f);
    for (int c = 0; c < 3; ++c) two(1, 0, c) = 1.0f;
    writePng(two, dir.path() / "two.png", DisplayOptions{});
    auto store = std::make_shared<TextureStore>();
    const int file = store->open(dir.path() / "two.png", "scene.json", "/m");
    ASSERT_TRUE(store->info(file).srgb);
    const detail::Texture t = fileTexture(store, file, TextureWrap::Clamp, true);
    EXPECT_NEAR(t.lookup({0.5f, 0.5f}).x, srgbDecode(0.5f), 1e-4);
    EXPECT_NEAR(t.lookup({0.75f, 0.5f}).x, 1.0f, 1e-6);
    // As data (normal maps, roughness) the values stay as stored.
    EXPECT_NEAR(fileTexture(store, file, TextureWrap::Clamp, false).lookup({0.5f, 0.5f}).x, 0.5f,
                1e-4);
}

TEST(TextureStore, AnUntaggedEightBitTiledFileIsSrgbAsAWholeOneIs) {
    // A tiled 8-bit TIFF that declares no colour space (as older tools write them) is sRGB, by
    // the rule readImage applies to a whole BMP or TGA; a float file that declares none is
    // linear.
    test::TempDir dir("tex_untagged");
    OIIO::ImageSpec spec(128, 128, 3, OIIO::TypeDesc::UINT8);
    spec.tile_width = spec.tile_height = 64;
    OIIO::ImageBuf grey(spec);
    const float half[3] = {0.5f, 0.5f, 0.5f};
    OIIO::ImageBufAlgo::fill(grey, half);
    grey.set_write_tiles(64, 64);
    ASSERT_TRUE(grey.write((dir.path() / "grey.tif").string()));
    test::writeCheckerTexture(dir.path() / "checker.exr", 64, 8);
    auto store = std::make_shared<TextureStore>();
    const int tif = store->open(dir.path() / "grey.tif", "scene.json", "/m");
    EXPECT_TRUE(store->info(tif).tiled);
    EXPECT_TRUE(store->info(tif).srgb);
    // The same decoded value either way (code value 128 of 255).
    const float decoded = srgbDecode(128.0f / 255.0f);
    EXPECT_NEAR(readImage(dir.path() / "grey.tif", true)(5, 5, 0), decoded, 1e-4);
    EXPECT_NEAR(
        fileTexture(store, tif, TextureWrap::Clamp, store->info(tif).srgb).lookup({0.5f, 0.5f}).x,
        decoded, 1e-4);
    EXPECT_FALSE(store->info(store->open(dir.path() / "checker.exr", "scene.json", "/m")).srgb);
    EXPECT_TRUE(srgbEncodedFile("sRGB", false));
    EXPECT_FALSE(srgbEncodedFile("Linear", true));
}

TEST(TextureStore, FarTexturesAreFilteredOverThePixelFootprint) {
    // A checkerboard of single texels, 512 of them across a 16-pixel film: one sample a pixel
    // without filtering would see 0 or 1; filtered over the pixel's footprint it is grey.
    test::TempDir dir("tex_far");
    test::writeCheckerTexture(dir.path() / "checker.exr", 512, 1);
    Renderer renderer(loadScene(quadScene(dir, "checker.exr", 16)));
    Settings s = renderer.scene().settings();
    s.spp = 1;
    s.threads = 2;
    const FrameBuffers frame = renderer.render(s).frame;
    const Image& albedo = frame.layer(Layer::Albedo);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) EXPECT_NEAR(albedo(x, y, 0), 0.5f, 0.1f) << x << ", " << y;
}

TEST(TextureStore, ACacheSmallerThanTheTexturesRendersTheSame) {
    // 1024² RGB float: 12 MB at the finest level, 16 MB with its MIP levels; a 1 MB cache evicts
    // tiles all the time. Lookups do not depend on what the cache holds, nor on the threads.
    test::TempDir dir("tex_cache");
    test::writeCheckerTexture(dir.path() / "big.exr", 1024, 3);
    // 256 pixels across a quarter of 1024 texels: camera hits read the finest level (not
    // resident) through the cache; bounces read the resident levels.
    const fs::path scene = quadScene(dir, "big.exr", 256, 0.25f);
    // Each render loads the scene afresh: a store of its own, filled from empty.
    auto render = [&](int threads, int cacheMb, std::uint64_t& cacheBytes) {
        Renderer renderer(loadScene(scene));
        Settings s = renderer.scene().settings();
        s.threads = threads;
        s.spp = 4;
        s.textureCacheMb = cacheMb;
        FrameBuffers frame = renderer.render(s).frame;
        cacheBytes = detail::sceneData(renderer.scene()).textureStore->cacheBytesUsed();
        return frame;
    };
    std::uint64_t smallBytes = 0, largeBytes = 0;
    const FrameBuffers small = render(2, 1, smallBytes);
    const FrameBuffers large = render(1, 1024, largeBytes);
    test::expectSameFrames(large, small);
    // The large cache kept every tile read; the small one held a fraction of them.
    EXPECT_LT(smallBytes * 2, largeBytes) << smallBytes << " vs " << largeBytes;
}

TEST(TextureStore, ADamagedTextureFailsNamingTheFile) {
    test::TempDir dir("tex_damaged");
    // 1024²: the finest level is not resident (kResidentTextureSize is 512).
    test::writeCheckerTexture(dir.path() / "full.exr", 1024, 4);
    const auto size = fs::file_size(dir.path() / "full.exr");
    auto expectFailure = [&](const std::string& name, bool atLoad) {
        try {
            // A texel a pixel (256 pixels over a quarter of 1024 texels): camera hits read the
            // finest level.
            Renderer renderer(loadScene(quadScene(dir, name, 256, 0.25f)));
            EXPECT_FALSE(atLoad) << name << ": loaded";
            Settings s = renderer.scene().settings();
            s.spp = 1;
            renderer.render(s);
            ADD_FAILURE() << name << ": rendered";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Io) << e.what();
            EXPECT_NE(e.file().find(name), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    };
    // Cut in half: the header is whole, but the small MIP levels at the end of the file, read
    // at load for the resident levels, are gone.
    fs::copy_file(dir.path() / "full.exr", dir.path() / "cut.exr");
    fs::resize_file(dir.path() / "cut.exr", size / 2);
    expectFailure("cut.exr", true);
    // Garbage over most of the finest level (the first three quarters of the file's tiles),
    // the resident levels after it intact: the file loads, and the tiles fail when the render
    // reads them (the lookup gives 0; render() throws once the render ends).
    fs::copy_file(dir.path() / "full.exr", dir.path() / "garbled.exr");
    {
        std::fstream f(dir.path() / "garbled.exr", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size / 10));
        const std::string junk(size * 6 / 10, '\xa5');
        f.write(junk.data(), std::streamsize(junk.size()));
    }
    expectFailure("garbled.exr", false);
}

TEST(TextureStore, AnAbsurdCacheSizeIsRefused) {
    Settings s;
    for (int mb : {0, -5, kMaxTextureCacheMb + 1}) {
        s.textureCacheMb = mb;
        try {
            validate(s);
            ADD_FAILURE() << mb << " MB accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(e.message().find("textureCacheMb"), std::string::npos) << e.what();
        }
    }
    s.textureCacheMb = 1;
    EXPECT_NO_THROW(validate(s));
}

}  // namespace
}  // namespace glint::render
