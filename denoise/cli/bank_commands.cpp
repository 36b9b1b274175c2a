// glint-denoise bank: build a filter bank's cache folder, or a part of one (docs/navigation.md).
// What a bank can reach against a reference is measured by glint-lab (lab/cli/).
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"

namespace glint::denoise::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// ---- bank ------------------------------------------------------------------------------------

struct BankArgs {
    std::string input, out, filters, roi, memoryLimit, members;
    std::string size = "64", seed = "1";  // parsed strictly (parseInteger, parseUnsigned)
    bool prefilter = false, json = false;
    std::vector<std::string> filterParams;
};

// Checks before any work that the bank folder `out` can be created or written: not a file, in an
// existing folder, writable.
void checkBankFolder(const std::string& out) {
    std::error_code ec;
    if (fs::exists(out, ec) && !fs::is_directory(out, ec))
        throw Error(ErrorKind::InvalidArgument, "exists and is not a folder", out, "--out");
    const fs::path parent =
        fs::path(out).parent_path().empty() ? fs::path(".") : fs::path(out).parent_path();
    if (!fs::is_directory(parent, ec))
        throw Error(ErrorKind::InvalidArgument,
                    "the folder '" + parent.string() + "' that would hold the bank does not exist",
                    out, "--out");
    // access() also reports a read-only file system (EROFS), even to root.
    if (fs::is_directory(out, ec) && ::access(out.c_str(), W_OK | X_OK) != 0)
        throw Error(ErrorKind::InvalidArgument,
                    "the bank folder is not writable (a bank build writes its members and "
                    "index.json there)",
                    out, "--out");
    if (!fs::exists(out, ec) && ::access(parent.c_str(), W_OK | X_OK) != 0)
        throw Error(
            ErrorKind::InvalidArgument,
            "cannot create the bank folder: the folder '" + parent.string() + "' is not writable",
            out, "--out");
}

