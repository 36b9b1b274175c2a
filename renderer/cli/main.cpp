// glint-render: renders a scene.json or a bare glTF asset to a layered EXR (docs/renderer.md,
// docs/assets.md).
#include <unistd.h>
#include <cctype>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <CLI/CLI.hpp>

#include <nlohmann/json.hpp>
#include "cli_boundary.h"

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"
#include "glint/image/metrics.h"
#include "glint/image/shard.h"
#include "glint/image/tev_client.h"
#include "glint/render/asset_formats.h"
#include "glint/render/importance_map.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings.h"
#include "glint/render/settings_codec.h"

namespace {

using glint::render::Settings;

struct Options {
    std::string scene, out, reference, memoryLimit;
    std::optional<std::string> camera;  // a glTF asset's camera, by name
    std::optional<int> threads;
    std::optional<std::string> shard;
    double timeLimit = 0.0;
    bool json = false;
    /// The named render settings given (--spp, --seed) as text, read
    /// strictly by the settings codec ("-1" must not wrap to a seed of 2^64 - 1).
    glint::render::SettingValues settings;
    /// --set: any named render setting, "name=value" each (scene.json's render keys).
    std::vector<std::string> set;
    std::string importance;  ///< --importance: the adaptive passes' per-pixel weights
    std::string display;     ///< --display HOST:PORT: each pass to a running tev
};

/// The named settings with a flag of their own (--spp, --seed); the others are set by
/// --set name=value or the scene's render block.
constexpr const char* kSettingFlags[] = {"spp", "seed"};

bool hasOwnFlag(const std::string& name) {
    for (const char* n : kSettingFlags)
        if (name == n) return true;
    return false;
}

/// The flag that sets the Settings field `field` (validate's place), else "options".
std::string flagOf(const std::string& field) {
    if (const glint::render::SettingSpec* spec = glint::render::findSetting(field))
        return hasOwnFlag(field) ? glint::render::settingFlag(*spec) : "--set " + field;
    if (field == "threads") return "--threads";
    if (field == "timeLimit") return "--time-limit";
    if (field == "shard") return "--shard";
    if (field == "importance") return "--importance";
    return "options";
}

/// --help's text for a named setting: its meaning and values, and where its default comes from.
std::string settingHelp(const glint::render::SettingSpec& spec) {
    using glint::render::SettingKind;
    std::string help = spec.meaning;
    if (spec.kind == SettingKind::Integer)
        help += ", " + std::to_string(spec.lo) + " … " + std::to_string(spec.hi);
    if (spec.kind == SettingKind::Choice) {
        help += ": ";
        for (const char* c = spec.choices; *c; ++c) help += *c == ' ' ? " | " : std::string(1, *c);
    }
    if (spec.kind == SettingKind::Boolean)
        return help + " (default: the scene's render." + spec.name + ", else off)";
    return help + " (default: the scene's render." + spec.name + ")";
}

/// The Metropolis statistics as JSON numbers.
nlohmann::json mltJson(const glint::render::MltStats& m) {
    nlohmann::json j = {{"b", m.b},
                        {"bRelStdErr", m.bRelStdErr},
                        {"chainsRelStdErr", m.chainsRelStdErr},
                        {"meanRelStdErr", m.meanRelStdErr},
                        {"bootstrap", m.bootstrap},
                        {"chains", m.chains},
                        {"groups", m.groups},
                        {"featureSpp", m.featureSpp},
                        {"mutations", m.mutations},
                        {"mutationSeconds", m.mutationSeconds},
                        {"mutationsPerSecond", m.mutationsPerSecond()}};
    for (int k = 0; k < 4; ++k) {
        const std::string name = glint::render::mltMutationName(k);
        j["acceptance"][name] = m.acceptance(k);
        j["proposed"][name] = m.proposed[std::size_t(k)];
        j["probability"][name] = m.probabilities[std::size_t(k)];
    }
    return j;
}

/// Draws "[#####.....]  45%  pass 3" on a terminal.
void drawBar(double fraction, int pass) {
    const int width = 40;
    const int filled = int(fraction * width + 0.5);
    std::string bar(std::size_t(filled), '#');
    bar.append(std::size_t(width - filled), '.');
    std::fprintf(stderr, "\r[%s] %3d%%  pass %d", bar.c_str(), int(fraction * 100.0 + 0.5),
                 pass + 1);
    std::fflush(stderr);
}

/// A display sending each pass to tev at `address` as the image named after `out` (a pass's
/// frame is copied: the renderer goes on while it is sent); a tev that is not there or goes
/// away is one warning line, and the render goes on (docs/renderer.md, "Watching a render in
/// tev").
std::unique_ptr<glint::tev::Display> showPasses(const glint::tev::Address& address,
                                                const std::string& out,
                                                glint::render::Callbacks& callbacks) {
    glint::tev::DisplayOptions options;
    options.address = address;
    options.name = std::filesystem::path(out).filename().string();
    options.warn = [](const std::string& line) {
        std::fprintf(stderr, "glint-render: warning: %s\n", glint::oneLine(line).c_str());
    };
    auto display = std::make_unique<glint::tev::Display>(std::move(options));
    callbacks.passDone = [display = display.get(), before = callbacks.passDone](
                             int pass, const glint::FrameBuffers& frame) {
        if (before) before(pass, frame);
        display->show(std::make_shared<glint::FrameBuffers>(frame));
    };
    return display;
}

int run(const Options& opt) {
    const bool tty = isatty(fileno(stderr)) != 0;
    auto stage = [&](const std::string& line) {
        if (!opt.json || !tty)
            std::fprintf(stderr, "glint-render: %s\n", glint::oneLine(line).c_str());
    };
    // Everything that does not need the scene is checked before any work.
    glint::cli::checkOutputPath(opt.out, {".exr"}, "--out");
    glint::cli::checkOutputIsNoInput(opt.out, "--out", {{opt.reference, "--reference"}});
    glint::cli::removeTemporariesOnSignal({opt.out});
    std::optional<glint::tev::Address> tevAddress;
    if (!opt.display.empty()) tevAddress = glint::tev::parseAddress(opt.display, "--display");
    const auto t0 = std::chrono::steady_clock::now();
    // --memory-limit holds the load too: an asset whose predicted load peak exceeds it is
    // refused before it is read (docs/renderer.md, "Memory").
    const std::uint64_t memoryLimit =
        opt.memoryLimit.empty() ? 0 : glint::parseMemorySize(opt.memoryLimit, "--memory-limit");
    stage("loading " + opt.scene);
    glint::render::Scene scene = glint::render::loadScene(opt.scene, memoryLimit);
    for (const std::string& warning : scene.warnings()) stage("warning: " + warning);
    if (opt.camera) {
        try {
            scene.useAssetCamera(*opt.camera);
        } catch (const glint::Error& e) {
            throw glint::Error(e.kind(), e.message(), "command line", "--camera");
        }
    }
    // Every file the scene was read from is an input too (its OBJ and MTL files, a .gltf's
    // buffers, its textures and environment image).
    std::vector<glint::cli::NamedInput> sceneFiles;
    for (const auto& file : scene.inputs())
        sceneFiles.push_back({file.string(), "the scene (" + opt.scene + ")"});
    glint::cli::checkOutputIsNoInput(opt.out, "--out", sceneFiles);
    Settings settings = scene.settings();
    if (!opt.settings.count("spp") && opt.timeLimit > 0.0) settings.spp = 0;
    // The named settings through the codec, each error naming its flag.
    glint::render::SettingValues given = opt.settings;
    for (auto& [name, text] : glint::render::parseSettingAssignments(opt.set, "--set"))
        given[name] = text;
    for (const auto& [name, text] : given) {
        const glint::render::SettingSpec& spec = *glint::render::findSetting(name);
        glint::render::setSetting(settings, spec, text, "command line", flagOf(name));
    }
    // An importance map steers adaptive sampling, so it turns it on.
    if (!opt.importance.empty()) {
        glint::cli::checkOutputIsNoInput(opt.out, "--out", {{opt.importance, "--importance"}});
        auto weights =
            std::make_shared<glint::Image>(glint::render::readImportanceMap(opt.importance));
        glint::render::checkImportanceMap(*weights, scene.width(), scene.height(), opt.importance);
        settings.importance = std::move(weights);
        settings.adaptive = true;
    }
    if (opt.threads) settings.threads = *opt.threads;
    settings.timeLimit = opt.timeLimit;
    if (opt.shard) {
        const auto [index, count] = glint::parseShardSpec(*opt.shard, "--shard");
        settings.shard = glint::render::Shard{index, count};
    }
    if (memoryLimit > 0) settings.memoryLimit = memoryLimit;
    // Settings errors name the field; report the flag that sets it.
    try {
        glint::render::validate(settings);
    } catch (const glint::Error& e) {
        throw glint::Error(glint::ErrorKind::InvalidArgument, e.message(), "command line",
                           flagOf(e.where()));
    }
    // Re-throw option errors with the option as the place.
    auto option = [](const char* name, auto parse) {
        try {
            return parse();
        } catch (const glint::Error& e) {
            throw glint::Error(glint::ErrorKind::InvalidArgument, e.message(), "command line",
                               name);
        }
    };
    if (settings.integrator == glint::render::Integrator::Mlt)
        option("--set", [&] {
            glint::render::validateMlt(settings.mlt);
            return 0;
        });

    std::optional<glint::Image> reference;
    if (!opt.reference.empty()) {
        stage("reading reference " + opt.reference);
        glint::FrameBuffers ref = glint::readExr(opt.reference);
        if (ref.width() != scene.width() || ref.height() != scene.height())
            throw glint::Error(glint::ErrorKind::InvalidArgument,
                               "reference is " + std::to_string(ref.width()) + "x" +
                                   std::to_string(ref.height()) + ", the scene renders " +
                                   std::to_string(scene.width()) + "x" +
                                   std::to_string(scene.height()),
                               opt.reference);
        reference = ref.color();
    }

    stage("building BVH (" + std::to_string(scene.triangleCount()) + " triangles, " +
          std::to_string(scene.areaLightCount()) + " emissive)");
    const glint::render::Accel asked =
        glint::render::estimateSceneMemory(scene, settings.accel, settings.textureCacheMb).accel;
    // Within --memory-limit (or the memory available), the scene and the film together; auto
    // takes clusters when Embree's triangles would not fit (docs/renderer.md, "Memory").
    glint::render::Renderer renderer(std::move(scene), settings);
    if (renderer.accel() != asked)
        stage(
            "the BVH is built over clusters: over Embree's triangles the scene would not fit "
            "the memory");
    const double setupSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    nlohmann::json passes = nlohmann::json::array();
    glint::render::Callbacks callbacks;
    if (tty && !opt.json) callbacks.progress = [](int pass, double f) { drawBar(f, pass); };
    double lastRelMse = -1.0, lastSsim = -1.0;
    if (reference || !tty) {
        callbacks.passDone = [&](int pass, const glint::FrameBuffers& frame) {
            std::string line = "pass " + std::to_string(pass + 1) + ": " +
                               std::to_string(frame.metadata().spp) + " spp";
            nlohmann::json entry = {{"pass", pass + 1}, {"spp", frame.metadata().spp}};
            if (reference) {
                lastRelMse = glint::relMse(frame.color(), *reference).value;
                lastSsim = glint::ssim(frame.color(), *reference).value;
                char buf[96];
                std::snprintf(buf, sizeof buf, "  relMSE %.6g  SSIM %.4f", lastRelMse, lastSsim);
                line += buf;
                entry["relMse"] = lastRelMse;
                entry["ssim"] = lastSsim;
            }
            passes.push_back(entry);
            if (tty && !opt.json)
                std::fprintf(stderr, "\r%-60s\n", line.c_str());
            else if (!opt.json)
                stage(line);
        };
    }

    std::unique_ptr<glint::tev::Display> display;
    if (tevAddress) display = showPasses(*tevAddress, opt.out, callbacks);

    glint::render::RenderResult result = renderer.render(settings, callbacks);
    const glint::FrameBuffers& frame = result.frame;
    const glint::render::RenderStats& stats = result.stats;
    if (tty && !opt.json) std::fprintf(stderr, "\n");
    // The first pass always completes: a time limit shorter than it gets that one pass.
    if (settings.timeLimit > 0.0 && stats.passes == 1 && stats.seconds > settings.timeLimit) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "warning: the time limit (%g s) is shorter than one pass (%.3g s at 1 spp): "
                      "writing that one pass",
                      settings.timeLimit, stats.seconds);
        std::fprintf(stderr, "glint-render: %s\n", buf);
    }
    stage("writing " + opt.out);
    glint::writeExr(frame, opt.out);
    if (display) {
        display->show(std::make_shared<glint::FrameBuffers>(frame));
        display->finish();
    }
    // A variance below float's range is written as 0: say so, it is no estimate of the noise.
    const auto underflow = frame.metadata().extra.find(glint::kVarianceUnderflowKey);
    const long long underflowPixels =
        underflow == frame.metadata().extra.end() ? 0 : std::stoll(underflow->second);
    if (underflowPixels > 0)
        std::fprintf(stderr,
                     "glint-render: warning: the variance of %lld pixels is below float's range "
                     "(radiance about 1e-19 or less) and is written as 0; variance-based denoising "
                     "will see no noise there (scale the emission up)\n",
                     underflowPixels);

    const double samplesPerSecond =
        stats.seconds > 0.0 ? double(stats.samples) / stats.seconds : 0.0;
    const double raysPerSecond = stats.seconds > 0.0 ? double(stats.rays) / stats.seconds : 0.0;
    if (opt.json) {
        nlohmann::json j = {
            {"scene", opt.scene},
            {"out", opt.out},
            {"width", frame.width()},
            {"height", frame.height()},
            {"spp", stats.completedSpp},
            {"seed", settings.seed},
            {"mis", glint::render::misName(settings.mis)},
            {"accel", glint::render::accelName(settings.accel)},
            {"bvh", glint::render::accelName(renderer.accel())},
            {"maxDepth", settings.maxDepth},
            {"threads", settings.threads},
            {"setupSeconds", setupSeconds},
            {"seconds", stats.seconds},
            {"samples", stats.samples},
            {"meanSpp", double(stats.samples) / (double(frame.width()) * double(frame.height()))},
            {"rays", stats.rays},
            {"samplesPerSecond", samplesPerSecond},
            {"raysPerSecond", raysPerSecond},
            {"nonFiniteSamples", stats.nonFiniteSamples},
            {"varianceUnderflowPixels", underflowPixels},
            {"passes", passes}};
        if (reference) j["relMse"] = lastRelMse, j["ssim"] = lastSsim;
        if (settings.shard) {
            const auto [begin, end] =
                glint::shardSampleRange(settings.spp, settings.shard->index, settings.shard->count);
            j["shard"] = {{"index", settings.shard->index},
                          {"count", settings.shard->count},
                          {"totalSpp", settings.spp},
                          {"samples", {begin, end}},
                          {"cancelled", stats.cancelled}};
        }
        if (stats.mlt) j["mlt"] = mltJson(*stats.mlt);
        std::cout << j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    } else {
        std::printf("rendered %s: %dx%d, %d spp in %.3f s (setup %.3f s)\n", opt.scene.c_str(),
                    frame.width(), frame.height(), stats.completedSpp, stats.seconds, setupSeconds);
        if (settings.shard) {
            const auto [begin, end] =
                glint::shardSampleRange(settings.spp, settings.shard->index, settings.shard->count);
            std::printf("  shard %d/%d: samples [%d, %d) of %d spp per pixel%s\n",
                        settings.shard->index, settings.shard->count, begin, end, settings.spp,
                        stats.cancelled ? " (cancelled: sampleCount says what it holds)" : "");
        }
        std::printf("  %.3f M samples/s, %.3f M rays/s, %lld NaN/Inf samples discarded\n",
                    samplesPerSecond * 1e-6, raysPerSecond * 1e-6,
                    static_cast<long long>(stats.nonFiniteSamples));
        if (reference) std::printf("  relMSE %.6g  SSIM %.4f\n", lastRelMse, lastSsim);
        if (stats.mlt) {
            const glint::render::MltStats& m = *stats.mlt;
            std::printf(
                "  mlt: b %.6g (rel. std. error %.3g; the image's mean %.3g), %llu bootstrap "
                "paths, %d chains, %llu mutations at %.3f M/s\n",
                m.b, m.bRelStdErr, m.meanRelStdErr, static_cast<unsigned long long>(m.bootstrap),
                m.chains, static_cast<unsigned long long>(m.mutations),
                m.mutationsPerSecond() * 1e-6);
            std::printf("  mlt acceptance:");
            for (int k = 0; k < 4; ++k)
                std::printf(" %s %.3f", glint::render::mltMutationName(k), m.acceptance(k));
            std::printf("\n");
        }
        std::printf("  wrote %s\n", opt.out.c_str());
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"glint-render: render a scene.json into a layered EXR"};
    Options opt;
    std::string assets;
    for (const std::string& ext : glint::render::assetExtensions())
        assets += (assets.empty() ? "" : ", ") + ext;
    app.add_option(
           "scene", opt.scene,
           "scene.json, or an asset (" + assets + ") rendered with its own camera or a framing one")
        ->required();
    app.add_option("--camera", opt.camera,
                   "render through the glTF camera of this name (a node's or camera's name)");
    app.add_option("--out", opt.out, "output EXR (.exr, in an existing folder)")->required();
    app.add_option("--threads", opt.threads, "worker threads, 0 (all) … 1024");
    app.add_option("--time-limit", opt.timeLimit,
                   "seconds, 0 … 1e7: render passes until time runs out (at least 1 spp)");
    app.add_option("--shard", opt.shard,
                   "i/N: render only shard i (0-based) of N of the per-pixel samples, for "
                   "glint-image merge (docs/distributed.md)");
    app.add_option("--reference", opt.reference, "reference EXR: print relMSE and SSIM per pass");
    app.add_option("--memory-limit", opt.memoryLimit,
                   "refuse an asset whose load would peak above this before reading it, and a "
                   "render whose scene, BVH, textures and film need more before building "
                   "anything; auto takes clusters when that fits (e.g. 2G; default: what is "
                   "available, not checked while loading)");
    app.add_flag("--json", opt.json, "print one JSON object on stdout");
    // The render settings the artist sets here, one flag each from the codec (scene.json's render
    // block under the same names, docs/scene-format.md); the others are the scene's.
    for (const char* name : kSettingFlags) {
        const glint::render::SettingSpec& spec = *glint::render::findSetting(name);
        const std::string key = spec.name;
        if (spec.kind == glint::render::SettingKind::Boolean)
            app.add_flag_callback(
                glint::render::settingFlag(spec), [&opt, key] { opt.settings[key] = "true"; },
                settingHelp(spec));
        else
            app.add_option_function<std::string>(
                glint::render::settingFlag(spec),
                [&opt, key](const std::string& text) { opt.settings[key] = text; },
                settingHelp(spec));
    }
    // Every other render setting, name=value each, under its scene.json name.
    app.add_option("--set", opt.set,
                   glint::render::settingAssignmentsHelp(
                       "integrator, maxDepth, halfBuffers, accel, positionLayer, adaptive, "
                       "noiseThreshold, minSpp"));
    app.add_option("--importance", opt.importance,
                   "adaptive sampling with these per-pixel weights (EXR: one channel, or the "
                   "luminance of RGB; the film's size) multiplying each pixel's estimated error");
    app.add_option("--display", opt.display,
                   "HOST:PORT of a running tev (e.g. 127.0.0.1:14158): each pass is sent to it "
                   "with every layer; a tev that is not there is one warning");
    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-render"))
        return *code;
    return glint::cli::runGuarded("glint-render", [&] { return run(opt); });
}
