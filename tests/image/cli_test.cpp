// glint-image end to end: runs the built binary (path from tests/image/cli.cmake) and checks exit
// codes, the one-line error format and the --json output.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"

using namespace glint;
namespace fs = std::filesystem;

namespace {

struct CliRun {
    int code = -1;
    std::string out;
    std::string err;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string quote(const std::string& s) {
    return "'" + s + "'";
}

class CliTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::path(::testing::TempDir()) /
                (std::string("glint_cli_") + info->name() + "_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    /// Runs glint-image with `args` (already shell-quoted where needed), with the environment
    /// assignments `env` ("NAME=value …") when given.
    CliRun run(const std::string& args, const std::string& env = "") const {
        const std::string out = path("stdout.txt"), err = path("stderr.txt");
        const std::string cmd = (env.empty() ? "" : env + " ") + quote(GLINT_IMAGE_CLI) + " " +
                                args + " >" + quote(out) + " 2>" + quote(err);
        const int status = std::system(cmd.c_str());
        CliRun r;
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(out);
        r.err = slurp(err);
        fs::remove(out);
        fs::remove(err);
        return r;
    }

    /// Expects exit code 2 and exactly one stderr line starting "glint-image: <prefix>".
    void expectBadInput(const std::string& args, const std::string& prefix) const {
        const CliRun r = run(args);
        EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
        EXPECT_EQ(r.err.rfind("glint-image: " + prefix, 0), 0u) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_TRUE(r.out.empty()) << r.out;
    }

    /// A 16x12 frame of constant colour `value` with an albedo layer.
    std::string writeFrame(const std::string& name, float value, int w = 16, int h = 12) const {
        FrameBuffers frame(w, h);
        frame.color().fill(value);
        frame.ensure(Layer::Albedo).fill(0.5f);
        Image& depth = frame.ensure(Layer::Depth);
        for (int x = 0; x < w; ++x) depth(x, 0, 0) = float(x);
        frame.metadata().spp = 4;
        frame.metadata().integrator = "path";
        writeExr(frame, path(name));
        return path(name);
    }

    fs::path m_dir;
};

nlohmann::json parseOneObject(const std::string& text) {
    // parse() rejects trailing content, so this also checks there is exactly one JSON value.
    nlohmann::json j = nlohmann::json::parse(text);
    EXPECT_TRUE(j.is_object());
    return j;
}

}  // namespace

TEST_F(CliTest, InfoJsonListsLayersMetadataAndNonFinite) {
    FrameBuffers frame(5, 4);
    frame.color().fill(0.2f);
    frame.color()(1, 1, 0) = std::numeric_limits<float>::quiet_NaN();
    frame.color()(1, 1, 2) = std::numeric_limits<float>::infinity();
    frame.color()(3, 2, 1) = -std::numeric_limits<float>::infinity();
    frame.ensure(Layer::Normal);
    frame.metadata().spp = 32;
    frame.metadata().seed = 7;
    frame.metadata().extra["camera"] = "main";
    writeExr(frame, path("a.exr"));

    const CliRun r = run("info " + quote(path("a.exr")) + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(r.err.empty());
    const nlohmann::json j = parseOneObject(r.out);
    EXPECT_EQ(j["width"], 5);
    EXPECT_EQ(j["height"], 4);
    EXPECT_EQ(j["source"], "glint");
    ASSERT_EQ(j["layers"].size(), 2u);
    EXPECT_EQ(j["layers"][0]["name"], "color");
    EXPECT_EQ(j["layers"][0]["nonFinitePixels"], 2);  // two pixels, three bad values
    EXPECT_EQ(j["layers"][1]["name"], "normal");
    EXPECT_EQ(j["layers"][1]["channels"][2], "normal.Z");
    EXPECT_EQ(j["layers"][1]["nonFinitePixels"], 0);
    EXPECT_EQ(j["metadata"]["spp"], 32);
    EXPECT_EQ(j["metadata"]["seed"], 7);
    EXPECT_EQ(j["metadata"]["extra"]["camera"], "main");

    const CliRun text = run("info " + quote(path("a.exr")));
    EXPECT_EQ(text.code, 0);
    EXPECT_NE(text.out.find("5x4"), std::string::npos);
    EXPECT_NE(text.out.find("normal.X,normal.Y,normal.Z"), std::string::npos);
}

TEST_F(CliTest, InfoJsonSurvivesAttributesThatAreNotUtf8) {
    // Other tools may write Latin-1 strings; JSON output replaces the invalid bytes (U+FFFD)
    // instead of failing.
    FrameBuffers frame(4, 4);
    frame.metadata().extra["artist"] = "Ren\xe9";
    writeExr(frame, path("latin1.exr"));
    const CliRun r = run("info " + quote(path("latin1.exr")) + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = parseOneObject(r.out);
    EXPECT_EQ(j["metadata"]["extra"]["artist"], "Ren\xef\xbf\xbd");
}

TEST_F(CliTest, DiffPrintsMetricAndNonFiniteCount) {
    const std::string ref = writeFrame("ref.exr", 0.5f);
    FrameBuffers noisy(16, 12);
    noisy.color().fill(0.6f);  // constant offset 0.1: MSE = 0.01
    noisy.color()(0, 0, 1) = std::numeric_limits<float>::quiet_NaN();
    writeExr(noisy, path("offset.exr"));

    const CliRun r = run("diff " + quote(path("offset.exr")) + " --reference " + quote(ref) +
                         " --metric mse --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = parseOneObject(r.out);
    EXPECT_EQ(j["metric"], "mse");
    EXPECT_NEAR(j["value"].get<double>(), 0.01, 1e-6);
    EXPECT_EQ(j["nonFinitePixels"], 1);
    EXPECT_EQ(j["pixels"], 192);
    EXPECT_EQ(j["nonFiniteTreatment"], "excluded");
    EXPECT_TRUE(j["crop"].is_null());

    // A crop restricts the pixel count; identical images give PSNR +inf, reported as null.
    const CliRun c = run("diff " + quote(ref) + " --reference " + quote(ref) +
                         " --metric psnr --crop 2,6,1,4 --json");
    ASSERT_EQ(c.code, 0) << c.err;
    const nlohmann::json k = parseOneObject(c.out);
    EXPECT_EQ(k["pixels"], 12);
    EXPECT_TRUE(k["value"].is_null());
    EXPECT_EQ(k["finite"], false);
    EXPECT_EQ(k["crop"], nlohmann::json({2, 6, 1, 4}));

    const CliRun s = run("diff " + quote(ref) + " --reference " + quote(ref) + " --metric ssim");
    ASSERT_EQ(s.code, 0) << s.err;
    EXPECT_EQ(s.out.rfind("ssim 1\n", 0), 0u) << s.out;
    EXPECT_NE(s.out.find("0 non-finite pixels"), std::string::npos);
}

TEST_F(CliTest, BadInputExitsTwoWithOneLine) {
    const std::string ref = writeFrame("ref.exr", 0.5f);
    const std::string small = writeFrame("small.exr", 0.5f, 8, 8);
    const std::string missing = path("missing.exr");
    expectBadInput("info " + quote(missing), missing + ": open: ");
    std::ofstream(path("text.exr")) << "not an image";
    expectBadInput("info " + quote(path("text.exr")), path("text.exr") + ": open: ");

    fs::copy_file(ref, path("cut.exr"));
    fs::resize_file(path("cut.exr"), fs::file_size(ref) / 2);
    expectBadInput("info " + quote(path("cut.exr")), path("cut.exr") + ": ");

    writeImage(Image(4, 4, 1, 0.5f), path("grey.exr"));  // channel Y only
    expectBadInput("info " + quote(path("grey.exr")), path("grey.exr") + ": channels: ");

    const std::string diff = "diff " + quote(ref) + " --reference ";
    expectBadInput(diff + quote(small) + " --metric mse", small + ": size: ");
    expectBadInput(diff + quote(missing) + " --metric mse", missing + ": open: ");
    expectBadInput(diff + quote(ref) + " --metric mse --crop 0,17,0,4", ref + ": --crop: ");
    expectBadInput(diff + quote(ref) + " --metric mse --crop 5,5,0,4", ref + ": --crop: ");
    expectBadInput(diff + quote(ref) + " --metric mse --crop 1,2,3", "--crop: ");
    expectBadInput(diff + quote(ref) + " --metric nope", "--metric: ");
    // Errors of the metric itself name the image too (SSIM needs an 11x11 window).
    expectBadInput(diff + quote(ref) + " --metric ssim --crop 0,8,0,8", ref + ": ssim: ");
    expectBadInput("diff " + quote(ref) + " --metric mse", "command line: ");
    expectBadInput("frobnicate", "command line: ");

    expectBadInput("convert " + quote(ref) + " " + quote(path("o.png")) + " --false-color 0,1",
                   ref + ": --false-color: ");
    expectBadInput("convert " + quote(ref) + " " + quote(path("o.png")) + " --layer position",
                   ref + ": --layer: ");
    expectBadInput("convert " + quote(ref) + " " + quote(path("o.jpg")), "OUT: cannot write");
    // A false-colour range is refused for the reason that holds (not "lo < hi" when lo < hi).
    const std::string convert = "convert " + quote(ref) + " " + quote(path("o.png"));
    const std::pair<const char*, const char*> ranges[] = {
        {"1,0", "--false-color: expected lo < hi"},
        {"1,x", "--false-color: expected lo,hi (two numbers)"},
        {"0,inf", "--false-color: expected two finite numbers"},
        {"-3e38,3e38", "--false-color: the range must fit a float"},
        {"1e40,1e41", "--false-color: the range must fit a float"},
        {"1,1.00000001", "--false-color: lo and hi are the same number in float precision"},
    };
    for (const auto& [range, message] : ranges)
        expectBadInput(convert + " --layer depth --false-color " + range, message);
    // Tiny but distinct in float: shown.
    EXPECT_EQ(run(convert + " --layer depth --false-color 1e-30,2e-30").code, 0);
    fs::remove(path("o.png"));
    EXPECT_FALSE(fs::exists(path("o.png")));
    EXPECT_FALSE(fs::exists(path("o.jpg")));
}

// EXRs are read and written through OpenEXR, PNGs through libpng, JPEGs read through libjpeg;
// OpenImageIO (some 260 libraries, 0.4 s to load) comes in a module loaded by the first image of
// another format. The dynamic loader's own log (LD_DEBUG=files) names every library the process
// opens.
TEST_F(CliTest, ExrPngAndJpegCommandsNeverLoadOpenImageIo) {
    const std::string a = writeFrame("a.exr", 0.5f), b = writeFrame("b.exr", 0.25f);
    auto loads = [](const CliRun& r, const std::string& library) {
        return r.err.find(library) != std::string::npos;
    };
    writeImage(Image(4, 3, 3, 0.5f), path("j.jpg"));  // through the module, in this process
    for (const std::string& args :
         {"info " + quote(a), "diff " + quote(a) + " --reference " + quote(b) + " --metric mse",
          "convert " + quote(a) + " " + quote(path("c.exr")),
          "convert " + quote(a) + " " + quote(path("a.png")), "info " + quote(path("a.png")),
          "info " + quote(path("j.jpg"))}) {
        const CliRun r = run(args, "LD_DEBUG=files");
        EXPECT_NE(r.code, -1) << args;
        EXPECT_TRUE(loads(r, "libOpenEXR")) << args << "\n" << r.err;  // the log is there
        EXPECT_FALSE(loads(r, "libOpenImageIO")) << args;
        EXPECT_FALSE(loads(r, "libglint_image_formats")) << args;
    }
    // A TIFF loads the module, and the module OpenImageIO.
    writeImage(Image(4, 3, 3, 0.5f), path("a.tif"));
    const CliRun tif = run("info " + quote(path("a.tif")), "LD_DEBUG=files");
    EXPECT_EQ(tif.code, 0);
    EXPECT_TRUE(loads(tif, "libglint_image_formats"));
    EXPECT_TRUE(loads(tif, "libOpenImageIO"));

    // A module the user names that is not there is one clear error, not a silent fallback.
    const std::string wrong = path("nowhere/libglint_image_formats.so");
    const CliRun r =
        run("info " + quote(path("a.tif")), "GLINT_IMAGE_FORMATS_MODULE=" + quote(wrong));
    EXPECT_NE(r.code, 0);
    EXPECT_EQ(r.err.rfind("glint-image: " + path("a.tif") +
                              ": open: cannot read or write formats "
                              "other than OpenEXR: GLINT_IMAGE_FORMATS_MODULE names " +
                              wrong,
                          0),
              0u)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // EXRs and PNGs need no module.
    EXPECT_EQ(run("info " + quote(a), "GLINT_IMAGE_FORMATS_MODULE=" + quote(wrong)).code, 0);
    EXPECT_EQ(
        run("info " + quote(path("a.png")), "GLINT_IMAGE_FORMATS_MODULE=" + quote(wrong)).code, 0);
}

TEST_F(CliTest, ConvertWritesDisplayPng) {
    const std::string in = writeFrame("in.exr", 0.25f);
    const CliRun r = run("convert " + quote(in) + " " + quote(path("out.png")) + " --exposure 1");
    ASSERT_EQ(r.code, 0) << r.err;
    auto png = OIIO::ImageInput::open(path("out.png"));
    ASSERT_TRUE(png);
    std::vector<unsigned char> px(16 * 12 * 3);
    ASSERT_TRUE(png->read_image(0, 0, 0, 3, OIIO::TypeUInt8, px.data()));
    EXPECT_EQ(px[0], 188);  // 0.25 · 2 = 0.5 → sRGB 0.7354 → 188
    png->close();

    // One channel in false colour: depth ramps 0..15 along the first row.
    const CliRun f = run("convert " + quote(in) + " " + quote(path("depth.png")) +
                         " --layer depth.Z --false-color 0,15");
    ASSERT_EQ(f.code, 0) << f.err;
    const Image d = readImage(path("depth.png"), false);
    ASSERT_EQ(d.channels(), 3);
    EXPECT_LT(d(0, 0, 1), 0.1f);   // low end of the ramp: dark
    EXPECT_GT(d(15, 0, 1), 0.8f);  // high end: bright yellow
}