void runBank(const BankArgs& a) {
    BankOptions options;
    options.size = parseInteger(a.size, "--size");
    options.seed = glint::cli::parseUnsigned(a.seed, glint::cli::kMaxSeed, "--seed");
    options.filters = splitList(a.filters);
    // prefilter.NAME=VALUE sets the feature prefilter's parameters, the others a filter's.
    std::vector<std::string> fixed = a.filterParams;
    options.prefilterParams = takePrefilterParams(fixed, a.prefilter, "--filter-param");
    options.filterParams = parseFilterParams(fixed, "--filter-param");
    options.prefilter = a.prefilter;
    if (!a.memoryLimit.empty())
        options.memoryLimit = parseMemorySize(a.memoryLimit, "--memory-limit");
    if (!a.members.empty()) {
        // "a:b", both non-negative integers (b past the end of the bank is clamped).
        const std::size_t colon = a.members.find(':');
        int first = -1, end = -1;
        const char* text = a.members.c_str();
        const auto [p1, e1] =
            std::from_chars(text, text + (colon == std::string::npos ? 0 : colon), first);
        const auto [p2, e2] = colon == std::string::npos
                                  ? std::from_chars(text, text, end)
                                  : std::from_chars(text + colon + 1, text + a.members.size(), end);
        if (colon == std::string::npos || e1 != std::errc() || e2 != std::errc() ||
            p1 != text + colon || p2 != text + a.members.size())
            throw Error(ErrorKind::InvalidArgument,
                        "'" + a.members + "' is not a member range a:b (e.g. 0:32)", {},
                        "--members");
        options.members = std::pair{first, end};
        options.cacheDir = a.out;  // validate() wants the shared folder
    }
    validate(options);  // before reading anything or creating the folder
    glint::cli::checkOutputIsNoInput(a.out, "--out", {{a.input, "IN"}});
    checkBankFolder(a.out);
    const InputFrame input = readInput(a.input);
    const FrameBuffers& frame = input.frame;
    if (!a.roi.empty()) options.region = parseRegion(a.roi, frame.width(), frame.height(), a.input);
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec)
        throw Error(ErrorKind::Io, "cannot create the bank folder (" + ec.message() + ")", a.out,
                    "--out");
    sayInput(input);
    options.cacheDir = a.out;
    const bool tty = isatty(fileno(stderr)) != 0;
    if (tty && !a.json)
        options.progress = [](double f) {
            std::fprintf(stderr, "\rglint-denoise: bank %3d%%", int(f * 100.0 + 0.5));
            return true;
        };
    const json leftOut = reportLeftOutFilters(options);
    const auto t0 = Clock::now();
    const FilterBank bank = buildBank(frame, options);
    const double seconds = secondsSince(t0);
    if (tty && !a.json) std::fprintf(stderr, "\n");
    const json unavailable = reportUnavailableMembers(bank, a.out);
    json members = json::array();
    for (int m = 0; m < int(bank.size()); ++m) members.push_back(memberJson(bank, m));
    json report{{"input", a.input},           {"bank", a.out},
                {"members", bank.size()},     {"computed", bank.size() - bank.cacheHits()},
                {"cached", bank.cacheHits()}, {"region", rectJson(bank.region())},
                {"seconds", seconds},         {"list", members}};
    if (!leftOut.empty()) report["leftOut"] = leftOut;
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (!a.members.empty()) {
        report["firstMember"] = bank.firstMember();
        report["bankMembers"] = bank.bankMembers();
        report["indexWritten"] = bank.indexWritten();
    }
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf(
        "bank of %zu members over %dx%d in %.2f s (%zu computed, %zu from the cache) -> %s\n",
        bank.size(), bank.region().width(), bank.region().height(), seconds,
        bank.size() - bank.cacheHits(), bank.cacheHits(), a.out.c_str());
    if (!a.members.empty())
        std::printf("  members %zu..%zu of %zu; %s\n", bank.firstMember(),
                    bank.firstMember() + bank.size(), bank.bankMembers(),
                    bank.indexWritten() ? "every part present: index.json written"
                                        : "index.json waits for the other parts");
}

}  // namespace

std::vector<Command> addBankCommands(CLI::App& app) {
    auto bank = std::make_shared<BankArgs>();
    CLI::App* bankCmd =
        app.add_subcommand("bank", "Build (or update) a filter bank's cache folder");
    bankCmd->add_option("IN", bank->input, "Input layered EXR")->required();
    bankCmd->add_option("--out", bank->out, "Bank folder (created; reused as a cache)")->required();
    bankCmd->add_option("--size", bank->size,
                        "Latin-hypercube members (1 … 4096; defaults on top)");
    bankCmd->add_option("--seed", bank->seed, "Seed of the Latin hypercube (0 … 2^63 - 1)");
    bankCmd->add_option("--filters", bank->filters, "Only these filters, comma-separated");
    bankCmd->add_option("--filter-param", bank->filterParams,
                        std::string(kFilterParamHelp) +
                            "; with --prefilter, prefilter.name=value sets the feature "
                            "prefilter's (radius, sigmaSpatial, varianceScale)");
    bankCmd->add_flag("--prefilter", bank->prefilter, "Build on prefiltered features");
    bankCmd->add_option("--roi", bank->roi, "Only this region x0,x1,y0,y1 (half-open)");
    bankCmd->add_option("--memory-limit", bank->memoryLimit,
                        "Refuse a bank needing more memory than this (e.g. 2G; default: what is "
                        "available)");
    bankCmd->add_option("--members", bank->members,
                        "Compute only members a:b (0-based, b excluded) into the shared folder; "
                        "the part that completes the bank writes index.json");
    bankCmd->add_flag("--json", bank->json, "Print one JSON object on stdout");

    return {{bankCmd, [bank] { runBank(*bank); }}};
}

}  // namespace glint::denoise::cli
