// Where adaptive sampling's time goes (docs/lab/adaptive-dof.md, "Why adaptive loses on
// dof"): one scene rendered for the same wall-clock time uniformly and adaptively (the fixed
// threshold, halved at convergence as glint-final does), with the samples, rays and rays per
// sample of each, and per adaptive pass the pixels it took, its samples, its seconds, the gap
// between passes (snapshot, plan) and the largest tile's share of its samples (load balance).
//   build/bin/bench_adaptive_throughput [--scene dof] [--seed 21] [--seconds 8] [--threads 2]
//                                       [--min-spp 16] [--passes 0|1 (print every pass)]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"

#include "bench_options.h"

namespace {

using Clock = std::chrono::steady_clock;

struct PassRecord {
    double called = 0.0;  // the importance callback (after the snapshot, before the plan)
    double first = 0.0, last = 0.0;  // the pass's first and last tile done
    std::uint64_t samples = 0, active = 0, largestTile = 0;
};

}  // namespace

int main(int argc, char** argv) {
    std::string scene = "dof";
    unsigned long long seed = 21;
    double seconds = 8.0;
    int threads = 2, minSpp = 16, printPasses = 0;
    glint::bench::OptionTable options;
    options.bind("--scene", scene);
    options.bind("--seed", seed);
    options.bind("--seconds", seconds);
    options.bind("--threads", threads);
    options.bind("--min-spp", minSpp);
    options.bind("--passes", printPasses);
    if (const int rc = options.parse("bench_adaptive_throughput", argc, argv)) return rc;
    const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + scene;
    glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
    std::printf(
        "way\tthreads\tseconds\tsamples\tmeanSpp\tsamplesPerSec\traysPerSample\traysPerSec"
        "\tpasses\tadaptivePasses\tmeanActive\tgapSeconds\tpassSeconds\tbalance\n");
    for (const bool adaptive : {false, true}) {
        glint::render::Settings s = renderer.scene().settings();
        s.spp = 0;
        s.seed = seed;
        s.threads = threads;
        s.timeLimit = seconds;
        s.halfBuffers = true;
        s.adaptive = adaptive;
        s.minSpp = minSpp;
        const int w = renderer.scene().width(), h = renderer.scene().height();
        const int ts = s.tileSize;
        std::vector<PassRecord> passes;
        std::vector<float> counts(std::size_t(w) * h, 0.0f);
        double boost = 1.0;
        const Clock::time_point start = Clock::now();
        auto now = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
        glint::render::Callbacks cb;
        cb.progress = [&](int pass, double) {
            if (std::size_t(pass) >= passes.size()) passes.resize(std::size_t(pass) + 1);
            PassRecord& r = passes[std::size_t(pass)];
            r.last = now();
            if (r.first == 0.0) r.first = r.last;
        };
        // Before each adaptive pass: what the previous adaptive pass took, from the sample
        // counts (the map is kept).
        auto record = [&](int pass, const glint::FrameBuffers& frame) {
            if (std::size_t(pass) >= passes.size()) passes.resize(std::size_t(pass) + 1);
            passes[std::size_t(pass)].called = now();
            const glint::Image& n = frame.layer(glint::Layer::SampleCount);
            std::map<int, std::uint64_t> perTile;
            PassRecord& prev = passes[std::size_t(std::max(pass - 1, 0))];
            std::uint64_t samples = 0, active = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    float& c = counts[std::size_t(y) * w + x];
                    const auto added = std::uint64_t(std::max(0.0f, n(x, y, 0) - c));
                    c = n(x, y, 0);
                    samples += added;
                    active += added > 0;
                    perTile[(y / ts) * 1000 + x / ts] += added;
                }
            if (pass > 0 && samples > 0) {
                prev.samples = samples;
                prev.active = active;
                for (const auto& [tile, k] : perTile)
                    prev.largestTile = std::max(prev.largestTile, k);
            }
        };
        cb.importance = [&](int pass, const glint::FrameBuffers& frame) {
            record(pass, frame);
            return std::shared_ptr<const glint::Image>();
        };
        cb.converged = [&](int pass, const glint::FrameBuffers& frame) {
            record(pass, frame);
            boost *= 2.0;
            return std::make_shared<const glint::Image>(w, h, 1, float(boost));
        };
        const glint::render::RenderResult r =
            renderer.render(s, adaptive ? cb : glint::render::Callbacks{});
        const glint::render::RenderStats& st = r.stats;
        // Adaptive passes only: the gap (last tile of one pass to the next's callback) and the
        // pass (callback to its last tile), and the balance: the pass's samples over threads ×
        // max(largest tile, samples / threads) (1: the threads could share it evenly).
        int adaptivePasses = 0;
        double gap = 0.0, passTime = 0.0, activeSum = 0.0, balance = 0.0;
        for (std::size_t p = 1; p < passes.size(); ++p) {
            const PassRecord& r0 = passes[p - 1];
            const PassRecord& r1 = passes[p];
            if (r1.called == 0.0 || r1.samples == 0) continue;
            ++adaptivePasses;
            gap += r1.called - r0.last;
            passTime += r1.last - r1.called;
            activeSum += double(r1.active);
            const double ideal = std::max(double(r1.largestTile), double(r1.samples) / threads);
            balance += double(r1.samples) / (threads * ideal);
            if (printPasses)
                std::printf(
                    "#pass %zu\tactive %llu\tsamples %llu\tlargestTile %llu\tgap %.4f\tpass %.4f\n",
                    p, (unsigned long long)r1.active, (unsigned long long)r1.samples,
                    (unsigned long long)r1.largestTile, r1.called - r0.last, r1.last - r1.called);
        }
        // Least squares over the adaptive passes: pass seconds = fixed + perSample · samples;
        // what the passes cost beyond their samples is passes × (fixed + gap).
        double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
        for (std::size_t p = 1; p < passes.size(); ++p) {
            const PassRecord& r1 = passes[p];
            if (r1.called == 0.0 || r1.samples == 0) continue;
            const double x = double(r1.samples), y = r1.last - r1.called;
            sx += x, sy += y, sxx += x * x, sxy += x * y;
        }
        const double np = double(adaptivePasses);
        const double perSample =
            np > 1 ? (np * sxy - sx * sy) / std::max(np * sxx - sx * sx, 1e-300) : 0.0;
        const double fixed = np > 0 ? (sy - perSample * sx) / np : 0.0;
        const double k = adaptivePasses > 0 ? 1.0 / adaptivePasses : 0.0;
        if (adaptive)
            std::printf(
                "#fit: a pass costs %.2f ms + %.3f us a sample; passes beyond their "
                "samples (fixed + gap): %.2f s of %.2f\n",
                1e3 * fixed, 1e6 * perSample, np * (fixed + gap * k), st.seconds);
        std::printf("%s\t%d\t%.2f\t%llu\t%.1f\t%.0f\t%.2f\t%.0f\t%d\t%d\t%.0f\t%.4f\t%.4f\t%.3f\n",
                    adaptive ? "adaptive" : "uniform", threads, st.seconds,
                    (unsigned long long)st.samples, double(st.samples) / (double(w) * h),
                    double(st.samples) / st.seconds, double(st.rays) / double(st.samples),
                    double(st.rays) / st.seconds, st.passes, adaptivePasses, activeSum * k, gap * k,
                    passTime * k, balance * k);
        std::fflush(stdout);
    }
    return 0;
}
