// Layered EXR, alias tables, bad input, atomic writes and display/PNG export.
#include <gtest/gtest.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"

using namespace glint;
namespace fs = std::filesystem;

namespace {

/// A fresh directory per test, removed afterwards.
class IoTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::path(::testing::TempDir()) /
                (std::string("glint_io_") + info->test_suite_name() + "_" + info->name() + "_" +
                 std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path path(const std::string& name) const { return m_dir / name; }
    std::vector<std::string> files() const {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(m_dir)) out.push_back(e.path().filename());
        return out;
    }
    fs::path m_dir;
};

/// Writes a float EXR with arbitrary channel names and attributes, as another renderer would.
void writeRawExr(const fs::path& file, int w, int h, const std::vector<std::string>& names,
                 const std::vector<float>& pixels,
                 const std::function<void(OIIO::ImageSpec&)>& attributes = {}) {
    OIIO::ImageSpec spec(w, h, int(names.size()), OIIO::TypeFloat);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    if (attributes) attributes(spec);
    auto out = OIIO::ImageOutput::create(file.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(out->open(file.string(), spec)) << out->geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data())) << out->geterror();
    ASSERT_TRUE(out->close());
}

/// Value of channel `c` of pixel `i` in a raw test file: distinct per channel and pixel.
float rawValue(std::size_t i, int c) {
    return float(c) * 100.0f + float(i) * 0.25f + 0.5f;
}

std::vector<float> rawPixels(int w, int h, int n) {
    std::vector<float> px(std::size_t(w) * h * n);
    for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
        for (int c = 0; c < n; ++c) px[i * n + c] = rawValue(i, c);
    return px;
}

/// Checks that `layer` holds the raw channels `first..` of the file (pixel i, channel c).
void expectChannels(const Image& layer, const std::vector<int>& fileChannels, float divisor = 1) {
    ASSERT_EQ(layer.channels(), int(fileChannels.size()));
    for (std::size_t i = 0; i < layer.pixelCount(); ++i)
        for (int c = 0; c < layer.channels(); ++c)
            ASSERT_EQ(layer.data()[i * layer.channels() + c],
                      rawValue(i, fileChannels[c]) / divisor)
                << "pixel " << i << " channel " << c;
}

bool bitEqual(const Image& a, const Image& b) {
    return a.sameShape(b) &&
           std::memcmp(a.data().data(), b.data().data(), a.data().size() * sizeof(float)) == 0;
}

/// A 7x5 frame with every layer and awkward values (NaN, ±Inf, -0, denormals, huge).
FrameBuffers everyLayerFrame() {
    FrameBuffers frame(7, 5);
    const float special[] = {std::numeric_limits<float>::quiet_NaN(),
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             -0.0f,
                             std::numeric_limits<float>::denorm_min(),
                             3.4e38f,
                             1.0f / 3.0f};
    for (int l = 0; l < kLayerCount; ++l) {
        Image& im = frame.ensure(Layer(l));
        for (std::size_t i = 0; i < im.data().size(); ++i)
            im.data()[i] = (i % 11 == 3) ? special[(i + l) % 7] : float(l) + 0.001f * float(i);
    }
    FrameMetadata& md = frame.metadata();
    md.spp = 64;
    md.seed = 18446744073709551557ull;  // needs all 64 bits
    md.integrator = "mlt";
    md.scene = "scenes/cornell/scene.json";
    md.varianceOf = "mean";
    md.normalSpace = "world";
    md.depthKind = "cameraZ";
    md.nonFiniteSamples = 5000000000ll;
    md.extra["renderSeconds"] = "12.5";
    md.extra["note"] = "with spaces, and: colons";
    return frame;
}

}  // namespace

