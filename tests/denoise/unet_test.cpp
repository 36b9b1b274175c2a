// The learned filter unet (denoise/src/learned/, docs/learned.md): the weight-blob reader on
// blobs made here (good, truncated, corrupt), SHA-256, missing and corrupt weight files, equality
// with the OIDN peer on a committed crop of scenes/glossy, thread-count determinism and tiling.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "learned/oidn_color.h"
#include "learned/sha256.h"
#include "learned/tza.h"
#include "learned/unet_tiles.h"
#include "learned/weights_dir.h"
#include "synthetic_frames.h"
#include "unet_weights_dir.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using learned::parseTza;

// Appends the little-endian bytes of v.
template <typename T>
void put(std::vector<std::uint8_t>& b, T v) {
    std::uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    b.insert(b.end(), raw, raw + sizeof(T));
}

// A version-2 blob with "w" (2 × 1 × 1 × 1 oihw, fp16 1.0 and -2.0) and "b" ("x", fp32 0.5).
std::vector<std::uint8_t> tinyBlob() {
    std::vector<std::uint8_t> b;
    put<std::uint16_t>(b, 0x41D7);
    put<std::uint8_t>(b, 2);
    put<std::uint8_t>(b, 0);
    put<std::uint64_t>(b, 0);  // table offset, patched below
    const std::uint64_t wData = b.size();
    put<std::uint16_t>(b, 0x3C00);  // 1.0
    put<std::uint16_t>(b, 0xC000);  // -2.0
    const std::uint64_t bData = b.size();
    put<float>(b, 0.5f);
    const std::uint64_t table = b.size();
    std::memcpy(b.data() + 4, &table, 8);
    put<std::uint32_t>(b, 2);
    put<std::uint16_t>(b, 1);
    b.push_back('w');
    put<std::uint8_t>(b, 4);
    for (std::uint32_t d : {2u, 1u, 1u, 1u}) put<std::uint32_t>(b, d);
    for (char c : std::string("oihw")) b.push_back(std::uint8_t(c));
    b.push_back('h');
    put<std::uint64_t>(b, wData);
    put<std::uint16_t>(b, 1);
    b.push_back('b');
    put<std::uint8_t>(b, 1);
    put<std::uint32_t>(b, 1);
    b.push_back('x');
    b.push_back('f');
    put<std::uint64_t>(b, bData);
    return b;
}

TEST(UNetWeights, ABlobIsReadWithItsShapesLayoutsAndValues) {
    const auto t = parseTza(tinyBlob(), "tiny.tza");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_EQ(t.at("w").shape, (std::vector<int>{2, 1, 1, 1}));
    EXPECT_EQ(t.at("w").layout, "oihw");
    EXPECT_EQ(t.at("w").data, (std::vector<float>{1.0f, -2.0f}));
    EXPECT_EQ(t.at("b").data, (std::vector<float>{0.5f}));
}

TEST(UNetWeights, HalfFloatsConvertExactlyIncludingSubnormals) {
    EXPECT_EQ(learned::halfToFloat(0x0001), std::ldexp(1.0f, -24));
    EXPECT_EQ(learned::halfToFloat(0x03FF), 1023.0f * std::ldexp(1.0f, -24));
    EXPECT_EQ(learned::halfToFloat(0x7BFF), 65504.0f);
    EXPECT_TRUE(std::isinf(learned::halfToFloat(0xFC00)));
    EXPECT_EQ(learned::halfToFloat(0x3555), 0.333251953125f);
}

TEST(UNetWeights, EveryTruncationOfABlobIsAFormatErrorNamingFileAndByte) {
    const std::vector<std::uint8_t> blob = tinyBlob();
    for (std::size_t n = 0; n < blob.size(); ++n) {
        const std::vector<std::uint8_t> cut(blob.begin(), blob.begin() + std::ptrdiff_t(n));
        try {
            parseTza(cut, "cut.tza");
            ADD_FAILURE() << "a blob cut to " << n << " bytes was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << n;
            EXPECT_EQ(e.file(), "cut.tza");
            EXPECT_NE(e.where().find("byte"), std::string::npos) << e.what();
        }
    }
}

