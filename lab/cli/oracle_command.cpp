// glint-lab oracle: what a bank can reach against a reference: the noisy input, the best single
// member, the best three per pixel, the per-pixel optimum, auto's composite and the expected-error
// oracle (docs/lab/navigation.md, "The research tools in detail"; docs/lab/oidn-gap.md, "What
// limits the share").
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/lab/expected_oracle.h"
#include "glint/lab/oracle.h"
#include "lab_commands.h"

namespace glint::lab::cli {

namespace {

using namespace glint::denoise;
using namespace glint::denoise::cli;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// The oracle's "auto" column: SSIM of the auto composite of `bank` (its defaults) against
// `reference` over the bank's region, or a null SSIM and a note when `frame` cannot use it.
json autoOracleColumn(const FilterBank& bank, const FrameBuffers& frame, const Image& reference,
                      const std::string& bankDir) {
    try {
        checkAutoInput(frame, AutoEstimator::Auto);
    } catch (const Error& e) {
        return {{"ssim", nullptr}, {"note", e.where() + ": " + e.message()}};
    }
    const AutoOptions options = autoOptionsOfBank(bankDir);
    const auto t0 = Clock::now();
    const AutoResult r = autoComposite(bank, frame, options);
    const double seconds = secondsSince(t0);
    MetricOptions mo;
    return {{"ssim", ssim(r.composite, reference.crop(bank.region()), mo).value},
            {"membersUsed", r.layers.size()},
            {"estimator", autoEstimatorName(r.estimator)},
            {"bestMember", memberJson(bank, r.bestMember)},
            {"seconds", seconds}};
}

struct OracleArgs {
    std::string input, reference, bank, choiceMap;
    std::vector<std::string> expected;
    bool json = false;
};

void runOracle(const OracleArgs& a) {
    if (!a.choiceMap.empty()) {
        glint::cli::checkOutputPath(a.choiceMap, {".png"}, "--choice-map");
        glint::cli::checkOutputIsNoInput(a.choiceMap, "--choice-map",
                                         {{a.input, "IN"}, {a.reference, "--reference"}});
        for (const std::string& other : a.expected)
            glint::cli::checkOutputIsNoInput(a.choiceMap, "--choice-map", {{other, "--expected"}});
        checkOutputIsNoBankFile(a.choiceMap, "--choice-map", a.bank);
        glint::cli::removeTemporariesOnSignal({a.choiceMap});
    }
    const InputFrame input = readInput(a.input);
    const FrameBuffers& frame = input.frame;
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const auto t0 = Clock::now();
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
    sayInput(input);
    OracleResult r;
    try {
        r = oracle(bank, frame.color(), ref.color());
    } catch (const Error& e) {
        // About the bank (too few members, too small a region): name its folder.
        if (e.file().empty()) throw Error(e.kind(), e.message(), a.bank, "--bank");
        throw;
    }
    const double seconds = secondsSince(t0);
    const json autoColumn = autoOracleColumn(bank, frame, ref.color(), a.bank);
    // The expected-error oracle over IN and the other renders (each must match IN's size).
    json expected;
    if (!a.expected.empty()) {
        std::vector<FrameBuffers> others;
        for (const std::string& path : a.expected) {
            others.push_back(readExr(path));
            if (others.back().width() != frame.width() || others.back().height() != frame.height())
                throw Error(ErrorKind::InvalidArgument,
                            "is " + std::to_string(others.back().width()) + "x" +
                                std::to_string(others.back().height()) + ", the input " +
                                std::to_string(frame.width()) + "x" +
                                std::to_string(frame.height()) +
                                " (--expected takes other renders of the same scene)",
                            path);
        }
        const BankOptions bankOptions = readBankOptions(a.bank);
        ExpectedOracleOptions eo;
        eo.prefilter = bankOptions.prefilter;
        eo.prefilterParams = bankOptions.prefilterParams;
        const ExpectedOracleResult e = expectedErrorOracle(bank, others, ref.color(), eo);
        json share = json::array();
        for (double v : e.ssim)
            share.push_back(
                r.perPixel > r.bestSingle ? (v - r.bestSingle) / (r.perPixel - r.bestSingle) : 0.0);
        expected = {{"renders", e.renders}, {"radii", e.radii}, {"ssim", e.ssim}, {"share", share}};
    }
    if (!a.choiceMap.empty()) writeChoiceMap(r.choice, bank.size(), a.choiceMap);
    json best3 = json::array();
    for (int m : r.best3Members) best3.push_back(memberJson(bank, m));
    json report{{"input", a.input},
                {"reference", a.reference},
                {"bank", a.bank},
                {"members", bank.size()},
                {"noisy", r.noisy},
                {"bestSingle", r.bestSingle},
                {"bestMember", memberJson(bank, r.bestMember)},
                {"best3", r.best3},
                {"best3Members", best3},
                {"perPixel", r.perPixel},
                {"auto", autoColumn},
                {"seconds", seconds}};
    if (!expected.is_null()) report["expected"] = expected;
    if (!leftOut.empty()) report["leftOut"] = leftOut;
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf("SSIM against %s over %dx%d (%zu members):\n", a.reference.c_str(),
                bank.region().width(), bank.region().height(), bank.size());
    std::printf("  noisy               %.4f\n", r.noisy);
    std::printf("  best single         %.4f  %s\n", r.bestSingle,
                memberText(bank, r.bestMember).c_str());
    std::printf("  best 3, per pixel   %.4f\n", r.best3);
    std::printf("  per-pixel optimal   %.4f\n", r.perPixel);
    if (autoColumn["ssim"].is_null())
        std::printf("  auto                n/a (%s)\n",
                    autoColumn["note"].get<std::string>().c_str());
    else
        std::printf("  auto (%s)%*s%.4f\n", autoColumn["estimator"].get<std::string>().c_str(),
                    int(13 - autoColumn["estimator"].get<std::string>().size()), "",
                    autoColumn["ssim"].get<double>());
    if (!expected.is_null())
        for (std::size_t i = 0; i < expected["radii"].size(); ++i)
            std::printf("  expected error, r %-2d %.4f  (%+.0f %% of the way; %d renders)\n",
                        expected["radii"][i].get<int>(), expected["ssim"][i].get<double>(),
                        100.0 * expected["share"][i].get<double>(), expected["renders"].get<int>());
    if (!a.choiceMap.empty()) std::printf("  choice map -> %s\n", a.choiceMap.c_str());
}

}  // namespace

std::vector<Command> addOracleCommand(CLI::App& app) {
    auto orc = std::make_shared<OracleArgs>();
    CLI::App* oracleCmd =
        app.add_subcommand("oracle", "SSIM of noisy, best single, best 3 and per-pixel choices");
    oracleCmd->add_option("IN", orc->input, "Input layered EXR")->required();
    oracleCmd->add_option("--reference", orc->reference, "Reference EXR")->required();
    oracleCmd->add_option("--bank", orc->bank, "Bank folder of IN")->required();
    oracleCmd->add_option("--choice-map", orc->choiceMap, "Write the per-pixel choice as a PNG");
    oracleCmd
        ->add_option("--expected", orc->expected,
                     "Other renders of the same scene (another seed, same settings), comma-"
                     "separated: also choose per pixel by each member's error averaged over "
                     "IN and them, at radii 0, 2, 4 and 8")
        ->delimiter(',');
    oracleCmd->add_flag("--json", orc->json, "Print one JSON object on stdout");
    return {{oracleCmd, [orc] { runOracle(*orc); }}};
}

}  // namespace glint::lab::cli
