// bench_nfor: the speed figure of the "nfor" filter in docs/denoise.md. Renders cornell at size²
// with half buffers (not timed), then times nfor (default parameters, cross-filtering the
// halves; --radius sets windowRadius, 0 keeps its default) and nlmeans beside it on `threads`
// threads, best of `reps` in wall time and in process CPU time (std::clock), and prints one JSON
// object.
//   build/bin/bench_nfor [--size 1024] [--spp 4] [--threads 2] [--reps 3] [--radius 0]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_options.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    glint::bench::RenderBankOptions o;
    o.reps = 3;
    int radius = 0;
    const int parsed = glint::bench::parseOptions(
        "bench_nfor", argc, argv, [&](const std::string& a, const std::string& text) {
            const int value = glint::bench::intOption(a, text);
            if (a == "--radius") {
                radius = value;
                return true;
            }
            return a != "--members" && a != "--retain-freed" && o.take(a, value);
        });
    if (parsed != 0) return parsed;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(o.threads));

    // The input: cornell at size², a low spp, half buffers (the render is not timed).
    const fs::path root = GLINT_SOURCE_DIR;
    std::ifstream in(root / "scenes/cornell/scene.json");
    nlohmann::json scene = nlohmann::json::parse(in);
    scene["film"] = {{"width", o.size}, {"height", o.size}};
    glint::render::Renderer renderer(
        glint::render::parseScene(scene.dump(), root / "scenes/cornell/scene.json"));
    glint::render::Settings s = renderer.scene().settings();
    s.spp = o.spp;
    s.threads = o.threads;
    s.halfBuffers = true;
    const glint::FrameBuffers frame = renderer.render(s).frame;

    nlohmann::json out = {
        {"size", o.size}, {"spp", o.spp}, {"threads", o.threads}, {"reps", o.reps}};
    if (radius > 0) out["windowRadius"] = radius;
    for (const char* name : {"nfor", "nlmeans"}) {
        const glint::denoise::Filter& filter = glint::denoise::findFilter(name);
        glint::denoise::FilterOptions options;
        options.threads = o.threads;
        glint::denoise::ParamValues params;
        if (radius > 0 && std::string(name) == "nfor") params["windowRadius"] = radius;
        double best = std::numeric_limits<double>::infinity(), bestCpu = best;
        for (int r = 0; r < o.reps; ++r) {
            const auto t0 = std::chrono::steady_clock::now();
            const std::clock_t c0 = std::clock();
            const glint::Image result = glint::denoise::applyFilter(filter, frame, params, options);
            const std::clock_t c1 = std::clock();
            const auto t1 = std::chrono::steady_clock::now();
            best = std::min(best, std::chrono::duration<double>(t1 - t0).count());
            bestCpu = std::min(bestCpu, double(c1 - c0) / CLOCKS_PER_SEC);
        }
        out[std::string(name) + "Seconds"] = best;
        out[std::string(name) + "CpuSeconds"] = bestCpu;
    }
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
