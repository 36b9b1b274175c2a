// glint-final: renders a scene and denoises it to a time or error target, adaptive sampling
// steered by auto's estimated error of the denoised image (docs/final-render.md).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_boundary.h"

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"
#include "glint/image/process_clock.h"
#include "glint/pipeline/final_render.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings_codec.h"

namespace {

struct Options {
    std::string scene, out;
    std::optional<double> timeLimit, targetError;
    std::optional<int> threads;
    std::vector<std::string> set;  ///< --set: render settings, name=value each
};

/// What the time limit keeps for writing the EXR and the exit, a fixed part and a part per
/// pixel: measured 0.06–0.09 s at 256² and 0.27–0.39 s at 1024² (45 channels, 2 threads), and
/// kept with a margin of about 1.5 (docs/research/start-and-writing.md).
constexpr double kWriteSeconds = 0.1;
constexpr double kWriteSecondsPerPixel = 0.35e-6;

/// The flag that sets the option or Settings field `field` (validate's place).
std::string flagOf(const std::string& field) {
    if (field == "timeLimit") return "--time-limit";
    if (field == "targetError") return "--target-error";
    if (field == "threads") return "--threads";
    if (glint::render::findSetting(field)) return "--set " + field;
    return "options";
}

int run(const Options& opt, std::chrono::steady_clock::time_point started) {
    glint::cli::checkOutputPath(opt.out, {".exr"}, "--out");
    glint::cli::removeTemporariesOnSignal({opt.out});
    // A target given must be one: > 0 (0 is "none" only in the library).
    auto positive = [](const std::optional<double>& v, const char* flag, const char* what) {
        if (v && !(*v > 0.0))
            throw glint::Error(glint::ErrorKind::InvalidArgument,
                               std::string(what) + " must be > 0, got " + glint::numberText(*v),
                               "command line", flag);
    };
    positive(opt.timeLimit, "--time-limit", "the time limit");
    positive(opt.targetError, "--target-error", "the error target");
    const glint::render::SettingValues given =
        glint::render::parseSettingAssignments(opt.set, "--set");

    std::fprintf(stderr, "glint-final: loading %s\n", opt.scene.c_str());
    glint::render::Scene scene = glint::render::loadScene(opt.scene);
    std::vector<glint::cli::NamedInput> sceneFiles;
    for (const auto& file : scene.inputs())
        sceneFiles.push_back({file.string(), "the scene (" + opt.scene + ")"});
    glint::cli::checkOutputIsNoInput(opt.out, "--out", sceneFiles);

    glint::pipeline::FinalOptions options;
    options.settings = scene.settings();
    options.settings.adaptive = true;
    // A time limit alone renders until it runs out; --set spp=N bounds every pixel.
    if (opt.timeLimit && !given.count("spp")) options.settings.spp = 0;
    for (const auto& [name, text] : given)
        glint::render::setSetting(options.settings, *glint::render::findSetting(name), text,
                                  "command line", flagOf(name));
    if (opt.threads) options.settings.threads = *opt.threads;
    options.timeLimit = opt.timeLimit.value_or(0.0);
    // The renderer is built for these settings (its memory check validates them): with the time
    // limit, so that spp 0 (until time runs out) is valid.
    options.settings.timeLimit = options.timeLimit;
    options.targetError = opt.targetError.value_or(0.0);
    options.steering = glint::pipeline::defaultSteering(options.timeLimit, options.targetError);
    options.log = [](const std::string& line) {
        std::fprintf(stderr, "glint-final: %s\n", line.c_str());
    };
    try {
        glint::pipeline::validate(options);
    } catch (const glint::Error& e) {
        throw glint::Error(glint::ErrorKind::InvalidArgument, e.message(), "command line",
                           flagOf(e.where()));
    }

    const double pixels = double(scene.width()) * double(scene.height());
    glint::render::Renderer renderer(std::move(scene), options.settings);
    // The time limit covers the whole run: the process's start (counted from its exec), loading
    // the scene and building the renderer took part of it already, and the EXR's writing and the
    // exit take some (kWriteSeconds…); the loop gets what is left (at least a moment: the first
    // pass always completes).
    if (opt.timeLimit) {
        const double spent =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        const double writing = kWriteSeconds + kWriteSecondsPerPixel * pixels;
        options.timeLimit = std::max(*opt.timeLimit - spent - writing, 1e-9);
        std::fprintf(stderr,
                     "glint-final: time limit: %.2f s taken by the start and the scene, %.2f s "
                     "kept for writing, %.2f s for the render and auto\n",
                     spent, writing, options.timeLimit);
    }
    const glint::pipeline::FinalResult result = glint::pipeline::renderFinal(renderer, options);
    if (result.overTime)
        std::fprintf(stderr,
                     "glint-final: warning: the time limit (%g s) is shorter than one pass and "
                     "its denoising (%.3g s): writing that one pass, denoised (%s)\n",
                     *opt.timeLimit, result.seconds, result.finalPlan.c_str());
    glint::writeExr(result.frame, opt.out);
    std::printf(
        "final %s: %dx%d, %.1f spp a pixel (%d passes, %d refreshes), estimated relMSE %.4g%s in "
        "%.2f s (auto %.2f s)\n  final auto: %s\n  wrote %s\n",
        opt.scene.c_str(), result.frame.width(), result.frame.height(),
        double(result.render.samples) / pixels, result.render.passes, result.refreshes,
        result.estimatedRelMse, result.targetReached ? " (target reached)" : "", result.seconds,
        result.autoSeconds, result.finalPlan.c_str(), opt.out.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    // The time limit counts from the process's exec: before main, loading the shared libraries
    // (OpenImageIO's bring some 260) takes 0.4 s on a 2-core machine
    // (docs/research/start-and-writing.md).
    const auto started =
        std::chrono::steady_clock::now() -
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::duration<double>(glint::processAgeSeconds().value_or(0.0)));
    // Auto's probes, refreshes and final run allocate and free frame-sized buffers by the
    // hundred (glint/image/memory.h).
    glint::retainFreedMemory();
    CLI::App app{
        "glint-final: render a scene and denoise it to a time or error target (adaptive sampling "
        "steered by the render's variance under a time limit alone, else by auto's estimated "
        "error of the denoised image)"};
    Options opt;
    app.add_option("scene", opt.scene, "scene.json, or an asset glint-render reads")->required();
    app.add_option(
           "--out", opt.out,
           "output EXR: the denoised colour, the render's layers and its colour (layer noisy)")
        ->required();
    app.add_option("--time-limit", opt.timeLimit,
                   "seconds for everything (render, auto's refreshes, the final auto), > 0 … 1e7");
    app.add_option("--target-error", opt.targetError,
                   "stop once auto's estimated relMSE of the denoised image (display values) is "
                   "at most this, > 0 … 1e6");
    app.add_option("--set", opt.set,
                   glint::render::settingAssignmentsHelp(
                       "spp (the most a pixel takes), seed, noiseThreshold, minSpp"));
    app.add_option("--threads", opt.threads, "worker threads, 0 (all) … 1024");
    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-final"))
        return *code;
    return glint::cli::runGuarded("glint-final", [&] { return run(opt, started); });
}
