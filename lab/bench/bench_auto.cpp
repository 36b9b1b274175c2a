// bench_auto: the auto start's speed (docs/lab/auto.md, "Speed"). Renders scenes/cornell at
// SIZE×SIZE (default 1024) with SPP samples (default 4; with half buffers for the halves
// estimator), then times on THREADS threads (default 2), REPS times each (best kept; the machine
// may be shared): the bank of MEMBERS Latin-hypercube members (plus the defaults, no cache), and
// autoComposite over it — SURE: one more application of every member to the perturbed input;
// halves: one (--one-sided 1) or two applications to the halves — maps, choice. Prints one JSON
// object with both times and their ratio (target: auto ≤ 2× the bank).
//   bench_auto [--estimator sure|halves] [--one-sided 0|1] [--shortlist 16 (0: all)]
//              [--space display|display-tangent|display-exact|linear] [--size 1024] [--spp 4]
//              [--threads 2] [--members 64] [--reps 3] [--feather R (default: the estimator's)]
//              [--stack K (default: the estimator's; 0: off)]
//              [--stack-features 1|0 (the stacking's albedo and normal regressors; default 1)]
//              [--retain-freed 1|0 (glint::retainFreedMemory, as glint-denoise; default 1)]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <string>

#include <nlohmann/json.hpp>

#include "bench_options.h"
#include "cornell_input.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/image/memory.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsOf(const std::function<void()>& fn) {
    const auto t0 = Clock::now();
    fn();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
    glint::bench::RenderBankOptions o;
    o.reps = 3;
    int oneSided = 0, shortlist = 16, feather = -1, stack = -1, stackFeatures = 1;
    std::string estimator = "sure";
    std::string space = "display";
    const int parsed = glint::bench::parseOptions(
        "bench_auto", argc, argv, [&](const std::string& a, const std::string& text) {
            if (a == "--estimator") {
                estimator = text;
                if (estimator != "sure" && estimator != "halves")
                    throw glint::bench::OptionError("--estimator is sure or halves");
                return true;
            }
            if (a == "--space") {
                try {
                    glint::denoise::parseParamValue(
                        *glint::denoise::findParam(glint::denoise::autoTuningSpecs(), "space"),
                        text);
                    space = text;
                } catch (const std::exception& e) {
                    throw glint::bench::OptionError("--space: " + std::string(e.what()));
                }
                return true;
            }
            const int v = glint::bench::intOption(a, text);
            if (a == "--one-sided")
                oneSided = v;
            else if (a == "--shortlist")
                shortlist = v;
            else if (a == "--feather")
                feather = v;
            else if (a == "--stack")
                stack = v;
            else if (a == "--stack-features")
                stackFeatures = v;
            else
                return o.take(a, v);
            return true;
        });
    if (parsed != 0) return parsed;
    const int size = o.size, spp = o.spp, threads = o.threads, members = o.members, reps = o.reps,
              retainFreed = o.retainFreed;
    const bool retained = retainFreed != 0 && glint::retainFreedMemory();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    // The input: cornell at size², a low spp (the render is not timed).
    const glint::FrameBuffers frame =
        glint::bench::cornellInput(size, spp, threads, estimator == "halves");

    glint::denoise::BankOptions options;
    options.size = members;
    options.seed = 1;
    const glint::denoise::AutoEstimator autoEstimator = estimator == "halves"
                                                            ? glint::denoise::AutoEstimator::Halves
                                                            : glint::denoise::AutoEstimator::Sure;
    if (feather < 0) feather = int(glint::denoise::autoTuningDefaults(autoEstimator).at("feather"));
    double bankSeconds = 1e30, autoSeconds = 1e30;
    std::size_t bankSize = 0, used = 0;
    int stacked = 0, features = 0;
    for (int r = 0; r < reps; ++r) {
        glint::denoise::FilterBank bank;
        bankSeconds = std::min(
            bankSeconds, secondsOf([&] { bank = glint::denoise::buildBank(frame, options); }));
        bankSize = bank.size();
        glint::denoise::AutoResult result;
        glint::denoise::AutoOptions ao;
        ao.estimator = autoEstimator;
        const auto& specs = glint::denoise::autoTuningSpecs();
        ao.tuning = {{"oneSided", oneSided != 0 ? 1 : 0},
                     {"space", glint::denoise::parseParamValue(
                                   *glint::denoise::findParam(specs, "space"), space)},
                     {"shortlist", shortlist},
                     {"feather", feather},
                     // on (1) or off (2)
                     {"stackAlbedo", stackFeatures != 0 ? 1 : 2},
                     {"stackNormal", stackFeatures != 0 ? 1 : 2}};
        if (stack >= 0) ao.tuning["stack"] = stack;
        autoSeconds =
            std::min(autoSeconds,
                     secondsOf([&] { result = glint::denoise::autoComposite(bank, frame, ao); }));
        used = result.layers.size();
        stacked = result.stacked;
        features = result.stackFeatures;
    }
    const nlohmann::json out = {{"size", size},
                                {"spp", spp},
                                {"threads", threads},
                                {"members", bankSize},
                                {"reps", reps},
                                {"estimator", estimator},
                                {"symmetric", oneSided == 0},
                                {"space", space},
                                {"shortlist", shortlist},
                                {"feather", feather},
                                {"stack", stacked},
                                {"stackFeatures", features},
                                {"retainFreed", retained},
                                {"bankSecondsBest", bankSeconds},
                                {"autoSecondsBest", autoSeconds},
                                {"autoOverBank", autoSeconds / bankSeconds},
                                {"membersUsed", used}};
    std::cout << out.dump(2) << "\n";
    return 0;
}
