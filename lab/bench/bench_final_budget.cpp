// What the final auto of glint-final costs by plan, and what glint-final's cost model predicts for
// it (docs/lab/race.md, "Keeping the time limit"). For a rendered frame with half buffers: the
// probe as glint-final makes it (cheapestPlan() on the centred kProbeSide² crop, the fastest of
// kProbeRuns runs) calibrates an AutoCost, then each plan of auto (a quality, a bank size,
// filters) is timed on the whole frame beside the model's prediction (the first default-bank run
// of the process with its cold start, as glint-final's final auto). The probe is also timed on a
// second crop side (--side2) and each plan on the crop (--crop; 0: none), so that other models can
// be fitted offline. --warmup PLAN runs PLAN once on the probe's crop first, as glint-final's
// warm-up (warmupPlan(): fast:1) pays the default bank's cold start: a row of its own, and the
// plans after it warm. One TSV row per plan and run; the probe's times repeat on every row.
//   build/bin/bench_final_budget FRAME.exr [--plans balanced,fast,fast:8,fast:1,cheapest]
//       [--crop 64] [--side2 32] [--runs 2] [--threads 2] [--label NAME] [--warmup fast:1]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include "glint/image/io.h"
#include "glint/pipeline/final_render.h"
#include "glint/pipeline/refresh.h"
#include "glint/pipeline/time_budget.h"

#include "bench_options.h"

namespace {

using glint::pipeline::AutoPlan;

std::vector<std::string> split(const std::string& text, char by) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, by);) out.push_back(item);
    return out;
}

/// "balanced", "fast:8", "fast:1:cross-bilateral+guided", or "cheapest" (cheapestPlan()).
AutoPlan parsePlan(const std::string& text) {
    if (text == "cheapest") return glint::pipeline::cheapestPlan();
    const std::vector<std::string> parts = split(text, ':');
    AutoPlan plan;
    plan.quality = glint::denoise::parseAutoQuality(parts[0]);
    if (parts.size() > 1) plan.bankSize = std::stoi(parts[1]);
    if (parts.size() > 2) plan.filters = split(parts[2], '+');
    return plan;
}

/// Seconds of one run of `plan` on `frame`.
double timed(const glint::FrameBuffers& frame, const AutoPlan& plan) {
    return glint::pipeline::denoiseFrame(
               frame, glint::pipeline::autoRun({}, plan.quality, plan.bankSize, plan.filters))
        .seconds;
}

