// glint-render as a user runs it: the built binary (next to this test binary) on a tiny Cornell
// box. Checks the summary and --json output, --reference metrics, determinism across --threads,
// and that bad input exits 2 with a last stderr line naming the file or flag and writes nothing.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "glint/image/io.h"
#include "glint/render/asset_formats.h"
#include "scene_cli_fixture.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

std::string lastLine(const std::string& text) {
    std::string t = text;
    while (!t.empty() && t.back() == '\n') t.pop_back();
    const std::size_t nl = t.rfind('\n');
    return nl == std::string::npos ? t : t.substr(nl + 1);
}

using glint::testing::RunResult;

class RenderCli : public glint::testing::SceneCliFixture {
  protected:
    RenderCli() : SceneCliFixture("glint-render", {24, 24, 8}) {}
};

TEST_F(RenderCli, TheHelpListsTheExtensionOfEveryAssetFormat) {
    const RunResult r = run("--help");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    ASSERT_FALSE(assetExtensions().empty());
    for (const std::string& ext : assetExtensions())
        EXPECT_NE(r.out.find(ext), std::string::npos) << ext << " in\n" << r.out;
}

TEST_F(RenderCli, JsonSummaryAndLayeredOutput) {
    const RunResult r =
        run(path("scene.json") + " --spp 4 --seed 3 --out " + path("a.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);  // exactly one JSON value
    EXPECT_GT(j["samplesPerSecond"].get<double>(), 0.0);
    EXPECT_GT(j["raysPerSecond"].get<double>(), 0.0);
    EXPECT_EQ(j["nonFiniteSamples"], 0);
    EXPECT_EQ(j["samples"], 24 * 24 * 4);
    const FrameBuffers frame = readExr(path("a.exr"));
    EXPECT_EQ(frame.width(), 24);
    EXPECT_EQ(frame.metadata().spp, 4);
    EXPECT_EQ(frame.metadata().seed, 3u);
    for (Layer l :
         {Layer::Variance, Layer::Albedo, Layer::Normal, Layer::Depth, Layer::SampleCount})
        EXPECT_TRUE(frame.has(l)) << channelName(l, 0);
    EXPECT_EQ(frame.layer(Layer::SampleCount)(5, 7, 0), 4.0f);
    EXPECT_FALSE(frame.has(Layer::HalfColor));
    // halfBuffers=true: the half layers round-trip through the EXR.
    const RunResult h =
        run(path("scene.json") + " --spp 4 --set halfBuffers=true --out " + path("h.exr"));
    ASSERT_EQ(h.exitCode, 0) << h.err;
    const FrameBuffers halves = readExr(path("h.exr"));
    for (int l = 0; l < kLayerCount; ++l) {
        if (isHalfLayer(Layer(l))) {
            EXPECT_TRUE(halves.has(Layer(l))) << layerDisplayName(Layer(l));
        }
    }
    EXPECT_EQ(halves.layer(Layer::HalfSampleCount)(5, 7, 0), 2.0f);
    EXPECT_EQ(halves.metadata().extra.at("halfBuffers"), "true");
}

TEST_F(RenderCli, ReferenceMetricsAndThreadIndependence) {
    ASSERT_EQ(run(path("scene.json") + " --spp 4 --threads 1 --out " + path("t1.exr")).exitCode, 0);
    const RunResult r = run(path("scene.json") + " --spp 4 --threads 2 --out " + path("t2.exr") +
                            " --reference " + path("t1.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    // Same seed, any thread count: identical pixels, so relMSE 0 and SSIM 1 exactly.
    EXPECT_EQ(j["relMse"].get<double>(), 0.0);
    EXPECT_EQ(j["ssim"].get<double>(), 1.0);
    test::expectSameFrames(readExr(path("t1.exr")), readExr(path("t2.exr")));
}

// OpenImageIO (some 260 libraries, 0.4 s to load) comes in the texture cache's module, which the
// first texture file of a format other than OpenEXR, PNG and JPEG loads (or a tiled EXR): a scene
// without one never opens it. The dynamic loader's own log (LD_DEBUG=files) names every library
// the process opens.
TEST_F(RenderCli, OnlyATextureOfAnotherFormatLoadsOpenImageIo) {
    auto loads = [](const RunResult& r, const char* library) {
        return r.err.find(library) != std::string::npos;
    };
    const RunResult plain =
        run("LD_DEBUG=files", path("scene.json") + " --spp 1 --out " + path("plain.exr"));
    ASSERT_EQ(plain.exitCode, 0) << lastLine(plain.err);
    EXPECT_TRUE(loads(plain, "libembree3"));  // the log is there
    EXPECT_FALSE(loads(plain, "libOpenImageIO"));
    EXPECT_FALSE(loads(plain, "libglint_textures"));

    // The same box with a texture on its white walls.
    const std::string text = glint::testing::slurp(m_dir / "scene.json");
    auto textured = [&](const std::string& texture) {
        writeImage(Image(4, 4, 3, 0.5f), path(texture));
        const std::string scene = path(texture + ".json");
        std::ofstream(scene) << text.substr(0, text.size() - 1)
                             << R"(, "materials": {"white": {"type": "diffuse", "texture": ")" +
                                    texture + R"("}}})";
        return scene;
    };
    for (const char* texture : {"wall.png", "wall.jpg", "wall.exr"}) {
        const RunResult r = run("LD_DEBUG=files", textured(texture) + " --spp 1 --out " +
                                                      path(std::string(texture) + ".exr"));
        ASSERT_EQ(r.exitCode, 0) << lastLine(r.err);
        EXPECT_FALSE(loads(r, "libglint_textures")) << texture;
        EXPECT_FALSE(loads(r, "libOpenImageIO")) << texture;
    }
    const std::string tiff = textured("wall.tif");
    const RunResult r = run("LD_DEBUG=files", tiff + " --spp 1 --out " + path("tif.exr"));
    ASSERT_EQ(r.exitCode, 0) << lastLine(r.err);
    EXPECT_TRUE(loads(r, "libglint_textures"));
    EXPECT_TRUE(loads(r, "libOpenImageIO"));

    // A texture module the user names that is not there: one error naming the scene.
    const std::string wrong = path("nowhere/libglint_textures.so");
    const RunResult bad =
        run("GLINT_TEXTURES_MODULE=" + wrong, tiff + " --spp 1 --out " + path("no.exr"));
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(lastLine(bad.err).find(tiff + ": "), std::string::npos) << bad.err;
    EXPECT_NE(
        lastLine(bad.err).find("cannot read texture files: GLINT_TEXTURES_MODULE names " + wrong),
        std::string::npos)
        << bad.err;
    EXPECT_FALSE(fs::exists(path("no.exr")));
    // A scene without such texture files needs no module.
    EXPECT_EQ(run("GLINT_TEXTURES_MODULE=" + wrong,
                  path("wall.png.json") + " --spp 1 --out " + path("plain2.exr"))
                  .exitCode,
              0);
}