TEST(UNetWeights, BadMagicVersionLayoutAndDataOffsetsAreFormatErrors) {
    auto expectFormat = [](std::vector<std::uint8_t> blob, std::size_t at, std::uint8_t v,
                           const std::string& mention) {
        blob[at] = v;
        try {
            parseTza(blob, "bad.tza");
            ADD_FAILURE() << "accepted a blob with byte " << at << " = " << int(v);
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format);
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    };
    const std::vector<std::uint8_t> blob = tinyBlob();
    expectFormat(blob, 0, 0x00, "magic");
    expectFormat(blob, 2, 3, "version");
    const std::size_t table = 12 + 8;  // header, then 8 bytes of data (2 halves, 1 float)
    const std::size_t layout = table + 4 + 2 + 1 + 1 + 16;
    expectFormat(blob, layout, 'q', "layout");
    expectFormat(blob, layout + 4, 'd', "data type");
    expectFormat(blob, layout + 5 + 7, 0x7f, "past the end");  // data offset's top byte
}

TEST(UNetWeights, Sha256MatchesTheFipsExamples) {
    const std::string abc = "abc";
    EXPECT_EQ(learned::sha256Hex({abc.begin(), abc.end()}),
              "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const std::string two = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    EXPECT_EQ(learned::sha256Hex({two.begin(), two.end()}),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(learned::sha256Hex({}),
              "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

using testing::UNetWeightsDir;

TEST(UNetWeights, MissingWeightsFailWithOneLineNamingFileAndDigest) {
    const fs::path dir = fs::temp_directory_path() / "glint_unet_missing";
    fs::create_directories(dir);
    const UNetWeightsDir scope(dir);
    const FrameBuffers frame = testing::syntheticFrame(20, 16);
    try {
        applyFilter(findFilter("unet"), frame, {});
        FAIL() << "ran without weights";
    } catch (const Error& e) {
        // The filter is unavailable without them (Filter::unavailable), so applyFilter refuses.
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        const std::string what = e.what();
        EXPECT_NE(what.find("rt_hdr_alb_nrm.tza"), std::string::npos) << what;
        EXPECT_NE(what.find("sha256 e586ef2ff48d7fbb"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos);
    }
}

TEST(UNetWeights, CorruptWeightsFailWithTheExpectedDigest) {
    const fs::path dir = fs::temp_directory_path() / "glint_unet_corrupt";
    fs::create_directories(dir);
    // One flipped byte in a copy of the colour-only weights.
    std::ifstream in(testing::shippedUNetWeights() / "rt_hdr.tza", std::ios::binary);
    std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    ASSERT_GT(bytes.size(), 1000u);
    bytes[bytes.size() / 2] ^= 1;
    std::ofstream(dir / "rt_hdr.tza", std::ios::binary)
        .write(bytes.data(), std::streamsize(bytes.size()));
    const UNetWeightsDir scope(dir);
    try {
        applyFilter(findFilter("unet"), testing::syntheticFrame(20, 16), {{"features", 1}});
        FAIL() << "ran with corrupt weights";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("weights corrupt"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("sha256 a097e8fe"), std::string::npos) << e.what();
    }
}

TEST(UNetWeights, TheFolderIsTheEnvironmentsThenTheInstalledCopyThenTheSourceTree) {
    const fs::path prefix =
        fs::temp_directory_path() / ("glint_unet_lookup_" + std::to_string(::getpid()));
    const fs::path installed = prefix / "share/glint/weights/oidn";
    fs::create_directories(installed);
    const fs::path exe = prefix / "bin/glint-denoise", rel = "../share/glint/weights/oidn";
    EXPECT_EQ(learned::weightsDir("/env/weights", exe, rel, "/src/weights"), "/env/weights");
    EXPECT_EQ(learned::weightsDir("", exe, rel, "/src/weights"), installed);
    fs::remove_all(prefix);
    EXPECT_EQ(learned::weightsDir("", exe, rel, "/src/weights"), "/src/weights");
    EXPECT_EQ(learned::weightsDir("", "", rel, "/src/weights"), "/src/weights");
    // This test binary runs from the build tree, which has no installed copy.
    unsetenv("GLINT_UNET_WEIGHTS_DIR");
    EXPECT_EQ(fs::canonical(learned::weightsDir()),
              fs::canonical(fs::path(GLINT_SOURCE_DIR) / "denoise/weights/oidn"));
}

// |difference| statistics of the peer comparison (docs/learned.md, "Equality with the peer").
struct Difference {
    double meanRelative = 0.0;  ///< mean |a − b| over mean |b|
    double maxDisplay = 0.0;    ///< largest |sRGB(a) − sRGB(b)| (clamped to [0, 1])
};

double srgb(double v) {
    v = std::clamp(v, 0.0, 1.0);
    return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

Difference difference(const Image& a, const Image& b) {
    Difference d;
    double sum = 0.0, ref = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        sum += std::fabs(double(a.data()[i]) - b.data()[i]);
        ref += std::fabs(double(b.data()[i]));
        d.maxDisplay = std::max(d.maxDisplay, std::fabs(srgb(a.data()[i]) - srgb(b.data()[i])));
    }
    d.meanRelative = sum / std::max(ref, 1e-30);
    return d;
}

// The committed crop (64 × 64 of scenes/glossy at 16 spp, colour, albedo and normal in half
// floats) and the OIDN peer's output for it (tests/data/unet/README.md tells how both were made).
TEST(UNetPeer, MatchesTheOidnPeerOnACrop) {
    const fs::path data = fs::path(GLINT_SOURCE_DIR) / "tests/data/unet";
    const FrameBuffers crop = readExr(data / "glossy_crop.exr");
    const Image peer = readExr(data / "glossy_crop_peer.exr").color();
    ASSERT_TRUE(crop.has(Layer::Albedo) && crop.has(Layer::Normal));
    const Image out = applyFilter(findFilter("unet"), crop, {});
    ASSERT_TRUE(out.sameShape(peer));
    const Difference d = difference(out, peer);
    EXPECT_LT(d.meanRelative, 1e-3);
    EXPECT_LE(d.maxDisplay, 1.0 / 255.0);
    // The network did something: the output is not the noisy input.
    EXPECT_GT(difference(crop.color(), peer).meanRelative, 10 * d.meanRelative);
}

TEST(UNetColor, AutoexposureIsTheKeyOverTheBinsGeometricMeanOnAnyThreadCount) {
    // A frame of luminance 1 (the Rec. 709 weights sum to 1): the key itself.
    EXPECT_NEAR(learned::autoexposure(Image(40, 24, 3, 1.0f)), 0.18, 1e-12);
    // Four bins at 4 and four at 1/4 (their log2 mean is 0); the bins at 0 do not count.
    Image halves(64, 48, 3, 0.0f);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            for (int k = 0; k < 3; ++k) halves(x, y, k) = x < 32 ? 4.0f : 0.25f;
    EXPECT_NEAR(learned::autoexposure(halves), 0.18, 1e-12);
    // The bins are summed in parallel: the same bits on 1 and 2 threads.
    const Image noisy = testing::syntheticFrame(333, 217, 0.1f).color();
    double one = 0.0, two = 0.0;
    tbb::task_arena(1).execute([&] { one = learned::autoexposure(noisy); });
    tbb::task_arena(2).execute([&] { two = learned::autoexposure(noisy); });
    EXPECT_EQ(one, two);
}

TEST(UNetFilter, OneAndTwoThreadsGiveTheSameBits) {
    const FrameBuffers frame = testing::syntheticFrame(150, 90, 0.1f);
    for (double features : {1.0, 3.0}) {
        FilterOptions one, two;
        one.threads = 1;
        two.threads = 2;
        const ParamValues p{{"features", features}};
        const Image a = applyFilter(findFilter("unet"), frame, p, one);
        const Image b = applyFilter(findFilter("unet"), frame, p, two);
        EXPECT_EQ(testing::maxAbsDiff(a, b), 0.0) << "features " << features;
    }
}

TEST(UNetFilter, TilesCoverTheRegionOnceOnTheSixteenPixelGrid) {
    const Rect frame{0, 1000, 0, 700}, roi{13, 990, 5, 700};
    const auto tiles = learned::planUNetTiles(frame, roi, 96, 400 * 400);
    ASSERT_GT(tiles.size(), 4u);
    std::vector<int> covered(std::size_t(frame.width() * frame.height()), 0);
    for (const auto& t : tiles) {
        EXPECT_EQ(t.in.x0 % 16, 0);
        EXPECT_EQ(t.in.y0 % 16, 0);
        EXPECT_LE(
            std::int64_t(learned::alignUp16(t.in.width())) * learned::alignUp16(t.in.height()),
            std::int64_t(416) * 416);
        // Output pixels lie at least the overlap inside the window, except at the frame's edges.
        EXPECT_TRUE(t.in.x0 == 0 || t.out.x0 - t.in.x0 >= 96);
        EXPECT_TRUE(t.in.x1 == frame.x1 || t.in.x1 - t.out.x1 >= 96);
        EXPECT_TRUE(t.in.y0 == 0 || t.out.y0 - t.in.y0 >= 96);
        EXPECT_TRUE(t.in.y1 == frame.y1 || t.in.y1 - t.out.y1 >= 96);
        for (int y = t.out.y0; y < t.out.y1; ++y)
            for (int x = t.out.x0; x < t.out.x1; ++x) ++covered[std::size_t(y * 1000 + x)];
    }
    for (int y = 0; y < 700; ++y)
        for (int x = 0; x < 1000; ++x)
            ASSERT_EQ(covered[std::size_t(y * 1000 + x)], roi.contains(x, y) ? 1 : 0)
                << x << "," << y;
}

TEST(UNetFilter, TiledOutputEqualsOnePass) {
    const FrameBuffers frame = testing::syntheticFrame(420, 300, 0.1f);
    const Filter& f = findFilter("unet");
    const Image whole = applyFilter(f, frame, {});
    const Image tiled = applyFilter(f, frame, {{"memoryMB", 64}});
    EXPECT_EQ(testing::maxAbsDiff(whole, tiled), 0.0);
}

// The studio runs unet on a new worker thread for each job, on the plans (oneDNN primitives)
// that earlier, perhaps finished, threads built, and a plan may be dropped on another thread than
// its builder's: with oneDNN's own scratchpad (the creating thread's) that read freed memory
// (Studio.Screenshots' SIGSEGV, issue 48). Eight frame sizes no other test uses (more than the
// network keeps plans for), each run on a new thread, against the bits of a run on this thread.
TEST(UNetFilter, PlansBuiltOnOneThreadRunOnAnotherWithTheSameBits) {
    const Filter& f = findFilter("unet");
    const ParamValues p{{"features", 3.0}};
    FilterOptions one;
    one.threads = 1;
    std::vector<FrameBuffers> frames;
    std::vector<Image> expected;
    for (int i = 0; i < 8; ++i) {
        frames.push_back(testing::syntheticFrame(40 + 16 * i, 24 + 8 * i, 0.1f, 11));
        expected.push_back(applyFilter(f, frames.back(), p, one));
    }
    for (int round = 0; round < 24; ++round) {
        const std::size_t a = std::size_t(round * 5 % 8), b = std::size_t(round * 3 % 8);
        Image gotA, gotB;
        std::thread([&] {
            gotA = applyFilter(f, frames[a], p, one);
            gotB = applyFilter(f, frames[b], p, one);
        }).join();
        ASSERT_EQ(testing::maxAbsDiff(expected[a], gotA), 0.0) << "round " << round;
        ASSERT_EQ(testing::maxAbsDiff(expected[b], gotB), 0.0) << "round " << round;
    }
}

}  // namespace
}  // namespace glint::denoise