TEST_F(IoTest, RoundTripEveryLayerBitExact) {
    const FrameBuffers frame = everyLayerFrame();
    writeExr(frame, path("all.exr"));
    const FrameBuffers back = readExr(path("all.exr"));
    ASSERT_EQ(back.width(), 7);
    ASSERT_EQ(back.height(), 5);
    for (int l = 0; l < kLayerCount; ++l) {
        ASSERT_TRUE(back.has(Layer(l))) << channelName(Layer(l), 0);
        EXPECT_TRUE(bitEqual(back.layer(Layer(l)), frame.layer(Layer(l))))
            << channelName(Layer(l), 0);
    }
    const FrameMetadata& md = back.metadata();
    EXPECT_EQ(md.spp, 64);
    EXPECT_EQ(md.seed, 18446744073709551557ull);
    EXPECT_EQ(md.integrator, "mlt");
    EXPECT_EQ(md.scene, "scenes/cornell/scene.json");
    EXPECT_EQ(md.varianceOf, "mean");
    EXPECT_EQ(md.normalSpace, "world");
    EXPECT_EQ(md.depthKind, "cameraZ");
    EXPECT_EQ(md.nonFiniteSamples, 5000000000ll);
    EXPECT_EQ(md.source, "glint");
    EXPECT_EQ(md.extra, frame.metadata().extra);
    EXPECT_EQ(files(), std::vector<std::string>{"all.exr"});

    // Zip compression is lossless too.
    writeExr(frame, path("zip.exr"), {.compression = ExrCompression::Zip});
    const FrameBuffers zipped = readExr(path("zip.exr"));
    for (int l = 0; l < kLayerCount; ++l)
        EXPECT_TRUE(bitEqual(zipped.layer(Layer(l)), frame.layer(Layer(l))));
}

TEST_F(IoTest, WritesDesignChannelNamesAndAttributes) {
    FrameBuffers frame(3, 2);
    frame.ensure(Layer::Depth);
    frame.ensure(Layer::SampleCount);
    frame.ensure(Layer::Noisy);
    frame.metadata().spp = 8;
    frame.metadata().extra["foo"] = "bar";
    writeExr(frame, path("names.exr"));
    auto in = OIIO::ImageInput::open(path("names.exr").string());
    ASSERT_TRUE(in);
    const OIIO::ImageSpec& spec = in->spec();
    std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R", "depth.Z", "noisy.B", "noisy.G",
                                               "noisy.R", "sampleCount.Y"}));
    EXPECT_EQ(spec.format, OIIO::TypeFloat);
    EXPECT_EQ(spec.get_string_attribute("compression"), "none");
    EXPECT_EQ(spec.get_int_attribute("glint:spp"), 8);
    EXPECT_EQ(spec.get_string_attribute("glint:varianceOf"), "mean");
    EXPECT_EQ(spec.get_string_attribute("glint:normalSpace"), "world");
    EXPECT_EQ(spec.get_string_attribute("glint:depth"), "cameraZ");
    EXPECT_EQ(spec.get_string_attribute("glint:foo"), "bar");
    EXPECT_EQ(in->spec(0, 0).nchannels, 8);
    EXPECT_FALSE(in->seek_subimage(1, 0));  // one part
    in->geterror();
}

TEST_F(IoTest, ReadsCyclesNames) {
    for (const std::string prefix : {"ViewLayer.", ""}) {
        const std::vector<std::string> names = {
            prefix + "Combined.R",         prefix + "Combined.G",
            prefix + "Combined.B",         prefix + "Combined.A",
            prefix + "Denoising Albedo.R", prefix + "Denoising Albedo.G",
            prefix + "Denoising Albedo.B", prefix + "Denoising Normal.X",
            prefix + "Denoising Normal.Y", prefix + "Denoising Normal.Z",
            prefix + "Denoising Depth.Z",  prefix + "Noisy Image.R",
            prefix + "Noisy Image.G",      prefix + "Noisy Image.B"};
        writeRawExr(path("cycles.exr"), 4, 3, names, rawPixels(4, 3, int(names.size())),
                    [](OIIO::ImageSpec& s) { s.attribute("cycles.ViewLayer.samples", "128"); });
        const FrameBuffers f = readExr(path("cycles.exr"));
        EXPECT_EQ(f.metadata().source, "cycles") << prefix;
        EXPECT_EQ(f.metadata().spp, 128);
        expectChannels(f.color(), {0, 1, 2});
        expectChannels(f.layer(Layer::Albedo), {4, 5, 6});
        expectChannels(f.layer(Layer::Normal), {7, 8, 9});
        expectChannels(f.layer(Layer::Depth), {10});
        // With denoising on, Combined is denoised and Noisy Image the render's colour.
        expectChannels(f.layer(Layer::Noisy), {11, 12, 13});
        EXPECT_FALSE(f.has(Layer::Variance));
        EXPECT_FALSE(f.has(Layer::Position));
    }
}