TEST_F(RenderCli, BadInputExitsTwoNamingTheProblemAndWritesNothing) {
    std::ofstream(path("broken.json")) << "{\"film\": {\"width\": 8,}\n";
    // The MIS heuristic and the sampler are the scene's (glint-render lost --mis and --sampler).
    const std::string text = glint::testing::slurp(m_dir / "scene.json");
    const std::size_t render = text.find("\"render\": {") + 11;
    std::ofstream(path("mis.json"))
        << text.substr(0, render) + "\"mis\": \"bogus\", " + text.substr(render);
    std::ofstream(path("stratified.json"))
        << text.substr(0, render) + "\"sampler\": \"stratified\", " + text.substr(render);
    writeExr(FrameBuffers(8, 8), path("small.exr"));
    const std::string scene = path("scene.json"), out = path("bad.exr");
    struct Case {
        std::string args, mention;
    };
    const Case cases[] = {
        {path("nope.json") + " --spp 4 --out " + out, "nope.json"},
        {path("broken.json") + " --spp 4 --out " + out, "line 1"},
        {scene + " --spp -3 --out " + out, "--spp"},
        {scene + " --spp 4 --threads -1 --out " + out, "--threads"},
        {scene + " --spp 4 --set maxDepth=0 --out " + out, "--set maxDepth"},
        {path("mis.json") + " --spp 4 --out " + out, "mis"},
        {path("stratified.json") + " --spp 4 --set halfBuffers=true --out " + out,
         "--set halfBuffers"},
        {scene + " --set integrator=mlt --set mltChains=many --out " + out, "--set mltChains"},
        {scene + " --set integrator=mlt --set nosuch=1 --out " + out, "--set"},
        {scene + " --set integrator=mlt --set mltChains --out " + out, "--set"},
        {scene + " --set integrator=mlt --set mltChains=30 --set mltGroups=4 --out " + out,
         "--set"},
        {scene + " --spp 4 --set halfBuffers=true --set integrator=mlt --out " + out,
         "--set halfBuffers"},
        {scene + " --spp 4 --reference " + path("small.exr") + " --out " + out, "small.exr"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        const std::string line = lastLine(r.err);
        EXPECT_EQ(line.rfind("glint-render: ", 0), 0u) << line;
        EXPECT_NE(line.find(c.mention), std::string::npos) << c.args << "\n" << line;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
}

TEST_F(RenderCli, MetropolisParametersAreSetByName) {
    const RunResult r =
        run(path("scene.json") +
            " --spp 4 --set integrator=mlt --set mltChains=32 --set mltGroups=4 "
            "--set mltBootstrap=2000 --set mltFeatureSpp=2 --set mltLarge=0.5 --json --out " +
            path("mlt.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["mlt"]["chains"], 32);
    EXPECT_EQ(j["mlt"]["groups"], 4);
    EXPECT_EQ(j["mlt"]["bootstrap"], 2000);
    EXPECT_EQ(j["mlt"]["featureSpp"], 2);
}

TEST_F(RenderCli, AdaptiveSamplingIsSetByNameAndSteeredByAnImportanceMap) {
    // --set adaptive=true with a threshold no pixel reaches: every pixel takes spp; a one-channel
    // map of weight 0 on the left half keeps those pixels at minSpp.
    Image weights(24, 24, 1, 1.0f);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 12; ++x) weights(x, y, 0) = 0.0f;
    writeImage(weights, path("w.exr"));
    const RunResult r = run(path("scene.json") +
                            " --spp 16 --set minSpp=4 --set noiseThreshold=1e-9 --importance " +
                            path("w.exr") + " --json --out " + path("ad.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const FrameBuffers f = readExr(path("ad.exr"));
    EXPECT_EQ(f.metadata().extra.at("adaptive"), "true");
    EXPECT_EQ(f.layer(Layer::SampleCount)(3, 10, 0), 4.0f);
    EXPECT_EQ(f.layer(Layer::SampleCount)(20, 10, 0), 16.0f);
    EXPECT_DOUBLE_EQ(nlohmann::json::parse(r.out)["meanSpp"].get<double>(), 10.0);
    // The same bits at 1 and 2 threads.
    for (int t : {1, 2})
        ASSERT_EQ(run(path("scene.json") + " --spp 16 --set adaptive=true --set minSpp=4 " +
                      "--set noiseThreshold=0.05 --threads " + std::to_string(t) + " --out " +
                      path("t" + std::to_string(t) + ".exr"))
                      .exitCode,
                  0);
    const FrameBuffers one = readExr(path("t1.exr")), two = readExr(path("t2.exr"));
    for (Layer l : {Layer::Color, Layer::Variance, Layer::SampleCount})
        EXPECT_TRUE(std::equal(one.layer(l).data().begin(), one.layer(l).data().end(),
                               two.layer(l).data().begin()))
            << layerDisplayName(l);
}

TEST_F(RenderCli, BadAdaptiveInputExitsTwoWithOneLineAndWritesNothing) {
    const std::string scene = path("scene.json"), out = path("bad.exr");
    auto map = [&](const std::string& name, int w, int h, float fill, float at34 = 1.0f) {
        Image m(w, h, 1, fill);
        if (w > 4 && h > 4) m(3, 4, 0) = at34;
        writeImage(m, path(name));
        return path(name);
    };
    struct Case {
        std::string args, mention;
    };
    const Case cases[] = {
        {scene + " --set adaptive=true --set noiseThreshold=0 --out " + out,
         "--set noiseThreshold: expected a number in [1e-09, 1e+06]"},
        {scene + " --set adaptive=true --set noiseThreshold=-0.1 --out " + out,
         "--set noiseThreshold"},
        {scene + " --set adaptive=true --set noiseThreshold=nan --out " + out,
         "--set noiseThreshold"},
        {scene + " --set adaptive=true --set noiseThreshold=2e6 --out " + out,
         "--set noiseThreshold"},
        {scene + " --spp 4 --set adaptive=true --set minSpp=8 --out " + out,
         "--spp: spp (4, the most samples an adaptive render gives a pixel) is below minSpp (8"},
        {scene + " --importance " + map("small.exr", 8, 8, 1.0f) + " --out " + out,
         "small.exr: the importance map is 8x8, the scene renders 24x24"},
        {scene + " --importance " + map("nan.exr", 24, 24, 1.0f, std::nanf("")) + " --out " + out,
         "nan.exr: pixel (3, 4): importance weight nan; expected a finite weight >= 0"},
        {scene + " --importance " + map("neg.exr", 24, 24, 1.0f, -2.0f) + " --out " + out,
         "neg.exr: pixel (3, 4): importance weight -2"},
        {scene + " --importance " + map("zero.exr", 24, 24, 0.0f, 0.0f) + " --out " + out,
         "zero.exr: every weight is 0"},
        {scene + " --importance " + path("missing.exr") + " --out " + out, "missing.exr"},
        {scene + " --set adaptive=true --shard 0/2 --out " + out, "--shard"},
        {scene + " --set adaptive=true --set integrator=mlt --out " + out, "path integrator only"},
        {scene + " --time-limit 1e9 --out " + out,
         "timeLimit must be a number of seconds in [0, 1e7], got 1e+09"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        const std::string line = lastLine(r.err);
        EXPECT_EQ(line.rfind("glint-render: ", 0), 0u) << line;
        EXPECT_NE(line.find(c.mention), std::string::npos) << c.args << "\n" << line;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
}

TEST_F(RenderCli, ATimeLimitShorterThanOnePassSaysSoAndWritesThatPass) {
    const RunResult r =
        run(path("scene.json") + " --time-limit 1e-9 --set adaptive=true --out " + path("t.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("the time limit (1e-09 s) is shorter than one pass"), std::string::npos)
        << r.err;
    EXPECT_EQ(readExr(path("t.exr")).layer(Layer::SampleCount)(5, 5, 0), 1.0f);
}

TEST_F(RenderCli, ARenderOverTheMemoryLimitIsRefusedAndWritesNothing) {
    // 24×24 needs about 220 KiB (384 bytes a pixel); a 100 KiB budget refuses it, from the
    // option or from GLINT_MEMORY_LIMIT, before rendering.
    RunResult r = run(path("scene.json") + " --memory-limit 100K --out " + path("m.exr"));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(lastLine(r.err).find("/film: a 24x24 path render needs 216 KiB but only 100 KiB is "
                                   "allowed (memory limit)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("m.exr")));
    r = run("GLINT_MEMORY_LIMIT=100K", path("scene.json") + " --out " + path("m.exr"));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(lastLine(r.err).find("is available on this machine"), std::string::npos) << r.err;
    r = run(path("scene.json") + " --memory-limit lots --out " + path("m.exr"));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(lastLine(r.err).find("--memory-limit: 'lots' is not a memory size"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(run(path("scene.json") + " --memory-limit 1M --out " + path("m.exr")).exitCode, 0);
}

}  // namespace
}  // namespace glint::render
