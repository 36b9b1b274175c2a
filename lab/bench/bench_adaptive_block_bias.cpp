// The block-scale bias of the studio's Keep Refining (docs/lab/adaptive-bias.md, "The studio's
// block-scale bias"): the raw colour of the studio's refining render (ProgressiveRender's
// settings: adaptive with half buffers from the bar's spp, the map from Refresher::provisional at
// the first adaptive pass, auto's maps after it with --steer auto) averaged over many seeds, on
// --block² block means, against uniform renders of other seeds. Per steering and mean-spp
// checkpoint: the whole frame's bias with its standard error, the bias's block relMSE with the
// seeds' noise taken off (what bench_studio_progressive's relMSE sees once the noise is gone), one
// image's block noise, the blocks' mean z² (1 without bias), and for the pixels refined the seeds'
// spread over the film's variance of the mean (above 1 if a pass repeated samples); then the
// cost: the share of the pixels still at the start ("frozen"), the most samples a pixel took
// (mean over seeds) and the seconds to the checkpoint. For each,
// the whole image, the even half (samples no decision saw when the map came from half B) and, with
// provisional-half, "held": every sample but half B's at the map's making (the ones that decided).
// --uniform-spp 0 reads the control at the checkpoints (the first uniform pass that reaches each:
// 32 for 20–32, then multiples of 64), so control and steered frames carry about the same
// samples. Remedies tried on the maps, bench-side: --floor F raises every weight of a map to at
// least F (auto's maps: F times the schedule's scale √(spp / spp at the first refresh)), so that no
// pixel stays frozen on the samples that chose it. (Since 2026-11-29 night the provisional map
// reads half B alone when the frame has it: --steer provisional and auto measure that.)
//   build/bin/bench_adaptive_block_bias --scene DIR/scene.json (bench_studio_progressive
//       --write-scene DIR) [--size 128] [--start 16] [--seeds 24] [--first-seed 1]
//       [--uniform-spp 64] [--checkpoints 20,24,32,48] [--steer provisional|provisional-half|
//       random|auto|threshold|uniform] [--floor 0]
//       [--threads 2] [--block 8]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/frame_buffers.h"
#include "glint/pipeline/refresh.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "model/progressive_render.h"

#include "bench_options.h"

using namespace glint;

namespace {

/// Sums over seeds of one estimator's block means and whole-frame mean, and per pixel of its
/// colour and its variance layer (for the spread against the film's own variance).
struct Accum {
    int seeds = 0;
    double spp = 0.0, frame1 = 0.0, frame2 = 0.0;
    /// Sums over seeds of the share of pixels at the start, the most samples a pixel took and
    /// the seconds to the checkpoint.
    double frozen = 0.0, most = 0.0, seconds = 0.0;
    std::vector<double> b1, b2, p1, p2, pv, n;

