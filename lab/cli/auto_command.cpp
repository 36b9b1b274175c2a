// glint-lab auto: glint-denoise auto (the same run, denoise/cli/auto_commands.cpp) with every
// flag the product leaves out: each tuning parameter (autoTuningSpecs, set through
// AutoOptions::tuning), the bank's size, seed, fixed parameters and prefilter, the choice map,
// the noise estimate, and the tuning table (docs/lab/auto-tuning.md).
#include <cstdio>
#include <memory>

#include "auto_args.h"
#include "glint/denoise/auto.h"
#include "lab_commands.h"

namespace glint::lab::cli {

namespace {

using namespace glint::denoise;
using namespace glint::denoise::cli;

// The tuning table of docs/lab/auto-tuning.md, generated from the specs (`--tuning-table`).
void printTuningTable() {
    const ParamValues halves = autoTuningDefaults(AutoEstimator::Halves);
    const ParamValues sure = autoTuningDefaults(AutoEstimator::Sure);
    std::printf(
        "| flag | `tuning` name | range | default: halves | default: SURE, image | meaning |\n");
    std::printf("|---|---|---|---|---|---|\n");
    for (const ParamSpec& spec : autoTuningSpecs()) {
        std::string range;
        if (spec.isChoice()) {
            for (const std::string& c : spec.choices) range += (range.empty() ? "" : ", ") + c;
        } else if (isTuningSwitch(spec)) {
            range = "(a switch)";
        } else {
            range = formatParamValue(spec, spec.min) + " … " + formatParamValue(spec, spec.max);
        }
        const std::string h = formatParamValue(spec, halves.at(spec.name));
        const std::string s = formatParamValue(spec, sure.at(spec.name));
        std::printf("| `%s` | `%s` | %s | %s | %s | %s |\n", autoTuningFlag(spec.name).c_str(),
                    spec.name.c_str(), range.c_str(), h.c_str(), s.c_str(), spec.help.c_str());
    }
}

}  // namespace

std::vector<Command> addAutoCommand(CLI::App& app) {
    auto a = std::make_shared<AutoArgs>();
    CLI::App* cmd = addAutoFlags(app, a);
    cmd->description(
        "glint-denoise auto with every tuning flag: per-pixel filter choice over a bank by each "
        "member's estimated error (SURE, the halves or the image-only estimate)");
    cmd->add_option("--reference", a->reference,
                    "Reference EXR: print SSIM/PSNR/relMSE of the input, of the best member and of "
                    "auto");
    cmd->add_option("--size", a->size,
                    "Without --bank: Latin-hypercube members (1 … 4096; default: the quality's)");
    cmd->add_option("--bank-seed", a->bankSeed,
                    "Without --bank: seed of the Latin hypercube (0 … 2^63 - 1)");
    cmd->add_option("--filter-param", a->filterParams,
                    std::string("Without --bank: ") + kFilterParamHelp);
    cmd->add_flag("--prefilter", a->prefilter, "Without --bank: build on prefiltered features");
    // The tuning map's flags the product has not, from its specs (docs/lab/auto-tuning.md).
    for (const ParamSpec& spec : autoTuningSpecs())
        if (!cmd->get_option_no_throw(autoTuningFlag(spec.name))) addTuningFlag(cmd, a, spec);
    auto tuningTable = std::make_shared<bool>(false);
    cmd->add_flag("--tuning-table", *tuningTable,
                  "Print the tuning parameters as the Markdown table of docs/lab/auto-tuning.md "
                  "and exit");
    cmd->add_option("--choice-map", a->choiceMap, "Write the chosen member per pixel as a PNG");
    cmd->add_option("--noise-out", a->noiseOut,
                    "With SURE or the image-only estimator: write the variance of the mean it "
                    "used as the colour of an EXR");
    return {{cmd, [a, tuningTable] {
                 if (*tuningTable)
                     printTuningTable();
                 else
                     runAuto(*a);
             }}};
}

}  // namespace glint::lab::cli