TEST_F(IoTest, ReadsPbrtNamesAndDividesVarianceBySpp) {
    const std::vector<std::string> names = {
        "R",   "G",          "B",          "Albedo.R",   "Albedo.G", "Albedo.B", "N.X",
        "N.Y", "N.Z",        "Ns.X",       "Ns.Y",       "Ns.Z",     "P.X",      "P.Y",
        "P.Z", "Variance.R", "Variance.G", "Variance.B", "u",        "v"};
    writeRawExr(path("pbrt.exr"), 5, 2, names, rawPixels(5, 2, int(names.size())),
                [](OIIO::ImageSpec& s) { s.attribute("samplesPerPixel", 16); });
    const FrameBuffers f = readExr(path("pbrt.exr"));
    EXPECT_EQ(f.metadata().source, "pbrt");
    EXPECT_EQ(f.metadata().spp, 16);
    EXPECT_EQ(f.metadata().normalSpace, "camera");
    EXPECT_EQ(f.metadata().varianceOf, "mean");
    expectChannels(f.color(), {0, 1, 2});
    expectChannels(f.layer(Layer::Albedo), {3, 4, 5});
    expectChannels(f.layer(Layer::Normal), {9, 10, 11});  // shading normal Ns preferred over N
    expectChannels(f.layer(Layer::Position), {12, 13, 14});
    expectChannels(f.layer(Layer::Depth), {14});                    // camera-space z = P.Z
    expectChannels(f.layer(Layer::Variance), {15, 16, 17}, 16.0f);  // per sample / spp
}

TEST_F(IoTest, PbrtVarianceWithoutSppFailsClearly) {
    const std::vector<std::string> names = {"R",          "G",          "B",
                                            "Variance.R", "Variance.G", "Variance.B"};
    writeRawExr(path("pbrt_nospp.exr"), 2, 2, names, rawPixels(2, 2, 6));
    try {
        readExr(path("pbrt_nospp.exr"));
        FAIL() << "expected glint::Error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_NE(std::string(e.what()).find("pbrt_nospp.exr"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("samplesPerPixel"), std::string::npos);
    }
    // pbrt names without Variance need no sample count; N is used when Ns is absent.
    const std::vector<std::string> n2 = {"R", "G", "B", "N.X", "N.Y", "N.Z"};
    writeRawExr(path("pbrt_n.exr"), 2, 2, n2, rawPixels(2, 2, 6));
    const FrameBuffers f = readExr(path("pbrt_n.exr"));
    EXPECT_EQ(f.metadata().source, "pbrt");
    expectChannels(f.layer(Layer::Normal), {3, 4, 5});
}

TEST_F(IoTest, ReadsMitsubaNames) {
    const std::vector<std::string> names = {"R",           "G",           "B",        "A",
                                            "albedo.R",    "albedo.G",    "albedo.B", "sh_normal.X",
                                            "sh_normal.Y", "sh_normal.Z", "depth.T"};
    writeRawExr(path("mitsuba.exr"), 3, 4, names, rawPixels(3, 4, int(names.size())));
    const FrameBuffers f = readExr(path("mitsuba.exr"));
    EXPECT_EQ(f.metadata().source, "mitsuba");
    EXPECT_EQ(f.metadata().depthKind, "rayDistance");
    expectChannels(f.color(), {0, 1, 2});
    expectChannels(f.layer(Layer::Albedo), {4, 5, 6});
    expectChannels(f.layer(Layer::Normal), {7, 8, 9});
    expectChannels(f.layer(Layer::Depth), {10});
}

