// The final render at equal time (docs/lab/adaptive-sampling.md, "Equal time after auto"): for
// each scene and seed, the same wall-clock budget for the render and auto together, four ways —
// uniform passes, the renderer's adaptive sampling at a fixed threshold, the threshold schedule
// with the renderer's error alone (variance) and with auto's error of the denoised image
// (denoiser) — and the relMSE of the denoised image against scenes/<scene>/reference.exr.
//   build/bin/bench_final [--scenes glossy,dof,cornell] [--seeds 21,22,23] [--seconds 8]
//                         [--threads 1] [--min-spp 16]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "glint/denoise/auto_stream.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/pipeline/final_render.h"
#include "glint/render/scene.h"

namespace {

std::vector<std::string> split(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) out.push_back(item);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    std::string scenes = "glossy,dof,cornell", seeds = "21,22,23";
    double seconds = 8.0;
    int threads = 1, minSpp = 16;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--scenes")
            scenes = value;
        else if (flag == "--seeds")
            seeds = value;
        else if (flag == "--seconds")
            seconds = std::stod(value);
        else if (flag == "--threads")
            threads = std::stoi(value);
        else if (flag == "--min-spp")
            minSpp = std::stoi(value);
        else {
            std::fprintf(stderr, "bench_final: unknown flag %s\n", flag.c_str());
            return 2;
        }
    }
    using glint::pipeline::Steering;
    struct Way {
        const char* name;
        bool adaptive;
        Steering steering;
    };
    const Way ways[] = {{"uniform", false, Steering::Fixed},
                        {"fixed", true, Steering::Fixed},
                        {"variance", true, Steering::Variance},
                        {"denoiser", true, Steering::Denoiser}};
    std::printf(
        "scene\tseed\tway\trelMSE\testimated\tmeanSpp\tpasses\trefreshes\tautoSeconds\tseconds\n");
    for (const std::string& name : split(scenes)) {
        const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + name;
        const glint::Image reference = glint::readExr(dir + "/reference.exr").color();
        glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
        // What auto takes on this film (the time limit keeps room for it before a refresh
        // measures it): once on a 16-spp render.
        glint::render::Settings calibration = renderer.scene().settings();
        calibration.spp = 16;
        calibration.halfBuffers = true;
        calibration.threads = threads;
        const glint::FrameBuffers frame = renderer.render(calibration).frame;
        const auto t0 = std::chrono::steady_clock::now();
        glint::denoise::autoCompositeStreamed(frame, {}, {});
        const double autoSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        for (const std::string& seed : split(seeds))
            for (const Way& way : ways) {
                glint::pipeline::FinalOptions o;
                o.settings = renderer.scene().settings();
                o.settings.spp = 0;
                o.settings.seed = std::stoull(seed);
                o.settings.threads = threads;
                o.settings.adaptive = way.adaptive;
                o.settings.minSpp = minSpp;
                o.timeLimit = seconds;
                o.steering = way.steering;
                o.expectedAutoSeconds = autoSeconds;
                const glint::pipeline::FinalResult r = glint::pipeline::renderFinal(renderer, o);
                const double relMse = glint::relMse(r.frame.color(), reference).value;
                const double pixels = double(r.frame.width()) * double(r.frame.height());
                std::printf("%s\t%s\t%s\t%.6g\t%.4g\t%.1f\t%d\t%d\t%.2f\t%.2f\n", name.c_str(),
                            seed.c_str(), way.name, relMse, r.estimatedRelMse,
                            double(r.render.samples) / pixels, r.render.passes, r.refreshes,
                            r.autoSeconds, r.seconds);
                std::fflush(stdout);
            }
    }
    return 0;
}
