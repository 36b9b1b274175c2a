// The shapes an OpenEXR file takes besides Glint's own scanline single part — tiled (what Arnold,
// RenderMan and Nuke write by default), mip-mapped (every .tx texture), multi-part, deep — read
// through every public reader of EXRs: readExr, readImage and the shard merge.
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"
#include "glint/image/shard.h"

using namespace glint;
namespace fs = std::filesystem;

namespace {

class ExrShapes : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::path(::testing::TempDir()) /
                ("glint_exr_shapes_" +
                 std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                 "_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    fs::path m_dir;
};

/// Distinct per pixel and channel, so that a misplaced tile, row or channel shows.
float value(int x, int y, int c) {
    return float(c) * 1000.0f + float(y) * 10.0f + float(x) * 0.125f + 0.5f;
}

/// The pixels of channels [first, first + n) of a w × h image, interleaved.
std::vector<float> pixels(int w, int h, int first, int n) {
    std::vector<float> px(std::size_t(w) * h * n);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < n; ++c)
                px[(std::size_t(y) * w + x) * n + c] = value(x, y, first + c);
    return px;
}

/// A part (subimage) to write: its channel names, the first value channel, tiles (0: scanline).
struct Part {
    std::string name;
    std::vector<std::string> channels;
    int first = 0;
    int tile = 0;
};

OIIO::ImageSpec specOf(const Part& part, int w, int h) {
    OIIO::ImageSpec spec(w, h, int(part.channels.size()), OIIO::TypeFloat);
    spec.channelnames = part.channels;
    spec.alpha_channel = -1;
    if (part.tile > 0) spec.tile_width = spec.tile_height = part.tile;
    if (!part.name.empty()) spec.attribute("oiio:subimagename", part.name);
    return spec;
}

/// Writes the parts as one EXR (one part: a single-part file).
void writeExr(const std::string& file, int w, int h, const std::vector<Part>& parts) {
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out);
    std::vector<OIIO::ImageSpec> specs;
    for (const Part& p : parts) specs.push_back(specOf(p, w, h));
    ASSERT_TRUE(out->open(file, int(specs.size()), specs.data())) << out->geterror();
    for (std::size_t s = 0; s < parts.size(); ++s) {
        if (s > 0) {
            ASSERT_TRUE(out->open(file, specs[s], OIIO::ImageOutput::AppendSubimage))
                << out->geterror();
        }
        const auto px = pixels(w, h, parts[s].first, int(parts[s].channels.size()));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
}

/// Writes a tiled, mip-mapped EXR texture as maketx does (every level down to 1×1).
void writeMipMapped(const std::string& file, int w, int h) {
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeFloat);
    OIIO::ImageBuf source(spec);
    const auto px = pixels(w, h, 0, 3);
    ASSERT_TRUE(source.set_pixels(OIIO::ROI::All(), OIIO::TypeFloat, px.data()));
    OIIO::ImageSpec config;
    config.attribute("maketx:filtername", "box");
    config.tile_width = config.tile_height = 16;
    config.format = OIIO::TypeFloat;
    ASSERT_TRUE(
        OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, source, file, config))
        << OIIO::geterror();
    auto in = OIIO::ImageInput::open(file);
    ASSERT_TRUE(in && in->seek_subimage(0, 1)) << "no second MIP level in " << file;
}

/// Checks that `layer` holds value channels first.. of the written file.
void expectLayer(const Image& layer, int first) {
    for (int y = 0; y < layer.height(); ++y)
        for (int x = 0; x < layer.width(); ++x)
            for (int c = 0; c < layer.channels(); ++c)
                ASSERT_EQ(layer(x, y, c), value(x, y, first + c))
                    << "pixel (" << x << ", " << y << ") channel " << c;
}

const std::vector<std::string> kRgb{"R", "G", "B"};
const std::vector<std::string> kAlbedo{"albedo.R", "albedo.G", "albedo.B"};

/// Throws unless `f` throws a glint::Error(Format) naming `file` whose text contains `text`.
template <class F>
void expectFormatError(F&& f, const std::string& file, const std::string& text) {
    try {
        f();
        FAIL() << "accepted: " << file;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
        EXPECT_EQ(e.file(), file) << e.what();
        EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
}

}  // namespace

TEST_F(ExrShapes, TiledFilesWithPartialEdgeTilesReadLikeScanlineFiles) {
    // 37 × 29 leaves partial tiles on the right and bottom; tile sizes that divide the reader's
    // strip (16, 32), exceed it (64) and do not divide it (24).
    for (int tile : {16, 24, 32, 64}) {
        const std::string file = path("tiled" + std::to_string(tile) + ".exr");
        writeExr(file, 37, 29,
                 {{"", {"R", "G", "B", "albedo.R", "albedo.G", "albedo.B"}, 0, tile}});
        const FrameBuffers frame = readExr(file);
        ASSERT_EQ(frame.width(), 37);
        ASSERT_EQ(frame.height(), 29);
        expectLayer(frame.color(), 0);
        expectLayer(frame.layer(Layer::Albedo), 3);
        expectLayer(readImage(file, false), 0);
    }
}

