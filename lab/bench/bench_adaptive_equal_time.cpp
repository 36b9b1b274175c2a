// The renderer's samples spent four ways in the same render time, then the same auto
// (docs/lab/adaptive-dof.md, "Why adaptive loses on dof"): uniform passes; the fixed
// threshold; the variance schedule (a uniform map of scale √(spp / spp at the adaptive start));
// and the spread map (lab::importanceFromSpread at that scale, remade whenever the mean spp
// has doubled). Every adaptive way halves its threshold at convergence, as glint-final does.
// relMSE after auto (balanced) against scenes/<scene>/reference.exr (scene_reference.h); one TSV
// row per run.
//   build/bin/bench_adaptive_equal_time [--scenes dof] [--seeds 21,22] [--seconds 12]
//                                       [--threads 2] [--min-spp 16]
//                                       [--ways uniform,fixed,variance,spread]
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/lab/spread_map.h"
#include "glint/pipeline/refresh.h"
#include "glint/pipeline/steering.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

#include "bench_options.h"
#include "scene_reference.h"

int main(int argc, char** argv) {
    std::string scenes = "dof", seeds = "21,22", ways = "uniform,fixed,variance,spread";
    double seconds = 12.0;
    int threads = 2, minSpp = 16;
    glint::bench::OptionTable options;
    options.bind("--scenes", scenes);
    options.bind("--seeds", seeds);
    options.bind("--seconds", seconds);
    options.bind("--threads", threads);
    options.bind("--min-spp", minSpp);
    options.bind("--ways", ways);
    if (const int rc = options.parse("bench_adaptive_equal_time", argc, argv)) return rc;
    const glint::pipeline::AutoRun autoRun =
        glint::pipeline::autoRun({}, glint::denoise::AutoQuality::Balanced);
    std::printf(
        "scene\tbudget\tseed\tway\trelMSE\traw\tmeanSpp\tpasses\thalvings\trenderSeconds\n");
    for (const std::string& name : glint::bench::splitList(scenes)) {
        const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + name;
        const glint::Image reference = glint::readExr(glint::bench::sceneReference(name)).color();
        glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
        const int w = renderer.scene().width(), h = renderer.scene().height();
        for (const std::string& seed : glint::bench::splitList(seeds))
            for (const std::string& way : glint::bench::splitList(ways)) {
                glint::render::Settings s = renderer.scene().settings();
                s.spp = 0;
                s.seed = std::stoull(seed);
                s.threads = threads;
                s.timeLimit = seconds;
                s.halfBuffers = true;
                s.adaptive = way != "uniform";
                s.minSpp = minSpp;
                // The schedule: the map's scale, remade at every doubling of the mean spp.
                double boost = 1.0, startSpp = 0.0, lastSpp = 0.0;
                int halvings = 0;
                std::shared_ptr<const glint::Image> map;
                auto makeMap = [&](const glint::FrameBuffers& frame) {
                    const double scale = boost * std::sqrt(lastSpp / startSpp);
                    if (way == "spread")
                        map = std::make_shared<const glint::Image>(
                            glint::lab::importanceFromSpread(frame, scale));
                    else if (way == "variance" || boost > 1.0)
                        map = std::make_shared<const glint::Image>(
                            w, h, 1, float(way == "variance" ? scale : boost));
                    return map;
                };
                glint::render::Callbacks cb;
                if (way == "variance" || way == "spread")
                    cb.importance = [&](int, const glint::FrameBuffers& frame)
                        -> std::shared_ptr<const glint::Image> {
                        const double spp = glint::pipeline::meanSpp(frame);
                        if (startSpp == 0.0) startSpp = spp;
                        if (lastSpp > 0.0 && spp < 2.0 * lastSpp) return nullptr;
                        lastSpp = spp;
                        return makeMap(frame);
                    };
                cb.converged = [&](int, const glint::FrameBuffers& frame) {
                    if (startSpp == 0.0) startSpp = lastSpp = glint::pipeline::meanSpp(frame);
                    boost *= 2.0;
                    ++halvings;
                    return makeMap(frame);
                };
                const glint::render::RenderResult r =
                    renderer.render(s, s.adaptive ? cb : glint::render::Callbacks{});
                const glint::pipeline::Denoised d = glint::pipeline::denoiseFrame(r.frame, autoRun);
                std::printf("%s\t%g\t%s\t%s\t%.6g\t%.6g\t%.1f\t%d\t%d\t%.2f\n", name.c_str(),
                            seconds, seed.c_str(), way.c_str(),
                            glint::relMse(d.result.composite, reference).value,
                            glint::relMse(r.frame.color(), reference).value,
                            double(r.stats.samples) / (double(w) * h), r.stats.passes, halvings,
                            r.stats.seconds);
                std::fflush(stdout);
            }
    }
    return 0;
}
