// The external filter: a stand-in program (external_denoiser_stub) in each of its modes, the
// list-of-strings parameter that names it, and the rule that a file never runs a program by
// itself (docs/external-denoiser.md).
#include <gtest/gtest.h>

#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_fixture.h"
#include "external_stub.h"
#include "filters/external_files.h"
#include "glint/denoise/external.h"
#include "glint/denoise/paint_script.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

using testing::stubParams;
using testing::stubPath;

class ExternalFilter : public testing::ExternalSandbox {
  protected:
    // The message of the error applyFilter throws for `params` (fails the test without one).
    std::string failure(const ParamValues& params, ErrorKind kind = ErrorKind::Io) {
        try {
            applyFilter(findFilter("external"), testing::syntheticFrame(8, 6), params);
        } catch (const Error& e) {
            EXPECT_EQ(int(e.kind()), int(kind)) << e.what();
            return e.what();
        }
        ADD_FAILURE() << "no error";
        return {};
    }
};

TEST_F(ExternalFilter, ReadsBackWhatTheProgramWritesInEitherFormatAndRemovesItsFolder) {
    const FrameBuffers frame = testing::syntheticFrame(9, 7);
    for (const std::string format : {"exr", "pfm"}) {
        const Image out = applyFilter(findFilter("external"), frame, stubParams("good", format));
        ASSERT_EQ(out.width(), 9);
        ASSERT_EQ(out.height(), 7);
        for (std::size_t i = 0; i < out.data().size(); ++i)
            ASSERT_EQ(out.data()[i], frame.color().data()[i] * 0.5f) << format << " at " << i;
        EXPECT_TRUE(temporaryFolderEmpty()) << format;
    }
}

TEST_F(ExternalFilter, ReturnsTheRegionOfTheWholeFrameResult) {
    const FrameBuffers frame = testing::syntheticFrame(9, 7);
    const Rect roi{2, 6, 1, 4};
    const Image out =
        applyFilter(findFilter("external"), frame, stubParams("good"), testing::inRegion(roi));
    ASSERT_EQ(out.width(), 4);
    ASSERT_EQ(out.height(), 3);
    EXPECT_EQ(out(1, 2, 0), frame.color()(3, 3, 0) * 0.5f);
}