namespace {
/// Runs `f`, expecting a glint::Error of `kind` whose text names `file` and contains `needle`.
template <typename F>
void expectError(F&& f, ErrorKind kind, const fs::path& file, const std::string& needle) {
    try {
        f();
        ADD_FAILURE() << "expected glint::Error for " << file;
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        EXPECT_EQ(e.file(), file.string()) << e.what();
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}
}  // namespace

TEST_F(IoTest, BadInputNamesFileAndProblem) {
    expectError([&] { readExr(path("missing.exr")); }, ErrorKind::Io, path("missing.exr"),
                "does not exist");
    expectError([&] { readImage(path("missing.png")); }, ErrorKind::Io, path("missing.png"),
                "does not exist");

    std::ofstream(path("text.exr")) << "this is not an image\n";
    expectError([&] { readExr(path("text.exr")); }, ErrorKind::Format, path("text.exr"),
                "not an image");

    // A valid EXR cut short: the header survives, pixel data does not.
    FrameBuffers frame(64, 64);
    for (float& v : frame.color().data()) v = 0.37f;
    frame.ensure(Layer::Albedo);
    writeExr(frame, path("whole.exr"));
    const auto size = fs::file_size(path("whole.exr"));
    fs::copy_file(path("whole.exr"), path("cut.exr"));
    fs::resize_file(path("cut.exr"), size * 2 / 3);
    // It names the first row whose data is not all there: uncompressed rows are stored in order
    // at the end, each 8 bytes (its y and size) and 64 pixels of 6 floats.
    const std::uintmax_t rowBytes = 8 + 64 * 6 * 4, dataStart = size - 64 * rowBytes;
    const std::uintmax_t firstCut = (size * 2 / 3 - dataStart) / rowBytes;
    expectError([&] { readExr(path("cut.exr")); }, ErrorKind::Format, path("cut.exr"),
                "row " + std::to_string(firstCut) + ": truncated or corrupt pixel data");
    fs::copy_file(path("whole.exr"), path("header_only.exr"));
    fs::resize_file(path("header_only.exr"), 40);
    expectError([&] { readExr(path("header_only.exr")); }, ErrorKind::Format,
                path("header_only.exr"), "");

    // A corrupt header claiming a huge size is refused before anything is allocated: patch
    // dataWindow's xmax/ymax (box2i: four little-endian int32 after "dataWindow\0box2i\0" and
    // a 4-byte size) to 1e9 in a copy of a valid file.
    {
        std::ifstream in(path("whole.exr"), std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const std::string key("dataWindow\0box2i\0", 17);
        const std::size_t at = bytes.find(key);
        ASSERT_NE(at, std::string::npos);
        const std::int32_t huge = 1000000000;
        std::memcpy(&bytes[at + key.size() + 4 + 8], &huge, 4);
        std::memcpy(&bytes[at + key.size() + 4 + 12], &huge, 4);
        std::ofstream(path("huge.exr"), std::ios::binary) << bytes;
        expectError([&] { readExr(path("huge.exr")); }, ErrorKind::Format, path("huge.exr"), "");
        expectError([&] { readImage(path("huge.exr")); }, ErrorKind::Format, path("huge.exr"), "");
    }

    // Missing colour channels.
    writeRawExr(path("nocolor.exr"), 2, 2, {"albedo.R", "albedo.G", "albedo.B"},
                rawPixels(2, 2, 3));
    expectError([&] { readExr(path("nocolor.exr")); }, ErrorKind::Format, path("nocolor.exr"),
                "expected R, G, B");
    writeRawExr(path("cycles_nocolor.exr"), 2, 2, {"ViewLayer.Denoising Depth.Z"},
                rawPixels(2, 2, 1));
    expectError([&] { readExr(path("cycles_nocolor.exr")); }, ErrorKind::Format,
                path("cycles_nocolor.exr"), "ViewLayer.Combined.R");

    // A layer with a channel missing.
    writeRawExr(path("partial.exr"), 2, 2, {"R", "G", "B", "normal.X", "normal.Y"},
                rawPixels(2, 2, 5));
    expectError([&] { readExr(path("partial.exr")); }, ErrorKind::Format, path("partial.exr"),
                "normal.Z missing");

    // An image that is not an EXR.
    writePng(Image(2, 2, 3, 0.5f), path("pic.png"));
    expectError([&] { readExr(path("pic.png")); }, ErrorKind::Format, path("pic.png"),
                "expected an OpenEXR file");

    // A directory, and a directory that does not exist for writing.
    expectError([&] { readExr(m_dir); }, ErrorKind::Io, m_dir, "directory");
    expectError([&] { writeExr(frame, path("no/such/dir/out.exr")); }, ErrorKind::Io,
                path("no/such/dir/out.exr"), "");
}

// A frame's file depends on its pixels and attributes alone (no date, no writer's stamp), so the
// bank's cached members and their checksums are the same from any build at any time
// (docs/distributed.md).
TEST_F(IoTest, WritingAFrameTwiceGivesTheSameBytes) {
    FrameBuffers frame(9, 7);
    for (std::size_t i = 0; i < frame.color().data().size(); ++i)
        frame.color().data()[i] = float(i) * 0.25f;
    frame.ensure(Layer::Albedo).fill(0.5f);
    frame.metadata().spp = 3;
    writeExr(frame, path("first.exr"));
    ::sleep(1);  // a stamp of the time, to the second, would differ
    writeExr(frame, path("second.exr"));
    auto bytes = [](const std::string& file) {
        std::ifstream in(file, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string first = bytes(path("first.exr"));
    EXPECT_FALSE(first.empty());
    EXPECT_EQ(first, bytes(path("second.exr")));
}

TEST_F(IoTest, AtomicWriteLeavesNoTemporaryOnFailure) {
    std::ofstream(path("keep.txt")) << "old";
    fs::path seenTmp;
    EXPECT_THROW(writeAtomically(path("keep.txt"),
                                 [&](const fs::path& tmp) {
                                     seenTmp = tmp;
                                     std::ofstream(tmp) << "half";
                                     throw Error(ErrorKind::Io, "disk full");
                                 }),
                 Error);
    EXPECT_NE(seenTmp, path("keep.txt"));
    EXPECT_EQ(seenTmp.parent_path(), m_dir);
    EXPECT_EQ(seenTmp.extension(), ".txt");
    EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});
    std::string content;
    std::ifstream(path("keep.txt")) >> content;
    EXPECT_EQ(content, "old");

    // A frame that cannot be written (extra key shadowing a field) leaves nothing either.
    FrameBuffers frame(2, 2);
    frame.metadata().extra["spp"] = "3";
    EXPECT_THROW(writeExr(frame, path("bad.exr")), Error);
    EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});

