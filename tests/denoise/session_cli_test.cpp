// glint-denoise paint | composite end to end, good and bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "glint/denoise/session.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

class PaintCli : public glint::testing::CliFixture {
  protected:
    PaintCli() : CliFixture("glint-denoise") {}
    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        writeExr(testing::syntheticFrame(48, 40, 0.1f, 1), m_dir / "a.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.1f, 2), m_dir / "b.exr");
        writeExr(testing::syntheticFrame(48, 40, 0.0f), m_dir / "ref.exr");
        writeExr(testing::syntheticFrame(20, 20, 0.1f), m_dir / "small.exr");
        script("good.json", R"({"layers": [{"filter": "gaussian", "params": {"sigma": 2}},
                   {"filter": "guided", "params": {"guide": "normal"}}],
           "edits": [{"weights": {"layer": 0, "value": 1}},
                     {"stroke": {"layer": 1, "size": 12, "softness": 0.5,
                                 "points": [[10, 10], [14, 12], [18, 14]]}},
                     {"fill": {"layer": 1, "mode": "add", "wand": {"seed": [40, 30], "color": -1}}},
                     {"stroke": {"layer": 1, "size": 8, "mode": "subtract", "points": [[2, 38]]}},
                     {"diffuse": {"layers": [1]}}]})");
    }
    void script(const std::string& name, const std::string& text) {
        std::ofstream(m_dir / name) << text;
    }
};

TEST_F(PaintCli, PaintSavesASessionThatCompositeAppliesToANewRender) {
    RunResult r = run("paint " + path("a.exr") + " --script " + path("good.json") + " --save " +
                      path("s.glint-session.json") + " --out " + path("a-out.exr") + " --png " +
                      path("a-out.png") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["layers"], 2);
    const Session s = Session::load(path("s.glint-session.json"));
    ASSERT_EQ(s.layerCount(), 2u);
    EXPECT_EQ(s.layer(1).params.at("guide"), 2.0);
    EXPECT_EQ(readExr(path("a-out.exr")).color().data()[0], s.composite().data()[0]);
    EXPECT_TRUE(fs::exists(path("a-out.png")));

    r = run("composite " + path("s.glint-session.json") + " --input " + path("b.exr") + " --out " +
            path("b-out.exr") + " --reference " + path("ref.exr") + " --json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_GT(j["metrics"]["ssim"].get<double>(), j["metricsInput"]["ssim"].get<double>());
    // The same painting on the new render, computed through the library.
    Session again = Session::load(path("s.glint-session.json"));
    again.reapply(readExr(path("b.exr")));
    const Image out = readExr(path("b-out.exr")).color();
    for (std::size_t i = 0; i < out.data().size(); ++i)
        ASSERT_EQ(out.data()[i], again.composite().data()[i]) << i;
}

TEST_F(PaintCli, BadScriptsAndRendersExitTwoNamingTheFileAndPlace) {
    ASSERT_EQ(run("paint " + path("a.exr") + " --script " + path("good.json") + " --save " +
                  path("s.glint-session.json"))
                  .exitCode,
              0);
    script("filter.json", R"({"layers": [{"filter": "gausian"}]})");
    script("param.json", R"({"layers": [{"filter": "guided", "params": {"guide": "albedos"}}]})");
    script("layer.json", R"({"layers": [{"filter": "gaussian"}],
                             "edits": [{"weights": {"layer": 3, "value": 1}}]})");
    script("edit.json", R"({"layers": [{"filter": "gaussian"}], "edits": [{"smudge": {}}]})");
    script("brush.json", R"({"layers": [{"filter": "gaussian"}],
                             "edits": [{"stroke": {"layer": 0, "size": -4, "points": [[1, 1]]}}]})");
    script("diffuse.json", R"({"layers": [{"filter": "gaussian"}],
                               "edits": [{"diffuse": {"layers": [0]}}]})");
    script("broken.json", R"({"layers": [)");
    struct Case {
        std::string args, mention;
    };
    const std::string in = path("a.exr"), save = " --save " + path("x.glint-session.json");
    const Case cases[] = {
        {"paint " + in + " --script " + path("filter.json") + save, "/layers/0/filter"},
        {"paint " + in + " --script " + path("param.json") + save, "/layers/0/params/guide"},
        {"paint " + in + " --script " + path("layer.json") + save, "/edits/0/weights/layer"},
        {"paint " + in + " --script " + path("edit.json") + save, "smudge"},
        {"paint " + in + " --script " + path("brush.json") + save, "/edits/0/stroke"},
        {"paint " + in + " --script " + path("diffuse.json") + save, "painted"},
        {"paint " + in + " --script " + path("broken.json") + save, "broken.json"},
        {"paint " + in + " --script " + path("good.json") + " --save " + path("x.txt"), ".json"},
        {"paint " + in + " --script " + path("good.json") + save + " --out " + path("o.png"),
         ".exr"},
        {"composite " + path("s.glint-session.json") + " --input " + path("small.exr") + " --out " +
             path("o.exr"),
         "small.exr"},
        {"composite " + path("missing.glint-session.json") + " --input " + in + " --out " +
             path("o.exr"),
         "missing.glint-session.json"},
    };
    for (const Case& c : cases) {
        const RunResult r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.mention), std::string::npos) << c.args << "\n" << r.err;
    }
    EXPECT_FALSE(fs::exists(path("x.glint-session.json")));
    EXPECT_FALSE(fs::exists(path("x.glint-session")));
    EXPECT_FALSE(fs::exists(path("o.exr")));
}

}  // namespace
}  // namespace glint::denoise