    void add(const Image& colour, const Image& variance, const Image& count, int block,
             int start = 0, double at = 0.0) {
        const int bw = colour.width() / block, bh = colour.height() / block;
        const std::size_t pixels = std::size_t(colour.width()) * std::size_t(colour.height());
        if (b1.empty()) {
            b1.assign(std::size_t(bw) * bh * 3, 0.0), b2 = b1;
            p1.assign(pixels * 3, 0.0), p2 = p1, pv = p1, n.assign(pixels, 0.0);
        }
        std::vector<double> means(b1.size(), 0.0);
        double frame = 0.0;
        for (int y = 0; y < bh * block; ++y)
            for (int x = 0; x < bw * block; ++x)
                for (int c = 0; c < 3; ++c) {
                    const double v = colour(x, y, c);
                    means[(std::size_t(y / block) * bw + x / block) * 3 + c] += v;
                    frame += v;
                }
        for (std::size_t i = 0; i < means.size(); ++i) {
            const double m = means[i] / double(block * block);
            b1[i] += m, b2[i] += m * m;
        }
        frame /= double(bw * bh * block * block * 3);
        frame1 += frame, frame2 += frame * frame;
        double total = 0.0, still = 0.0, top = 0.0;
        for (std::size_t i = 0; i < pixels; ++i) {
            n[i] += count.data()[i];
            total += count.data()[i];
            still += count.data()[i] <= float(start);
            top = std::max(top, double(count.data()[i]));
            for (int c = 0; c < 3; ++c) {
                const double v = colour.data()[3 * i + c];
                p1[3 * i + c] += v, p2[3 * i + c] += v * v;
                pv[3 * i + c] += variance.data()[3 * i + c];
            }
        }
        spp += total / double(pixels);
        frozen += still / double(pixels), most += top, seconds += at;
        ++seeds;
    }
    double blockMean(std::size_t i) const { return b1[i] / seeds; }
    /// The variance of one seed's block mean (the seeds' spread).
    double blockVar(std::size_t i) const {
        return std::max(0.0, (b2[i] - b1[i] * b1[i] / seeds) / (seeds - 1));
    }
};

/// Prints `a` against the uniform control `u`.
void report(const char* steer, const char* estimator, double checkpoint, const Accum& a,
            const Accum& u, int start) {
    const double S = a.seeds, fa = a.frame1 / S, fu = u.frame1 / u.seeds;
    const double va = (a.frame2 - a.frame1 * a.frame1 / S) / (S - 1) / S;
    const double vu = (u.frame2 - u.frame1 * u.frame1 / u.seeds) / (u.seeds - 1) / u.seeds;
    const double bias = (fa - fu) / fu, se = std::sqrt(va + vu) / fu;
    double biasRel = 0.0, noiseRel = 0.0, z2 = 0.0;
    int outliers = 0;
    for (std::size_t i = 0; i < a.b1.size(); ++i) {
        const double r = u.blockMean(i), floor = r * r + 0.01;
        const double d = a.blockMean(i) - r;
        const double var = a.blockVar(i) / S + u.blockVar(i) / u.seeds;
        biasRel += (d * d - var) / floor;
        noiseRel += a.blockVar(i) / floor;
        const double z = d / std::sqrt(std::max(var, 1e-30));
        z2 += z * z;
        outliers += std::abs(z) > 3.29;
    }
    const double blocks = double(a.b1.size());
    // The seeds' spread of each refined pixel (more samples than the start in every seed's mean)
    // over the film's variance of the mean there.
    double spread = 0.0, film = 0.0;
    for (std::size_t i = 0; i < a.n.size(); ++i) {
        if (a.n[i] / S < start + 1.0) continue;
        for (int c = 0; c < 3; ++c) {
            const std::size_t k = 3 * i + c;
            spread += (a.p2[k] - a.p1[k] * a.p1[k] / S) / (S - 1);
            film += a.pv[k] / S;
        }
    }
    std::printf(
        "%-17s %-6s %5.1f %6.2f %+8.3f%% %6.3f%% %+6.1f %10.3g %10.3g %7.3f %7.4f %7.3f "
        "%6.3f %6.0f %7.2f\n",
        steer, estimator, checkpoint, a.spp / S, 100.0 * bias, 100.0 * se, bias / se,
        biasRel / blocks, noiseRel / blocks, z2 / blocks, double(outliers) / blocks,
        film > 0.0 ? spread / film : 0.0, a.frozen / S, a.most / S, a.seconds / S);
}

}  // namespace

