// What the final auto of glint-final costs by plan (docs/lab/race.md, "Keeping the time limit"):
// for a rendered frame with half buffers, each plan of auto (a quality, a bank size, filters) timed
// on the whole frame and on a centred crop, alternating, so that the cost model of
// glint/pipeline/time_budget.h (AutoCost: seconds ∝ pixels × the plan's weight, calibrated by a
// probe on a crop) can be checked against the measured times. One TSV row per plan and run.
//   build/bin/bench_final_budget FRAME.exr [--plans
//   fast,balanced,best,fast:8,fast:1:cross-bilateral]
//                                [--crop 64] [--runs 2] [--threads 2]
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "glint/image/io.h"
#include "glint/pipeline/refresh.h"
#include "glint/pipeline/time_budget.h"

#include "bench_options.h"

namespace {

std::vector<std::string> split(const std::string& text, char by) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, by);) out.push_back(item);
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr,
                     "usage: bench_final_budget FRAME.exr [--plans …] [--crop N] "
                     "[--runs N] [--threads T]\n");
        return 2;
    }
    const std::string path = argv[1];
    std::string plans = "fast,balanced,best,fast:8,fast:1,fast:1:cross-bilateral,fast:1:guided";
    int crop = 64, runs = 2, threads = 2;
    glint::bench::OptionTable options;
    options.bind("--plans", plans);
    options.bind("--crop", crop);
    options.bind("--runs", runs);
    options.bind("--threads", threads);
    if (const int rc = options.parse("bench_final_budget", argc, argv, 2)) return rc;
    tbb::global_control pool(tbb::global_control::max_allowed_parallelism, threads);
    const glint::FrameBuffers frame = glint::readExr(path);
    const glint::FrameBuffers probe = glint::pipeline::probeFrame(frame, crop);
    const double pixels = double(frame.width()) * double(frame.height());
    const double probePixels = double(probe.width()) * double(probe.height());
    std::printf("plan\trun\tweight\tseconds\tprobeSeconds\tpredicted\n");
    for (int run = 0; run < runs; ++run)
        for (const std::string& text : split(plans, ',')) {
            const std::vector<std::string> parts = split(text, ':');
            glint::pipeline::AutoPlan plan;
            plan.quality = glint::denoise::parseAutoQuality(parts[0]);
            if (parts.size() > 1) plan.bankSize = std::stoi(parts[1]);
            if (parts.size() > 2) plan.filters = split(parts[2], '+');
            const glint::pipeline::AutoRun how =
                glint::pipeline::autoRun({}, plan.quality, plan.bankSize, plan.filters);
            const double probeSeconds = glint::pipeline::denoiseFrame(probe, how).seconds;
            const double seconds = glint::pipeline::denoiseFrame(frame, how).seconds;
            glint::pipeline::AutoCost cost;
            cost.calibrate(plan, probePixels, probeSeconds);
            std::printf("%s\t%d\t%.3f\t%.3f\t%.3f\t%.3f\n", text.c_str(), run,
                        glint::pipeline::planWeight(plan), seconds, probeSeconds,
                        cost.seconds(plan, pixels));
            std::fflush(stdout);
        }
    return 0;
}
