// What an ideal importance map could gain (docs/lab/adaptive-dof.md, "Why adaptive loses on
// dof"): where the error of the denoised image lives at uniform sampling, and an oracle that
// spends the same samples by the true error against the reference.
//  1. Uniform at --spp, auto (balanced): relMSE of the noisy and the denoised image; the share of
//     the denoised image's relMSE in its worst 1 %, 10 %, 25 % of pixels; the analytic bound of
//     any allocation of the same samples when a pixel's error falls as 1/n: the optimum puts
//     n_i ∝ √e_i and gives (mean √e)² / mean e of uniform's error (Cauchy–Schwarz).
//  2. The oracle: the true per-pixel error of another seed's uniform + auto (--map-seed; one
//     realisation's own error would steer to its own noise), box-blurred 5×5, gives each pixel
//     n_i ∝ √e_i samples (at least --pilot, at most 16× --spp, mean --spp); rendered with
//     adaptive passes that open exactly the pixels below their n_i; auto; relMSE of the
//     denoised image against uniform's at the same samples and at the oracle's rays (time);
//     and the same allocation by the noisy frame's own relative spread (sqrtVariance).
//  3. The cost-aware oracle: at equal time (Σ c_i n_i fixed, c_i a sample's rays at pixel i)
//     the optimum of Σ e_i/n_i is n_i ∝ √(e_i / c_i); c_i measured per --cost-block² block by
//     rendering each block alone (the map seed, --pilot spp) and read per pixel (oracleCost) or
//     averaged per 16² tile, what the renderer's tiles could count (oracleTileCost). Where e_i
//     falls as n^−β rather than 1/n the optimum is n_i ∝ (e_i / c_i)^(1/(1+β)): --exponent sets
//     that power for the cost ways and for oraclePow (cost-blind).
//  4. pilotSpread(Raw): sqrtVariance's allocation from the render's own first --pilot samples,
//     box-averaged 5 × 5 (or not): what the renderer alone could steer by; n_i ∝ (squared
//     spread)^--exponent (0.5: ∝ the spread; 1: ∝ its square, the threshold's rule). pilotAuto: the
//     oracle's allocation by auto's own estimated error of the denoised start instead of the true
//     error.
//  Each way is compared with uniform at its own rays.
//   build/bin/bench_adaptive_oracle [--scene dof] [--seed 21] [--spp 256] [--pilot 64]
//       [--map-seed 1021] [--threads 2] [--cost-block 4] [--exponent 0.5]
//       [--ways oracle,sqrtVariance,oracleCost,oracleTileCost,oraclePow,pilotSpread,pilotSpreadRaw,
//        pilotAuto]
//       [--map-out error.exr]
//       [--allocations-only 1]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "glint/image/box_mean.h"
#include "glint/image/io.h"
#include "glint/pipeline/refresh.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

#include "bench_options.h"
#include "oracle_allocation.h"
#include "scene_reference.h"

namespace {

using glint::bench::mean;
using glint::bench::relativeErrors;

/// The share of Σe in the largest `fraction` of the pixels.
double topShare(std::vector<double> e, double fraction) {
    std::sort(e.begin(), e.end(), std::greater<>());
    const auto k = std::size_t(std::max(1.0, fraction * double(e.size())));
    return std::accumulate(e.begin(), e.begin() + std::ptrdiff_t(k), 0.0) /
           std::accumulate(e.begin(), e.end(), 0.0);
}

/// (mean √e)² / mean e: the error of the best allocation of the same samples over uniform's.
double allocationBound(const std::vector<double>& e) {
    double root = 0.0;
    for (double v : e) root += std::sqrt(v);
    root /= double(e.size());
    return root * root / mean(e);
}

struct Run {
    glint::FrameBuffers frame;
    glint::render::RenderStats stats;
    double rawRelMse = 0.0, relMse = 0.0;
    std::vector<double> errors;  // of the denoised image, per pixel
};

}  // namespace