int main(int argc, char** argv) {
    std::string scenePath, steer = "provisional", checkpointList = "20,24,32,48";
    int size = 128, start = 16, seeds = 24, firstSeed = 1, uniformSpp = 64, threads = 2, block = 8;
    double floor = 0.0;
    bench::OptionTable options;
    options.bind("--scene", scenePath);
    options.bind("--steer", steer);
    options.bind("--checkpoints", checkpointList);
    options.bind("--size", size);
    options.bind("--start", start);
    options.bind("--seeds", seeds);
    options.bind("--first-seed", firstSeed);
    options.bind("--floor", floor);
    options.bind("--uniform-spp", uniformSpp);
    options.bind("--threads", threads);
    options.bind("--block", block);
    if (const int rc = options.parse("bench_adaptive_block_bias", argc, argv)) return rc;
    if (scenePath.empty() || seeds < 2 || size % block != 0 || uniformSpp < 0 || floor < 0.0) {
        std::fprintf(stderr,
                     "bench_adaptive_block_bias: --scene, --seeds >= 2, --size a "
                     "multiple of --block, --uniform-spp and --floor at least 0\n");
        return 2;
    }
    const std::vector<std::string> steers = {"provisional", "provisional-half", "random",
                                             "auto",        "threshold",        "uniform"};
    if (std::find(steers.begin(), steers.end(), steer) == steers.end()) {
        std::fprintf(stderr, "bench_adaptive_block_bias: unknown --steer %s\n", steer.c_str());
        return 2;
    }
    // The checkpoints, and the studio's scene (bench_studio_progressive --write-scene) at
    // --size²: a bad value or file ends the run with one line.
    std::vector<double> checkpoints;
    std::optional<render::Renderer> loaded;
    try {
        for (const std::string& c : bench::splitList(checkpointList))
            checkpoints.push_back(std::stod(c));
        std::ifstream in(scenePath);
        std::stringstream text;
        text << in.rdbuf();
        nlohmann::json json = nlohmann::json::parse(text.str());
        json["film"]["width"] = size;
        json["film"]["height"] = size;
        loaded.emplace(render::parseScene(json.dump(), scenePath));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_adaptive_block_bias: %s: %s\n", scenePath.c_str(), e.what());
        return 2;
    }
    render::Renderer& renderer = *loaded;
    render::Settings bar = renderer.scene().settings();
    bar.threads = threads;
    bar.spp = start;

    // The uniform control: other seeds, --uniform-spp (0: read at the checkpoints).
    std::vector<Accum> uniform(uniformSpp > 0 ? 1 : checkpoints.size());
    for (int s = 0; s < seeds; ++s) {
        render::Settings u = bar;
        u.seed = 100000 + std::uint64_t(firstSeed - 1 + s);
        u.spp = uniformSpp > 0 ? uniformSpp : int(std::ceil(checkpoints.back()));
        std::size_t next = 0;
        render::Callbacks cb;
        cb.passDone = [&](int, const FrameBuffers& frame) {
            const double spp = pipeline::meanSpp(frame);
            while (uniformSpp == 0 && next < checkpoints.size() && spp >= checkpoints[next])
                uniform[next++].add(frame.color(), frame.layer(Layer::Variance),
                                    frame.layer(Layer::SampleCount), block);
        };
        const FrameBuffers f = renderer.render(u, cb).frame;
        if (uniformSpp > 0)
            uniform[0].add(f.color(), f.layer(Layer::Variance), f.layer(Layer::SampleCount), block);
    }
    auto control = [&](std::size_t k) -> const Accum& { return uniform[uniformSpp > 0 ? 0 : k]; };

    // The studio's refining render (ProgressiveRender::refining), steered as --steer says.
    std::vector<Accum> whole(checkpoints.size()), even(checkpoints.size()),
        held(checkpoints.size());
    // The frames of the seeds that converged before the last checkpoint, and the checkpoints
    // every seed reached.
    Accum ended;
    std::size_t reached = checkpoints.size();
    for (int s = 0; s < seeds; ++s) {
        render::Settings r = studio::ProgressiveRender::refining(bar);
        r.seed = std::uint64_t(firstSeed + s);
        pipeline::Refresher refresher(studio::ProgressiveRender::refreshOptions());
        bool first = true;
        std::size_t next = 0;
        const auto begun = std::chrono::steady_clock::now();
        // --floor: every weight of the map at least floor (auto's maps: times the schedule's
        // scale, as the Refresher scales them).
        double startSpp = 0.0;
        auto floored = [&](std::shared_ptr<const Image> map,
                           double scale) -> std::shared_ptr<const Image> {
            if (!map || floor <= 0.0) return map;
            auto out = std::make_shared<Image>(*map);
            for (float& v : out->data()) v = std::max(v, float(floor * scale));
            return out;
        };
        // A refresh's map (none: none), floored at the schedule's scale.
        auto scheduled = [&](std::shared_ptr<const Image> map) -> std::shared_ptr<const Image> {
            if (!map) return map;
            if (refresher.refreshes() == 1) startSpp = refresher.last()->meanSpp;
            return floored(map, std::sqrt(refresher.last()->meanSpp / startSpp));
        };
        // Half B at the map's making (provisional-half): the samples that decided.
        std::optional<FrameBuffers> decided;
        render::Callbacks cb;
        cb.importance = [&](int, const FrameBuffers& frame) -> std::shared_ptr<const Image> {
            if (steer == "auto") {
                if (first) {
                    first = false;
                    return floored(refresher.provisional(frame), 1.0);
                }
                return scheduled(refresher.importance(frame));
            }
            // threshold: no map, the renderer's own threshold on half B decides alone.
            if (!first || steer == "threshold") return nullptr;
            first = false;
            if (steer == "provisional") return floored(refresher.provisional(frame), 1.0);
            if (steer == "provisional-half") {
                decided = splitHalves(frame).second;
                return floored(refresher.provisional(*decided), 1.0);
            }
            // random: the same share of pixels, chosen by a fixed draw that never sees a sample.
            auto map = std::make_shared<Image>(frame.width(), frame.height(), 1);
            std::mt19937 pick(12345);
            for (float& v : map->data()) v = pick() % 10 == 0 ? 1.0f : 0.0f;
            return map;
        };
        // As the studio: with no pixel open, one more refresh of the grown frame (its map goes
        // on where it says; none: the render ends).
        if (steer == "auto")
            cb.converged = [&](int, const FrameBuffers& frame) {
                return scheduled(refresher.converged(frame));
            };
        cb.passDone = [&](int, const FrameBuffers& frame) {
            const double spp = pipeline::meanSpp(frame);
            const double at =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
            while (next < checkpoints.size() && spp >= checkpoints[next]) {
                whole[next].add(frame.color(), frame.layer(Layer::Variance),
                                frame.layer(Layer::SampleCount), block, start, at);
                const FrameBuffers a = splitHalves(frame).first;
                even[next].add(a.color(), a.layer(Layer::Variance), a.layer(Layer::SampleCount),
                               block, (start + 1) / 2, at);
                if (decided) {
                    // Every sample but those that decided: (n·mean − n_B0·mean_B0) / (n − n_B0).
                    Image colour = frame.color(), count = frame.layer(Layer::SampleCount);
                    const Image& c0 = decided->color();
                    const Image& n0 = decided->layer(Layer::SampleCount);
                    for (std::size_t i = 0; i < count.data().size(); ++i) {
                        const float n = count.data()[i], m = n - n0.data()[i];
                        for (std::size_t c = 0; c < 3; ++c)
                            colour.data()[3 * i + c] = (n * colour.data()[3 * i + c] -
                                                        n0.data()[i] * c0.data()[3 * i + c]) /
                                                       m;
                        count.data()[i] = m;
                    }
                    held[next].add(colour, frame.layer(Layer::Variance), count, block, 0, at);
                }
                ++next;
            }
        };
        cb.cancel = [&] { return next >= checkpoints.size(); };
        if (steer == "uniform") {
            // The control's calibration: a uniform render of other seeds, read at the same
            // checkpoints.
            r.adaptive = false;
            r.minSpp = 0;
            r.spp = int(std::ceil(checkpoints.back()));
        }
        const FrameBuffers last = renderer.render(r, cb).frame;
        if (next < checkpoints.size()) {
            // Converged (no pixel open) before the last checkpoint: the frame it ended on.
            const double at =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - begun).count();
            ended.add(last.color(), last.layer(Layer::Variance), last.layer(Layer::SampleCount),
                      block, start, at);
            std::fprintf(stderr, "seed %d converged at checkpoint %zu\n", firstSeed + s, next);
            reached = std::min(reached, next);
        }
    }
    std::printf(
        "# %d^2 studio scene, start %d spp, seeds %d-%d, uniform control %d spp (0: at the "
        "checkpoints), floor %g, %dx%d blocks\n",
        size, start, firstSeed, firstSeed + seeds - 1, uniformSpp, floor, block, block);
    std::printf("%-17s %-6s %5s %6s %9s %7s %6s %10s %10s %7s %7s %7s %6s %6s %7s\n", "steer",
                "image", "at", "spp", "bias", "se", "z", "biasRelMSE", "noiseRelMSE", "meanZ2",
                ">3.29", "spread", "frozen", "most", "seconds");
    for (std::size_t k = 0; k < reached; ++k) {
        if (uniformSpp == 0 || k == 0)
            report(steer.c_str(), "unif", uniformSpp > 0 ? 0 : checkpoints[k], control(k),
                   control(k), start);
        report(steer.c_str(), "whole", checkpoints[k], whole[k], control(k), start);
        report(steer.c_str(), "even", checkpoints[k], even[k], control(k), start);
        if (held[k].seeds > 1)
            report(steer.c_str(), "held", checkpoints[k], held[k], control(k), start);
    }
    // Every seed converged: the frames they ended on, against the last control.
    if (ended.seeds == seeds) report(steer.c_str(), "end", 0, ended, uniform.back(), start);
    return 0;
}