/// The fastest of glint-final's probe runs of cheapestPlan() on `probe`.
double probeSeconds(const glint::FrameBuffers& probe) {
    double fastest = 0.0;
    for (int run = 0; run < glint::pipeline::kProbeRuns; ++run) {
        const double seconds = timed(probe, glint::pipeline::cheapestPlan());
        fastest = run == 0 ? seconds : std::min(fastest, seconds);
    }
    return fastest;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "--help") {
        std::fprintf(
            stderr,
            "usage: bench_final_budget FRAME.exr [--plans balanced,fast,fast:8,fast:1,"
            "cheapest] [--crop N] [--side2 N] [--runs N] [--threads T] [--label NAME]\n"
            "  [--warmup PLAN]\n"
            "  rows: label, size, plan, run, cold (the process's first default-bank run),\n"
            "  weight, seconds (whole frame), predicted (glint-final's model from its "
            "probe),\n"
            "  probe (cheapest on kProbeSide², fastest of kProbeRuns), probe2 (on "
            "side2²),\n"
            "  cropSeconds (the plan on crop²)\n");
        return argc < 2 ? 2 : 0;
    }
    const std::string path = argv[1];
    std::string plans = "balanced,fast,fast:8,fast:1,cheapest";
    std::string label = path;
    int crop = 64, side2 = 32, runs = 2, threads = 2, study = 0;
    std::string warmup;
    glint::bench::OptionTable options;
    options.bind("--plans", plans);
    options.bind("--crop", crop);
    options.bind("--side2", side2);
    options.bind("--runs", runs);
    options.bind("--threads", threads);
    options.bind("--label", label);
    options.bind("--study", study);
    options.bind("--warmup", warmup);
    if (const int rc = options.parse("bench_final_budget", argc, argv, 2)) return rc;
    tbb::global_control pool(tbb::global_control::max_allowed_parallelism, threads);
    const glint::FrameBuffers frame = glint::readExr(path);
    const glint::FrameBuffers probe =
        glint::pipeline::probeFrame(frame, glint::pipeline::kProbeSide);
    const glint::FrameBuffers probe2 = glint::pipeline::probeFrame(frame, side2);
    // --crop 0: no plan on a crop (probeFrame of side 0 would be empty).
    const glint::FrameBuffers cropped =
        crop > 0 ? glint::pipeline::probeFrame(frame, crop) : glint::FrameBuffers();
    const double pixels = double(frame.width()) * double(frame.height());
    const double probePixels = double(probe.width()) * double(probe.height());
    if (study > 0) {
        // Probes for the cost model: cheapestPlan() on crops of the frame, the fastest of
        // kProbeRuns runs of each, `study` times: the centred 64² (glint-final's), four 32² at the
        // quadrants' centres, the centred 128², and the whole frame once.
        std::printf("label\tprobe\tpixels\trun\tseconds\n");
        auto at = [&](int side, double fx, double fy) {
            const int x0 = std::clamp(int(fx * frame.width()) - side / 2, 0, frame.width() - side);
            const int y0 =
                std::clamp(int(fy * frame.height()) - side / 2, 0, frame.height() - side);
            glint::FrameBuffers c(side, side);
            c.metadata() = frame.metadata();
            for (int l = 0; l < glint::kLayerCount; ++l)
                if (const glint::Image* layer = frame.find(glint::Layer(l)))
                    c.set(glint::Layer(l), layer->crop({x0, x0 + side, y0, y0 + side}));
            return c;
        };
        const std::vector<glint::FrameBuffers> quads{at(32, 0.25, 0.25), at(32, 0.75, 0.25),
                                                     at(32, 0.25, 0.75), at(32, 0.75, 0.75)};
        const glint::FrameBuffers c128 = glint::pipeline::probeFrame(frame, 128);
        for (int run = 0; run < study; ++run) {
            double quad = 0.0;
            for (const glint::FrameBuffers& q : quads) quad += probeSeconds(q);
            std::printf("%s\tcentre64\t4096\t%d\t%.5f\n", label.c_str(), run, probeSeconds(probe));
            std::printf("%s\tquads32\t4096\t%d\t%.5f\n", label.c_str(), run, quad);
            std::printf("%s\tcentre128\t16384\t%d\t%.5f\n", label.c_str(), run, probeSeconds(c128));
        }
        std::printf("%s\tframe\t%.0f\t0\t%.5f\n", label.c_str(), pixels,
                    timed(frame, glint::pipeline::cheapestPlan()));
        return 0;
    }
    std::printf(
        "label\tw\th\tplan\trun\tcold\tweight\tseconds\tpredicted\tprobe\tprobe2\tcropSeconds\n");
    // One cost model for the process, as glint-final's: the first default bank pays the cold start.
    bool warm = false;
    if (!warmup.empty()) {
        const AutoPlan plan = parsePlan(warmup);
        std::printf("%s\t%d\t%d\twarmup %s\t0\t1\t%.3f\t%.4f\t0\t0\t0\t0\n", label.c_str(),
                    probe.width(), probe.height(), warmup.c_str(),
                    glint::pipeline::planWeight(plan), timed(probe, plan));
        warm = plan.filters.empty();
    }
    for (int run = 0; run < runs; ++run) {
        const double p = probeSeconds(probe), p2 = probeSeconds(probe2);
        glint::pipeline::AutoCost cost;
        cost.probed(probePixels, p);
        for (const std::string& text : split(plans, ',')) {
            const AutoPlan plan = parsePlan(text);
            const bool cold = plan.filters.empty() && !warm;
            if (warm) cost.ran(AutoPlan{});
            const double predicted = cost.seconds(plan, pixels);
            const double seconds = timed(frame, plan);
            warm = warm || plan.filters.empty();
            const double cropSeconds = crop > 0 ? timed(cropped, plan) : 0.0;
            std::printf("%s\t%d\t%d\t%s\t%d\t%d\t%.3f\t%.4f\t%.4f\t%.5f\t%.5f\t%.4f\n",
                        label.c_str(), frame.width(), frame.height(), text.c_str(), run, int(cold),
                        glint::pipeline::planWeight(plan), seconds, predicted, p, p2, cropSeconds);
            std::fflush(stdout);
        }
    }
    return 0;
}