TEST_F(ExrShapes, MipMappedFilesReadTheirFullResolutionLevel) {
    const std::string file = path("mip.exr");
    writeMipMapped(file, 40, 24);
    expectLayer(readExr(file).color(), 0);
    const Image plain = readImage(file, false);
    ASSERT_EQ(plain.width(), 40);
    expectLayer(plain, 0);
}

TEST_F(ExrShapes, MultiPartFilesJoinTheChannelsOfEveryPart) {
    // Part 0 holds the colour, part 1 the albedo with full channel names, part 2 the normal
    // with bare names that its part's name completes; in scanlines, then in tiles.
    for (int tile : {0, 8}) {
        const std::string file = path("multi" + std::to_string(tile) + ".exr");
        writeExr(file, 21, 13,
                 {{"rgba", kRgb, 0, tile},
                  {"albedo", kAlbedo, 3, tile},
                  {"normal", {"X", "Y", "Z"}, 6, tile}});
        const FrameBuffers frame = readExr(file);
        expectLayer(frame.color(), 0);
        expectLayer(frame.layer(Layer::Albedo), 3);
        ASSERT_TRUE(frame.has(Layer::Normal));
        expectLayer(frame.layer(Layer::Normal), 6);
    }
}

TEST_F(ExrShapes, PartsThatCannotFormOneFrameAreRefusedNamingThePart) {
    // A channel two parts both name in full.
    const std::string twice = path("twice.exr");
    writeExr(twice, 8, 8, {{"a", kRgb, 0, 0}, {"b", kAlbedo, 3, 0}, {"c", kAlbedo, 3, 0}});
    expectFormatError([&] { readExr(twice); }, twice, "part 2 ('c')");
    // A part of another size.
    const std::string sizes = path("sizes.exr");
    {
        auto out = OIIO::ImageOutput::create(sizes);
        OIIO::ImageSpec specs[2] = {specOf({"a", kRgb, 0, 0}, 8, 8),
                                    specOf({"b", kAlbedo, 3, 0}, 4, 4)};
        specs[1].full_width = specs[1].full_height = 8;  // one display window, two data windows
        ASSERT_TRUE(out->open(sizes, 2, specs));
        const auto a = pixels(8, 8, 0, 3), b = pixels(4, 4, 3, 3);
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, a.data()));
        ASSERT_TRUE(out->open(sizes, specs[1], OIIO::ImageOutput::AppendSubimage));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, b.data()));
        ASSERT_TRUE(out->close());
    }
    expectFormatError([&] { readExr(sizes); }, sizes, "expected part 0's 8x8");
}

TEST_F(ExrShapes, DeepFilesAreRefusedClearly) {
    const std::string file = path("deep.exr");
    OIIO::ImageSpec spec(4, 4, 4, OIIO::TypeFloat);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.z_channel = 3;
    spec.deep = true;
    auto out = OIIO::ImageOutput::create(file);
    ASSERT_TRUE(out->open(file, spec)) << out->geterror();
    OIIO::DeepData deep(spec);
    for (int p = 0; p < 16; ++p) deep.set_samples(p, 1);
    ASSERT_TRUE(out->write_deep_image(deep)) << out->geterror();
    ASSERT_TRUE(out->close());
    expectFormatError([&] { readExr(file); }, file, "deep EXR");
    EXPECT_THROW(readImage(file), Error);
    EXPECT_THROW(mergeShardFiles({file}, MergeKind::Whole), Error);
}

TEST_F(ExrShapes, TiledShardsMerge) {
    // Two shards of a 2 × 1 render written tiled by another tool: the merge reads their headers
    // and pixels through the same layout as readExr.
    std::vector<std::string> files;
    for (int i = 0; i < 2; ++i) {
        FrameBuffers f(2, 1);
        f.ensure(Layer::Color).fill(float(i + 1));
        f.ensure(Layer::SampleCount).fill(2.0f);
        f.metadata().spp = 2;
        ShardInfo info;
        info.index = i;
        info.count = 2;
        info.totalSpp = 4;
        std::tie(info.sampleBegin, info.sampleEnd) = shardSampleRange(4, i, 2);
        info.sceneHash = 0x1234;
        setShardInfo(f.metadata(), info);
        const std::string scan = path("scan" + std::to_string(i) + ".exr");
        glint::writeExr(f, scan);
        // Re-write it tiled, keeping every attribute.
        auto in = OIIO::ImageInput::open(scan);
        OIIO::ImageSpec spec = in->spec();
        std::vector<float> px(std::size_t(spec.image_pixels()) * spec.nchannels);
        ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, px.data()));
        in->close();
        spec.tile_width = spec.tile_height = 16;
        const std::string tiled = path("tiled" + std::to_string(i) + ".exr");
        auto out = OIIO::ImageOutput::create(tiled);
        ASSERT_TRUE(out->open(tiled, spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
        ASSERT_TRUE(out->close());
        files.push_back(tiled);
    }
    const FrameBuffers merged = mergeShardFiles(files, MergeKind::Whole);
    EXPECT_EQ(merged.color()(0, 0, 0), 1.5f);
    EXPECT_EQ(merged.layer(Layer::SampleCount)(1, 0, 0), 4.0f);
}