int main(int argc, char** argv) {
    std::string scene = "dof", mapOut;
    unsigned long long seed = 21, mapSeed = 1021;
    int spp = 256, pilot = 64, threads = 2, costBlock = 4;
    double exponent = 0.5;
    int allocationsOnly = 0;  // 1: print each way's allocation, render none of them
    std::string ways = "oracle,sqrtVariance,oracleCost,oracleTileCost";
    glint::bench::OptionTable options;
    options.bind("--scene", scene);
    options.bind("--seed", seed);
    options.bind("--map-seed", mapSeed);
    options.bind("--spp", spp);
    options.bind("--pilot", pilot);
    options.bind("--threads", threads);
    options.bind("--cost-block", costBlock);
    options.bind("--exponent", exponent);
    options.bind("--ways", ways);
    options.bind("--allocations-only", allocationsOnly);
    options.bind("--map-out", mapOut);
    if (const int rc = options.parse("bench_adaptive_oracle", argc, argv)) return rc;
    auto bad = [](const std::string& what) {
        std::fprintf(stderr, "bench_adaptive_oracle: %s\n", what.c_str());
        return 2;
    };
    if (costBlock < 1) return bad("--cost-block needs a block edge >= 1");
    if (!(exponent > 0.0 && exponent <= 4.0)) return bad("--exponent needs a power in (0, 4]");
    const std::vector<std::string> known = {"oracle",         "oraclePow",      "sqrtVariance",
                                            "oracleCost",     "oracleTileCost", "pilotSpread",
                                            "pilotSpreadRaw", "pilotAuto"};
    for (const std::string& way : glint::bench::splitList(ways))
        if (std::find(known.begin(), known.end(), way) == known.end())
            return bad("unknown way '" + way +
                       "' (expected oracle, oraclePow, sqrtVariance, oracleCost, oracleTileCost, "
                       "pilotSpread, pilotSpreadRaw, pilotAuto)");
    const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + scene;
    const glint::Image reference = glint::readExr(glint::bench::sceneReference(scene)).color();
    glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
    const int w = renderer.scene().width(), h = renderer.scene().height();
    const glint::pipeline::AutoRun autoRun =
        glint::pipeline::autoRun({}, glint::denoise::AutoQuality::Balanced);
    auto settingsFor = [&](unsigned long long s) {
        glint::render::Settings settings = renderer.scene().settings();
        settings.seed = s;
        settings.threads = threads;
        settings.spp = spp;
        settings.timeLimit = 0.0;
        settings.halfBuffers = true;
        return settings;
    };
    auto finish = [&](glint::render::RenderResult rendered) {
        Run run;
        run.frame = std::move(rendered.frame);
        run.stats = rendered.stats;
        run.rawRelMse = mean(relativeErrors(run.frame.color(), reference));
        const glint::pipeline::Denoised d = glint::pipeline::denoiseFrame(run.frame, autoRun);
        run.errors = relativeErrors(d.result.composite, reference);
        run.relMse = mean(run.errors);
        return run;
    };

    // 1. Uniform: where its error lives.
    const Run uniform = finish(renderer.render(settingsFor(seed)));
    std::printf("scene\tseed\tspp\traw\tdenoised\ttop1\ttop10\ttop25\tboundDenoised\tboundRaw\n");
    std::printf("%s\t%llu\t%d\t%.4g\t%.4g\t%.3f\t%.3f\t%.3f\t%.3f\t%.3f\n", scene.c_str(), seed,
                spp, uniform.rawRelMse, uniform.relMse, topShare(uniform.errors, 0.01),
                topShare(uniform.errors, 0.10), topShare(uniform.errors, 0.25),
                allocationBound(uniform.errors),
                allocationBound(relativeErrors(uniform.frame.color(), reference)));
    if (!mapOut.empty()) {
        // Grey, so that glint-image convert --false-color shows it.
        glint::Image map(w, h, 3);
        for (std::size_t i = 0; i < uniform.errors.size(); ++i)
            for (int c = 0; c < 3; ++c)
                map.data()[3 * i + std::size_t(c)] = float(uniform.errors[i]);
        glint::writeImage(map, mapOut);
    }

    auto targetsFrom = [&](const std::vector<double>& weight) {
        return glint::bench::targetsFrom(weight, spp, pilot);
    };
    auto renderTargets = [&](const std::vector<int>& target) {
        return glint::bench::renderTargets(renderer, settingsFor(seed), target, pilot);
    };

    // 2. The oracle's samples per pixel, from another realisation's true error, blurred.
    const Run other = finish(renderer.render(settingsFor(mapSeed)));
    const std::vector<double> blurred = glint::bench::boxBlur(other.errors, w, h, 2);
    // The renderer's own information instead of the reference: n_i ∝ the relative standard
    // deviation of a sample, √(v_i n_i) / √(μ_i² + 0.01) from the other seed's noisy frame (the
    // allocation that minimises the noisy image's relMSE; a threshold on the error, Cycles',
    // gives n_i ∝ its square).
    // A frame's squared relative spread of a sample per pixel, v_i n_i / (μ_i² + 0.01), mean over
    // the channels.
    auto squaredSpread = [&](const glint::FrameBuffers& frame) {
        const glint::Image& mu = frame.color();
        const glint::Image& var = frame.layer(glint::Layer::Variance);
        const glint::Image& n = frame.layer(glint::Layer::SampleCount);
        glint::Image out(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double sum = 0.0;
                for (int c = 0; c < 3; ++c)
                    sum += double(var(x, y, c)) * n(x, y, 0) /
                           (double(mu(x, y, c)) * mu(x, y, c) + 0.01);
                out(x, y, 0) = float(sum / 3.0);
            }
        return out;
    };
    std::vector<double> spread(blurred.size(), 0.0);
    {
        const glint::Image s2 = squaredSpread(other.frame);
        for (std::size_t i = 0; i < spread.size(); ++i) spread[i] = std::sqrt(double(s2.data()[i]));
    }
    // The same allocation from this render's own start: the seed's first --pilot samples of every
    // pixel (which the adaptive render then continues), their relative spread box-averaged over
    // 5 × 5 (pilotSpread) or not (pilotSpreadRaw): what a renderer could steer by with nothing but
    // its own uniform start.
    auto pilotSpread = [&](int radius) {
        glint::render::Settings s = settingsFor(seed);
        s.spp = pilot;
        const glint::Image smoothed =
            glint::boxMean(squaredSpread(renderer.render(s).frame), radius);
        std::vector<double> weight(blurred.size());
        for (std::size_t i = 0; i < weight.size(); ++i)
            weight[i] = std::pow(std::max(0.0, double(smoothed.data()[i])), exponent);
        return weight;
    };
    // The oracle's allocation with auto's own estimate of its error instead of the true one: one
    // auto (balanced) on the render's own first --pilot samples, n_i ∝ √(its estimated relative
    // error) (pilotAuto; the auto's seconds are printed, not counted in the rays).
    auto pilotAuto = [&] {
        glint::render::Settings s = settingsFor(seed);
        s.spp = pilot;
        const glint::pipeline::Denoised d =
            glint::pipeline::denoiseFrame(renderer.render(s).frame, autoRun);
        std::printf("pilotAuto\tauto on the start took %.2f s\n", d.seconds);
        std::vector<double> weight(blurred.size());
        for (std::size_t i = 0; i < weight.size(); ++i)
            weight[i] = std::sqrt(std::max(0.0, double(d.relative.data()[i])));
        return weight;
    };
    // A sample's cost per pixel: rays per sample of each block rendered alone (the map seed).
    auto costMap = [&] {
        std::vector<double> cost(blurred.size(), 1.0);
        for (int y0 = 0; y0 < h; y0 += costBlock)
            for (int x0 = 0; x0 < w; x0 += costBlock) {
                glint::render::Settings s = settingsFor(mapSeed);
                s.spp = pilot;
                s.region =
                    glint::Rect{x0, std::min(x0 + costBlock, w), y0, std::min(y0 + costBlock, h)};
                const glint::render::RenderStats stats = renderer.render(s).stats;
                const double c =
                    double(stats.rays) / double(std::max<std::uint64_t>(stats.samples, 1));
                for (int y = s.region->y0; y < s.region->y1; ++y)
                    for (int x = s.region->x0; x < s.region->x1; ++x)
                        cost[std::size_t(y) * w + x] = c;
            }
        double lo = cost[0], hi = cost[0];
        for (double c : cost) lo = std::min(lo, c), hi = std::max(hi, c);
        // Where the error is: the cost of a pixel weighted by its (map's) error.
        double weighted = 0.0, errorSum = 0.0;
        for (std::size_t i = 0; i < cost.size(); ++i)
            weighted += blurred[i] * cost[i], errorSum += blurred[i];
        std::printf(
            "cost\t%.2f mean rays/sample, %.2f to %.2f over %d^2 blocks, %.2f weighted by "
            "the error\n",
            mean(cost), lo, hi, costBlock, weighted / errorSum);
        return cost;
    };
    // The same cost averaged over the renderer's tiles (every pixel took the same samples).
    auto perTile = [&](const std::vector<double>& cost) {
        std::vector<double> tileCost(cost.size(), 1.0);
        const int tile = renderer.scene().settings().tileSize;
        for (int y0 = 0; y0 < h; y0 += tile)
            for (int x0 = 0; x0 < w; x0 += tile) {
                const int x1 = std::min(x0 + tile, w), y1 = std::min(y0 + tile, h);
                double sum = 0.0;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) sum += cost[std::size_t(y) * w + x];
                const double c = sum / double((x1 - x0) * (y1 - y0));
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) tileCost[std::size_t(y) * w + x] = c;
            }
        return tileCost;
    };
    std::vector<double> cost;
    // n_i ∝ (e_i / c_i)^exponent (c_i = 1: cost-blind).
    auto allocation = [&](const std::vector<double>* c, double power) {
        std::vector<double> weight(blurred.size());
        for (std::size_t i = 0; i < blurred.size(); ++i)
            weight[i] = std::pow(blurred[i] / (c ? (*c)[i] : 1.0), power);
        return weight;
    };

    // Each way, then uniform at its rays (equal time, rays being the time: the rate per ray of
    // adaptive and uniform passes agrees, bench_adaptive_throughput).
    auto meanSpp = [&](const Run& r) { return double(r.stats.samples) / (double(w) * h); };
    std::printf(
        "way\tmeanSpp\traysPerSample\trays\traw\tdenoised\tchange\tuniformAtRaysSpp\t"
        "uniformAtRays\tvsEqualRays\n");
    std::printf("uniform\t%.1f\t%.2f\t%llu\t%.4g\t%.4g\t+0 %%\t\t\t\n", meanSpp(uniform),
                double(uniform.stats.rays) / double(uniform.stats.samples),
                (unsigned long long)uniform.stats.rays, uniform.rawRelMse, uniform.relMse);
    for (const std::string& way : glint::bench::splitList(ways)) {
        std::vector<double> weight;
        if (way == "oracle")
            weight = allocation(nullptr, 0.5);
        else if (way == "oraclePow")
            weight = allocation(nullptr, exponent);
        else if (way == "sqrtVariance")
            weight = spread;
        else if (way == "pilotAuto")
            weight = pilotAuto();
        else if (way == "pilotSpread" || way == "pilotSpreadRaw")
            weight = pilotSpread(way == "pilotSpread" ? 2 : 0);
        else {  // oracleCost, oracleTileCost
            if (cost.empty()) cost = costMap();
            const std::vector<double> c = way == "oracleCost" ? cost : perTile(cost);
            weight = allocation(&c, exponent);
        }
        const std::vector<int> target = targetsFrom(weight);
        std::printf("%s\t%.1f %% of the pixels at the pilot\n", way.c_str(),
                    100.0 * double(std::count(target.begin(), target.end(), pilot)) /
                        double(target.size()));
        if (allocationsOnly) continue;
        const Run r = finish(renderTargets(target));
        glint::render::Settings equalRays = settingsFor(seed);
        equalRays.spp =
            int(std::lround(double(spp) * double(r.stats.rays) / double(uniform.stats.rays)));
        const Run u = finish(renderer.render(equalRays));
        std::printf("%s\t%.1f\t%.2f\t%llu\t%.4g\t%.4g\t%+.0f %%\t%d\t%.4g\t%+.0f %%\n", way.c_str(),
                    meanSpp(r), double(r.stats.rays) / double(r.stats.samples),
                    (unsigned long long)r.stats.rays, r.rawRelMse, r.relMse,
                    100.0 * (r.relMse / uniform.relMse - 1.0), equalRays.spp, u.relMse,
                    100.0 * (r.relMse / u.relMse - 1.0));
        std::fflush(stdout);
    }
    return 0;
}