    // Success replaces the file.
    writeAtomically(path("keep.txt"), [](const fs::path& tmp) { std::ofstream(tmp) << "new"; });
    std::ifstream(path("keep.txt")) >> content;
    EXPECT_EQ(content, "new");
    EXPECT_EQ(files(), std::vector<std::string>{"keep.txt"});
}

TEST(Display, SrgbKnownValues) {
    EXPECT_EQ(srgbEncode(0.0f), 0.0f);
    EXPECT_NEAR(srgbEncode(1.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(srgbEncode(0.0031308f), 0.0404500f, 1e-6f);  // the linear segment's end
    EXPECT_NEAR(srgbEncode(0.5f), 0.7353570f, 1e-6f);        // 1.055 * 0.5^(1/2.4) - 0.055
    EXPECT_NEAR(srgbEncode(0.18f), 0.4613561f, 1e-6f);
    EXPECT_NEAR(srgbEncode(0.001f), 0.01292f, 1e-7f);
    for (float v : {0.0f, 0.002f, 0.04f, 0.2f, 0.5f, 0.9f, 1.0f})
        EXPECT_NEAR(srgbDecode(srgbEncode(v)), v, 1e-6f);
}

TEST(Display, ExposureClampNanAndFalseColor) {
    Image im(4, 1, 3);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float px[4][3] = {{0.25f, 0.125f, 0.0f},
                            {2.0f, -1.0f, 0.5f},
                            {nan, 0.0f, 0.0f},
                            {0.0f, std::numeric_limits<float>::infinity(), 0.0f}};
    for (int x = 0; x < 4; ++x)
        for (int c = 0; c < 3; ++c) im(x, 0, c) = px[x][c];
    const Image d = toDisplay(im, {.exposure = 1.0f});
    EXPECT_NEAR(d(0, 0, 0), srgbEncode(0.5f), 1e-6f);  // 0.25 * 2^1
    EXPECT_NEAR(d(0, 0, 1), srgbEncode(0.25f), 1e-6f);
    EXPECT_NEAR(d(1, 0, 0), 1.0f, 1e-6f);  // clamped high
    EXPECT_EQ(d(1, 0, 1), 0.0f);           // clamped low
    EXPECT_NEAR(d(1, 0, 2), 1.0f, 1e-6f);  // 0.5 * 2 = 1
    for (int x : {2, 3}) {                 // NaN, Inf → magenta
        EXPECT_EQ(d(x, 0, 0), 1.0f);
        EXPECT_EQ(d(x, 0, 1), 0.0f);
        EXPECT_EQ(d(x, 0, 2), 1.0f);
    }
    const Image lin = toDisplay(im, {.exposure = -1.0f, .srgb = false});
    EXPECT_EQ(lin(0, 0, 0), 0.125f);

    // One channel is grey; false colour maps lo and hi to the ramp's ends.
    Image grey(3, 1, 1);
    grey(0, 0, 0) = 0.5f;
    grey(1, 0, 0) = 10.0f;
    grey(2, 0, 0) = 20.0f;
    const Image g = toDisplay(grey);
    EXPECT_EQ(g(0, 0, 0), g(0, 0, 1));
    EXPECT_EQ(g(0, 0, 1), g(0, 0, 2));
    DisplayOptions fc{.falseColorChannel = 0, .falseColorLo = 10.0f, .falseColorHi = 20.0f};
    const Image f = toDisplay(grey, fc);
    EXPECT_EQ(f(0, 0, 0), f(1, 0, 0));  // below lo clamps to the low end
    EXPECT_NE(f(1, 0, 0), f(2, 0, 0));
    EXPECT_GT(f(2, 0, 1), 0.8f);  // the high end is bright yellow
    EXPECT_LT(f(1, 0, 1), 0.1f);  // the low end is dark purple
    EXPECT_THROW(toDisplay(grey, {.falseColorChannel = 1}), Error);
    EXPECT_THROW(toDisplay(grey, {.falseColorChannel = 0, .falseColorLo = 1, .falseColorHi = 1}),
                 Error);
}

TEST_F(IoTest, PngHoldsDisplayBytes) {
    Image im(3, 1, 3);
    im(0, 0, 0) = 0.25f;  // × 2 = 0.5 → sRGB 0.73536 → 187.5 → 188
    im(0, 0, 1) = 1.0f;   // clamps to 255
    im(0, 0, 2) = -3.0f;  // clamps to 0
    im(1, 0, 0) = std::numeric_limits<float>::quiet_NaN();
    im(2, 0, 0) = 0.0005f;  // × 2 = 0.001 → 0.01292 → 3.29 → 3
    writePng(im, path("out.png"), {.exposure = 1.0f});
    auto in = OIIO::ImageInput::open(path("out.png").string());
    ASSERT_TRUE(in);
    ASSERT_EQ(in->spec().nchannels, 3);
    ASSERT_EQ(in->spec().format, OIIO::TypeUInt8);
    unsigned char px[9];
    ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeUInt8, px));
    EXPECT_EQ(px[0], 188);
    EXPECT_EQ(px[1], 255);
    EXPECT_EQ(px[2], 0);
    EXPECT_EQ(px[3], 255);  // NaN: magenta
    EXPECT_EQ(px[4], 0);
    EXPECT_EQ(px[5], 255);
    EXPECT_EQ(px[6], 3);
    in->close();
    EXPECT_EQ(files(), std::vector<std::string>{"out.png"});
}

