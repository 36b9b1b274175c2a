// The final render at equal time (docs/lab/adaptive-sampling.md, "Equal time after auto"): for
// each scene, budget and seed, the same wall-clock budget for the render and auto together, in
// any of four ways — uniform passes, the renderer's adaptive sampling at a fixed threshold
// (halved at convergence while time is left), the threshold schedule with the renderer's error
// alone (variance) and with auto's error of the denoised image (denoiser) — and the relMSE of
// the denoised image against scenes/<scene>/reference.exr (scene_reference.h). One TSV row per
// run, with the final auto's plan and, when one was stopped at its deadline, that plan, and the
// denoised image's relMSE in display values against the reference (`displayRelMSE`: the form of
// glint-final's estimate, the `estimated` column, which --target-error reads).
//   build/bin/bench_final [--scenes glossy,dof,cornell] [--seeds 21,22] [--seconds 15,30]
//                         [--threads 2] [--min-spp 16] [--ways uniform,fixed,variance,denoiser]
//                         (a steered way may name its samples cap, FinalOptions::sppCapRatio:
//                         variance:16, variance:0 for none)
//                         [--refresh-share 0.2] [--refresh-quality fast]
//                         [--frames-dir DIR]   (each run's frame as DIR/<scene>_<seed>_<way>.exr,
//                                               its render before auto kept as layer noisy)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "glint/image/display_curve.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/pipeline/final_render.h"
#include "glint/pipeline/steering.h"
#include "glint/render/scene.h"

#include "bench_options.h"
#include "scene_reference.h"

namespace {

/// The denoised image's relMSE in display values against the reference, in the form of
/// glint-final's estimate (pipeline::relativeError over the per-channel mean of the squared
/// display error, at exposure 0 as glint-final's auto runs): what an error target is met by.
double trueDisplayRelMse(const glint::Image& image, const glint::Image& reference) {
    const glint::DisplayCurve display(1.0);
    glint::Image error(image.width(), image.height(), 1);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            double sum = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double d =
                    display(double(image(x, y, c))) - display(double(reference(x, y, c)));
                sum += d * d;
            }
            error(x, y, 0) = float(sum / 3.0);
        }
    return glint::pipeline::estimatedRelMse(glint::pipeline::relativeError(error, image, 0.0f));
}

}  // namespace

int main(int argc, char** argv) {
    std::string scenes = "glossy,dof,cornell", seeds = "21,22", budgets = "15,30";
    std::string ways = "uniform,fixed,variance,denoiser", refreshQuality = "fast";
    int threads = 2, minSpp = 16;
    double refreshShare = 0.2;
    glint::bench::OptionTable options;
    options.bind("--scenes", scenes);
    options.bind("--seeds", seeds);
    options.bind("--seconds", budgets);
    options.bind("--threads", threads);
    options.bind("--min-spp", minSpp);
    options.bind("--ways", ways);
    options.bind("--refresh-share", refreshShare);
    options.bind("--refresh-quality", refreshQuality);
    std::string framesDir;
    options.bind("--frames-dir", framesDir);
    if (const int rc = options.parse("bench_final", argc, argv)) return rc;
    using glint::pipeline::Steering;
    std::printf(
        "scene\tbudget\tseed\tway\trelMSE\testimated\tmeanSpp\tpasses\trefreshes\thalvings\t"
        "refreshSeconds\tautoSeconds\tseconds\tplan\tstopped\tdisplayRelMSE\n");
    for (const std::string& name : glint::bench::splitList(scenes)) {
        const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + name;
        const glint::Image reference = glint::readExr(glint::bench::sceneReference(name)).color();
        glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
        // What the final auto takes on this film (the time limit keeps room for it until a
        // refresh measures it): the final auto of a 16-spp uniform final render.
        glint::pipeline::FinalOptions calibration;
        calibration.settings = renderer.scene().settings();
        calibration.settings.spp = 16;
        calibration.settings.adaptive = false;
        calibration.settings.threads = threads;
        const double autoSeconds = glint::pipeline::renderFinal(renderer, calibration).autoSeconds;
        for (const std::string& budget : glint::bench::splitList(budgets))
            for (const std::string& seed : glint::bench::splitList(seeds))
                for (const std::string& way : glint::bench::splitList(ways)) {
                    glint::pipeline::FinalOptions o;
                    o.settings = renderer.scene().settings();
                    o.settings.spp = 0;
                    o.settings.seed = std::stoull(seed);
                    o.settings.threads = threads;
                    o.settings.adaptive = way != "uniform";
                    o.settings.minSpp = minSpp;
                    o.timeLimit = std::stod(budget);
                    // A way may name the samples cap: variance:16, denoiser:0 (off).
                    const std::size_t colon = way.find(':');
                    const std::string steering = way.substr(0, colon);
                    if (colon != std::string::npos)
                        o.sppCapRatio = std::stod(way.substr(colon + 1));
                    o.steering = steering == "uniform" ? Steering::Fixed
                                                       : glint::pipeline::parseSteering(steering);
                    o.expectedAutoSeconds = autoSeconds;
                    o.refreshShare = refreshShare;
                    o.refreshQuality = glint::denoise::parseAutoQuality(refreshQuality);
                    const glint::pipeline::FinalResult r =
                        glint::pipeline::renderFinal(renderer, o);
                    const double relMse = glint::relMse(r.frame.color(), reference).value;
                    const double displayRelMse = trueDisplayRelMse(r.frame.color(), reference);
                    if (!framesDir.empty()) {
                        const std::string stem = framesDir + "/" + name + "_" + seed + "_" + way;
                        // It keeps the render's colour (layer noisy): glint-lab auto on it
                        // denoises the render again.
                        glint::writeExr(r.frame, stem + ".exr");
                    }
                    const double pixels = double(r.frame.width()) * double(r.frame.height());
                    std::printf(
                        "%s\t%s\t%s\t%s\t%.6g\t%.4g\t%.1f\t%d\t%d\t%d\t%.2f\t%.2f\t%.2f\t%s\t%s"
                        "\t%.4g\n",
                        name.c_str(), budget.c_str(), seed.c_str(), way.c_str(), relMse,
                        r.estimatedRelMse, double(r.render.samples) / pixels, r.render.passes,
                        r.refreshes, r.thresholdHalvings, r.refreshSeconds, r.autoSeconds,
                        r.seconds, r.finalPlan.c_str(),
                        r.finalStopped.empty() ? "-" : r.finalStopped.c_str(), displayRelMse);
                    std::fflush(stdout);
                }
    }
    return 0;
}