TEST_F(ExternalFilter, NeverShowsTheProgramAMissingPixel) {
    FrameBuffers frame = testing::syntheticFrame(8, 6);
    frame.color()(3, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    frame.color()(0, 0, 0) = std::numeric_limits<float>::infinity();
    // The stub exits with code 5 when its input holds a non-finite value.
    const Image out = applyFilter(findFilter("external"), frame, stubParams("good", "pfm"));
    EXPECT_EQ(out.countNonFinite(), 0u);
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, ANonZeroExitNamesTheCommandTheCodeAndTheLastStderrLine) {
    const std::string what = failure(stubParams("exit"));
    EXPECT_NE(what.find(stubPath().string()), std::string::npos) << what;
    EXPECT_NE(what.find("code 3"), std::string::npos) << what;
    EXPECT_NE(what.find("the model file is damaged"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, ADeathBySignalIsNamed) {
    const std::string what = failure(stubParams("abort"));
    EXPECT_NE(what.find("signal 6"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, AResultOfAnotherSizeIsRefused) {
    const std::string what = failure(stubParams("size", "pfm"), ErrorKind::Format);
    EXPECT_NE(what.find("9x6"), std::string::npos) << what;
    EXPECT_NE(what.find("8x6"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, ANonFiniteResultIsRefused) {
    const std::string what = failure(stubParams("nan"), ErrorKind::Numeric);
    EXPECT_NE(what.find("NaN"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, AMissingResultIsNamed) {
    const std::string what = failure(stubParams("missing"));
    EXPECT_NE(what.find("without writing its output"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, AProgramPastItsTimeoutIsStopped) {
    const std::string what = failure(stubParams("sleep", "exr", {}, 0.2));
    EXPECT_NE(what.find("timeout of 0.2 s"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, TheProgressCallbackStopsTheProgram) {
    FilterOptions options;
    int calls = 0;
    options.progress = [&](double) { return ++calls < 3; };
    try {
        applyFilter(findFilter("external"), testing::syntheticFrame(8, 6), stubParams("sleep"),
                    options);
        ADD_FAILURE() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled) << e.what();
    }
    EXPECT_GE(calls, 3);
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, AMissingOrNonExecutableProgramIsNamed) {
    ParamValues params = stubParams("good");
    params.strings["command"][0] = (m_dir / "no-such-denoiser").string();
    allowCommand(params.strings["command"][0]);
    EXPECT_NE(failure(params).find("does not exist"), std::string::npos);
    std::ofstream(m_dir / "not-executable") << "#!/bin/sh\n";
    params.strings["command"][0] = (m_dir / "not-executable").string();
    allowCommand(params.strings["command"][0]);
    const std::string what = failure(params);
    EXPECT_NE(what.find("not an executable"), std::string::npos) << what;
    EXPECT_NE(what.find("not-executable"), std::string::npos) << what;
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, IsUnavailableUntilItsProgramIsAllowed) {
    const fs::path marker = m_dir / "ran";
    clearAllowedCommands();
    const std::string what =
        failure(stubParams("good", "exr", marker.string()), ErrorKind::InvalidArgument);
    EXPECT_NE(what.find("unavailable"), std::string::npos) << what;
    EXPECT_NE(what.find("--allow-command " + stubPath().string()), std::string::npos) << what;
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_TRUE(temporaryFolderEmpty());
    // A program not named by its full path is never allowed.
    ParamValues relative = stubParams("good");
    relative.strings["command"][0] = "bin/tool";
    EXPECT_NE(failure(relative, ErrorKind::InvalidArgument).find("full path"), std::string::npos);
    // A filter without a command is unavailable too, and so never joins a bank by default.
    EXPECT_FALSE(
        findFilter("external").unavailable(resolveParams(findFilter("external"), {})).empty());
    for (const Filter* f : defaultBankFilters()) EXPECT_NE(f->name(), "external");
}

TEST_F(ExternalFilter, TheWorkedExampleScriptBoxBlurs) {
    // docs/examples/external_box_denoiser.py runs through `#!/usr/bin/env python3`.
    if (std::system("python3 -c pass >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
    const std::string script = GLINT_SOURCE_DIR "/docs/examples/external_box_denoiser.py";
    allowCommand(script);
    ParamValues params{{"format", 1.0}};
    params.strings["command"] = {script, "{color}", "{output}", "1"};
    const FrameBuffers frame = testing::syntheticFrame(7, 5);
    const Image out = applyFilter(findFilter("external"), frame, params);
    // The 3×3 box, clipped at the border, computed here.
    const Image& in = frame.color();
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x)
            for (int c = 0; c < 3; ++c) {
                double sum = 0.0;
                int n = 0;
                for (int j = std::max(0, y - 1); j <= std::min(4, y + 1); ++j)
                    for (int i = std::max(0, x - 1); i <= std::min(6, x + 1); ++i, ++n)
                        sum += in(i, j, c);
                ASSERT_NEAR(out(x, y, c), sum / n, 1e-5) << x << "," << y << "," << c;
            }
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST(ExternalCommands, AreNamedByFullPathAndReadFromTheUsersFile) {
    clearAllowedCommands();
    EXPECT_THROW(allowCommand("relative/tool"), Error);
    const fs::path file =
        fs::temp_directory_path() / ("allowed-commands-" + std::to_string(::getpid()));
    std::ofstream(file) << "# mine\n/opt/oidn/bin/oidnDenoise\n\n/usr/local/bin/../bin/tool\n";
    allowCommandsFromFile(file);
    EXPECT_TRUE(commandAllowed("/opt/oidn/bin/oidnDenoise"));
    EXPECT_TRUE(commandAllowed("/usr/local/bin/tool"));
    EXPECT_FALSE(commandAllowed("/opt/oidn/bin/other"));
    std::ofstream(file) << "/ok\nbin/tool\n";
    try {
        allowCommandsFromFile(file);
        ADD_FAILURE() << "a relative path was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    }
    fs::remove(file);
    clearAllowedCommands();
}

TEST(StringsParameter, ParsesAJsonArrayOrOneStringAndIsCheckedByKind) {
    const Filter& f = findFilter("external");
    const ParamSpec& command = *findParam(f.params(), "command");
    ParamValues values;
    setParamFromText(command, R"(["/opt/bin/tool", "--in={color}", "{output}"])", values);
    EXPECT_EQ(values.strings.at("command"),
              (std::vector<std::string>{"/opt/bin/tool", "--in={color}", "{output}"}));
    EXPECT_EQ(formatParam(command, values), R"(["/opt/bin/tool","--in={color}","{output}"])");
    setParamFromText(command, "/opt/bin/tool", values);
    EXPECT_EQ(values.strings.at("command"), std::vector<std::string>{"/opt/bin/tool"});
    EXPECT_THROW(setParamFromText(command, "[1, 2]", values), Error);
    EXPECT_THROW(setParamFromText(command, "[\"unterminated", values), Error);
    // A list for a number, or a number other than 0 for a list, is refused.
    ParamValues wrong;
    wrong.strings["timeout"] = {"1"};
    EXPECT_THROW(resolveParams(f, wrong), Error);
    EXPECT_THROW(resolveParams(f, ParamValues{{"command", 2.0}}), Error);
    // Lists take part in equality (a bank's and a session's identity of a member).
    ParamValues a = resolveParams(f, values), b = a;
    b.strings["command"].push_back("x");
    EXPECT_NE(a, b);
    // The placeholders name the layers the filter needs.
    values.strings["command"] = {"/opt/bin/tool", "{color}", "--aux={albedo}", "{output}"};
    EXPECT_EQ(f.requiredLayers(resolveParams(f, values)), std::vector<Layer>{Layer::Albedo});
}

TEST(StringsParameter, IsSummarisedAsQuotedArgvShortenedPastItsWidth) {
    const Filter& f = findFilter("external");
    const ParamSpec& command = *findParam(f.params(), "command");
    ParamValues values = resolveParams(f, {});
    values.strings["command"] = {"/opt/bin/tool", "--in={color}", "my file", "it's"};
    EXPECT_EQ(paramSummary(command, values), R"([/opt/bin/tool --in={color} 'my file' 'it'\''s'])");
    // Too wide: the arguments' paths by their file names, the program's kept while it fits.
    values.strings["command"] = {"/usr/bin/python3",
                                 "/home/me/glint/docs/examples/external_box_denoiser.py", "{color}",
                                 "{output}", "2"};
    EXPECT_EQ(paramSummary(command, values),
              "[/usr/bin/python3 …/external_box_denoiser.py {color} {output} 2]");
    EXPECT_EQ(paramsSummary(f.params(), values),
              "command=[/usr/bin/python3 …/external_box_denoiser.py {color} {output} 2] "
              "format=exr timeout=600");
    // Still too wide: the tail is cut.
    values.strings["command"] = {"/opt/bin/tool"};
    for (int i = 0; i < 30; ++i) values.strings["command"].push_back("--flag" + std::to_string(i));
    const std::string cut = paramSummary(command, values);
    EXPECT_LE(cut.size(), 72u) << cut;
    EXPECT_EQ(cut.rfind("[/opt/bin/tool --flag0 --flag1 ", 0), 0u) << cut;
    EXPECT_EQ(cut.substr(cut.size() - 5), " …]") << cut;
    // Numbers and choices as formatParamValue writes them.
    const Filter& g = findFilter("gaussian");
    EXPECT_EQ(paramSummary(g.params()[0], resolveParams(g, {})),
              formatParamValue(g.params()[0], g.params()[0].defaultValue));
}

// ---- a file never runs a program by itself -----------------------------------------------------

// Saves a session over a small frame with one external layer (the stub writing `marker`),
// painted everywhere, and removes the marker its creation wrote.
fs::path saveExternalSession(const fs::path& dir, const fs::path& marker) {
    Session s(testing::syntheticFrame(16, 12));
    s.addLayer("external", stubParams("good", "exr", marker.string()));
    s.setWeights(0, Image(16, 12, 1, 1.0f));
    const fs::path file = dir / "ext.glint-session.json";
    s.save(file);
    writeExr(testing::syntheticFrame(16, 12), dir / "render.exr");
    fs::remove(marker);
    return file;
}

TEST_F(ExternalFilter, ASessionNamingAProgramOpensWithoutRunningItUnlessAllowed) {
    const fs::path marker = m_dir / "ran";
    const fs::path file = saveExternalSession(m_dir, marker);
    clearAllowedCommands();
    const Session closed = Session::load(file);
    EXPECT_FALSE(fs::exists(marker));
    ASSERT_EQ(closed.layerCount(), 1u);
    EXPECT_NE(closed.layer(0).unavailable.find("not allowed"), std::string::npos);
    EXPECT_NE(closed.layer(0).unavailable.find("--allow-command"), std::string::npos);
    EXPECT_EQ(closed.layer(0).params.strings.at("command")[0], stubPath().string());
    EXPECT_EQ(testing::maxAbsDiff(closed.composite(), closed.input().color()), 0.0);
    allowCommand(stubPath());
    const Session open = Session::load(file);
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_TRUE(open.layer(0).unavailable.empty());
    EXPECT_GT(testing::maxAbsDiff(open.composite(), open.input().color()), 0.0);
    EXPECT_TRUE(temporaryFolderEmpty());
}

// The studio allows a program while a session that names it is open, then re-applies its
// layers to the same render: the layer runs and is no longer marked unavailable.
TEST_F(ExternalFilter, AnUnavailableLayerRunsWhenReappliedOnceItsProgramIsAllowed) {
    const fs::path marker = m_dir / "ran";
    const fs::path file = saveExternalSession(m_dir, marker);
    clearAllowedCommands();
    Session s = Session::load(file);
    ASSERT_FALSE(s.layer(0).unavailable.empty());
    s.reapply(FrameBuffers(s.input()));
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_FALSE(s.layer(0).unavailable.empty());
    allowCommand(stubPath());
    s.reapply(FrameBuffers(s.input()));
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_TRUE(s.layer(0).unavailable.empty()) << s.layer(0).unavailable;
    EXPECT_GT(testing::maxAbsDiff(s.composite(), s.input().color()), 0.0);
    EXPECT_TRUE(temporaryFolderEmpty());
}

TEST_F(ExternalFilter, APaintScriptNamesTheProgramAsAnArrayAndRunsItOnlyWhenAllowed) {
    const fs::path marker = m_dir / "ran";
    const std::string text = R"({"layers": [{"filter": "external", "params": {"command": [")" +
                             stubPath().string() + R"(", "good", "pfm", "{color}", "{output}", ")" +
                             marker.string() + R"("], "format": "pfm", "timeout": 60}}],
                                  "edits": [{"weights": {"layer": 0, "value": 1}}]})";
    const PaintScript script = PaintScript::parse(text, "script.json");
    ASSERT_EQ(script.layers().size(), 1u);
    EXPECT_EQ(script.layers()[0].params.strings.at("command")[1], "good");
    clearAllowedCommands();
    Session refused(testing::syntheticFrame(8, 6));
    EXPECT_THROW(script.apply(refused), Error);
    EXPECT_FALSE(fs::exists(marker));
    allowCommand(stubPath());
    Session s(testing::syntheticFrame(8, 6));
    script.apply(s);
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_EQ(s.composite()(2, 3, 1), s.input().color()(2, 3, 1) * 0.5f);
    // A list of anything but strings is refused at its place.
    const std::string bad = R"({"layers": [{"filter": "external", "params": {"command": [1]}}]})";
    EXPECT_THROW(PaintScript::parse(bad, "bad.json"), Error);
    EXPECT_TRUE(temporaryFolderEmpty());
}

class ExternalCli : public glint::testing::CliFixture {
  protected:
    ExternalCli() : CliFixture("glint-denoise") {}
};

TEST_F(ExternalCli, CompositeLeavesOutAProgramNotAllowedAndRunsItWhenAllowed) {
    const fs::path dir = m_dir;
    const fs::path marker = dir / "ran";
    clearAllowedCommands();
    allowCommand(stubPath());
    const fs::path file = saveExternalSession(dir, marker);
    clearAllowedCommands();
    const std::string args = "composite " + file.string() + " --input " + path("render.exr") +
                             " --out " + path("out.exr");
    const glint::testing::RunResult closed = run("XDG_CONFIG_HOME=" + m_dir.string(), args);
    EXPECT_EQ(closed.exitCode, 0) << closed.err;
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_NE(closed.err.find("unavailable"), std::string::npos) << closed.err;
    EXPECT_NE(closed.err.find("--allow-command " + stubPath().string()), std::string::npos)
        << closed.err;
    const glint::testing::RunResult open =
        run("XDG_CONFIG_HOME=" + m_dir.string(), args + " --allow-command " + stubPath().string());
    EXPECT_EQ(open.exitCode, 0) << open.err;
    EXPECT_TRUE(fs::exists(marker));
    EXPECT_EQ(open.err.find("unavailable"), std::string::npos) << open.err;
    // The user's config file allows it as well.
    fs::remove(marker);
    fs::create_directories(m_dir / "glint");
    std::ofstream(m_dir / "glint" / "allowed-commands") << stubPath().string() << "\n";
    const glint::testing::RunResult listed = run("XDG_CONFIG_HOME=" + m_dir.string(), args);
    EXPECT_EQ(listed.exitCode, 0) << listed.err;
    EXPECT_TRUE(fs::exists(marker));
}

// The --param of apply running the stub in `mode` (on PFM files), creating `marker` if given.
std::string stubParamArgs(const std::string& mode, const std::string& marker = {}) {
    return "--param 'command=" + nlohmann::json(testing::stubCommand(mode, "pfm", marker)).dump() +
           "' --param format=pfm";
}

TEST_F(ExternalCli, ApplyRunsTheProgramItNamesOnceAllowedAndReportsItsFailureOnOneLine) {
    writeExr(testing::syntheticFrame(10, 8), m_dir / "in.exr");
    auto command = [&](const std::string& mode) {
        return stubParamArgs(mode).substr(std::string("--param ").size()) + " --allow-command " +
               stubPath().string();
    };
    const glint::testing::RunResult good =
        run("apply " + path("in.exr") + " --filter external --param " + command("good") +
            " --out " + path("out.exr") + " --json");
    ASSERT_EQ(good.exitCode, 0) << good.err;
    const FrameBuffers out = readExr(m_dir / "out.exr");
    EXPECT_EQ(out.color()(4, 3, 2), testing::syntheticFrame(10, 8).color()(4, 3, 2) * 0.5f);
    const nlohmann::json report = nlohmann::json::parse(good.out);
    EXPECT_EQ(report["params"]["command"][0], stubPath().string());
    const glint::testing::RunResult bad =
        run("apply " + path("in.exr") + " --filter external --param " + command("exit") +
            " --out " + path("bad.exr"));
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_NE(bad.err.find("code 3"), std::string::npos) << bad.err;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_FALSE(fs::exists(m_dir / "bad.exr"));
}

TEST_F(ExternalCli, ApplyRefusesAProgramNotAllowedOnOneLineAndRunsNothing) {
    writeExr(testing::syntheticFrame(10, 8), m_dir / "in.exr");
    const fs::path marker = m_dir / "ran";
    // Typing the command is not allowing it: --allow-command (or the user's file) does that.
    const glint::testing::RunResult refused =
        run("XDG_CONFIG_HOME=" + m_dir.string(), "apply " + path("in.exr") + " --filter external " +
                                                     stubParamArgs("good", marker.string()) +
                                                     " --out " + path("out.exr"));
    EXPECT_EQ(refused.exitCode, 2) << refused.err;
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    EXPECT_NE(refused.err.find("not allowed"), std::string::npos) << refused.err;
    EXPECT_NE(refused.err.find("--allow-command " + stubPath().string()), std::string::npos)
        << refused.err;
    EXPECT_FALSE(fs::exists(marker));
    EXPECT_FALSE(fs::exists(m_dir / "out.exr"));
}

TEST(ExchangeFiles, APfmIsReadBottomRowFirstAndAShortOneIsRefused) {
    const fs::path file =
        fs::temp_directory_path() / ("pfm-" + std::to_string(::getpid()) + ".pfm");
    {
        std::ofstream out(file, std::ios::binary);
        out << "PF\n2 1\n-1.0\n";
        const float px[6] = {1, 2, 3, 4, 5, 6};
        out.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    const Image image = detail::readExchangeImage(file, detail::ExchangeFormat::Pfm);
    EXPECT_EQ(image(1, 0, 2), 6.0f);
    {
        std::ofstream out(file, std::ios::binary);
        out << "PF\n2 2\n-1.0\n";
        const float px[6] = {1, 2, 3, 4, 5, 6};
        out.write(reinterpret_cast<const char*>(px), sizeof px);
    }
    EXPECT_THROW(detail::readExchangeImage(file, detail::ExchangeFormat::Pfm), Error);
    fs::remove(file);
}

}  // namespace
}  // namespace glint::denoise