TEST_F(IoTest, PlainImagesRoundTrip) {
    Image im(5, 3, 3);
    for (std::size_t i = 0; i < im.data().size(); ++i) im.data()[i] = float(i) / 45.0f;
    writeImage(im, path("plain.exr"));
    EXPECT_TRUE(bitEqual(readImage(path("plain.exr")), im));

    // 8-bit files are sRGB-encoded on write and decoded on read: within one 8-bit step.
    writeImage(im, path("plain.png"));
    const Image back = readImage(path("plain.png"));
    ASSERT_TRUE(back.sameShape(im));
    for (std::size_t i = 0; i < im.data().size(); ++i) {
        const float v = im.data()[i];
        EXPECT_NEAR(srgbEncode(back.data()[i]), srgbEncode(v), 0.5f / 255.0f + 1e-5f);
    }
    const Image raw = readImage(path("plain.png"), false);
    EXPECT_NEAR(raw.data()[44], srgbEncode(44.0f / 45.0f), 0.5f / 255.0f + 1e-5f);
}

// Before: an 8-bit BMP or TGA (older exporters' textures: 3ds Max, the Blender 2.7 die of
// docs/obj-assets.md) declares no colour space and was read as linear: mid-grey 128 came out
// 0.502 instead of 0.216, every such texture rendered too bright.
TEST_F(IoTest, UntaggedEightBitFilesAreSrgb) {
    for (const char* name : {"grey.bmp", "grey.tga"}) {
        auto out = OIIO::ImageOutput::create(path(name).string());
        ASSERT_TRUE(out) << name;
        const std::vector<unsigned char> pixels(4 * 4 * 3, 128);
        ASSERT_TRUE(
            out->open(path(name).string(), OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::UINT8)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, pixels.data()));
        out->close();
        EXPECT_NEAR(readImage(path(name)).data()[0], srgbDecode(128.0f / 255.0f), 1e-6f) << name;
        EXPECT_NEAR(readImage(path(name), false).data()[0], 128.0f / 255.0f, 1e-6f) << name;
    }
}
