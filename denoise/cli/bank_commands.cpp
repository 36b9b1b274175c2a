// glint-denoise bank | oracle | navigate: build a filter bank, measure what it can reach (the
// oracle's auto column is in auto_commands.cpp), walk its navigation tree as a simulated user
// (docs/navigation.md).
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/denoise/oracle.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/research/expected_oracle.h"
#include "glint/denoise/research/local_artist.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"
#include "glint/image/metrics.h"

namespace glint::denoise::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string memberText(const FilterBank& bank, int m) {
    const BankMember& b = bank.members()[std::size_t(m)];
    return "#" + std::to_string(m) + " " + b.filter + " " +
           paramsSummary(findFilter(b.filter).params(), b.params);
}

// ---- bank ------------------------------------------------------------------------------------

struct BankArgs {
    std::string input, out, filters, roi, memoryLimit, members;
    std::string size = "64", seed = "1";  // parsed strictly (parseInteger, parseUnsigned)
    bool prefilter = false, json = false;
    std::vector<std::string> prefilterParams, filterParams;
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
    options.filterParams = parseFilterParams(a.filterParams, "--filter-param");
    options.prefilter = a.prefilter;
    if (!a.memoryLimit.empty())
        options.memoryLimit = parseMemorySize(a.memoryLimit, "--memory-limit");
    options.prefilterParams =
        parseParams(a.prefilterParams, prefilterParams(), "feature prefilter", "--prefilter-param");
    if (!a.prefilterParams.empty() && !a.prefilter)
        throw Error(ErrorKind::InvalidArgument, "given without --prefilter", {},
                    "--prefilter-param");
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
    const FrameBuffers frame = readExr(a.input);
    if (!a.roi.empty()) options.region = parseRegion(a.roi, frame.width(), frame.height(), a.input);
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec)
        throw Error(ErrorKind::Io, "cannot create the bank folder (" + ec.message() + ")", a.out,
                    "--out");
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

// ---- oracle ----------------------------------------------------------------------------------

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
    const FrameBuffers frame = readExr(a.input);
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const auto t0 = Clock::now();
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
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
        research::ExpectedOracleOptions eo;
        eo.prefilter = bankOptions.prefilter;
        eo.prefilterParams = bankOptions.prefilterParams;
        const research::ExpectedOracleResult e =
            research::expectedErrorOracle(bank, others, ref.color(), eo);
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

// ---- navigate --------------------------------------------------------------------------------

struct NavigateArgs {
    std::string input, reference, bank, roi, distance = "mse";
    bool simulate = false, json = false;
    std::string k = "4";  // parsed strictly (parseInteger)
    double p = 0.5;
    // The local artist (--local); empty: not given.
    bool local = false, keepAll = false, alone = false;
    std::string strokes, start, pick, brushSize, brushSoftness;
};

// The local artist (navigate --simulate --local): strokes over regions it picks, each navigated
// and painted with the soft brush (glint/denoise/research/local_artist.h).
void runLocalArtist(const NavigateArgs& a, const TreeOptions& tree) {
    if (!a.roi.empty())
        throw Error(ErrorKind::InvalidArgument, "the local artist picks its own regions", {},
                    "--roi");
    research::LocalArtistOptions options;
    options.tree = tree;
    if (!a.strokes.empty()) options.strokes = parseInteger(a.strokes, "--strokes");
    if (!a.pick.empty()) options.pick = research::parseArtistPick(a.pick);
    options.keepOnlyHelping = !a.keepAll;
    options.inContext = !a.alone;
    if (!a.brushSize.empty()) options.brush.size = parseNumber(a.brushSize, "--brush-size");
    if (!a.brushSoftness.empty())
        options.brush.softness = parseNumber(a.brushSoftness, "--brush-softness");
    const std::string start = a.start.empty() ? "auto" : a.start;
    if (start != "auto" && start != "best")
        throw Error(ErrorKind::InvalidArgument,
                    "unknown start '" + start + "' (expected auto or best)", {}, "--start");
    research::validate(options);
    const FrameBuffers frame = readExr(a.input);
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
    const Image refCrop = ref.color().crop(bank.region());
    // The starting composite: auto's (its defaults, no reference), or the best single member
    // chosen with the reference (the best any global filter of the bank does).
    Image composite;
    int startMember = -1;
    if (start == "auto") {
        try {
            checkAutoInput(frame, AutoEstimator::Auto);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message() + " (--start auto needs it; try --start best)",
                        a.input, e.where());
        }
        composite = autoComposite(bank, frame, autoOptionsOfBank(a.bank)).composite;
    } else {
        double best = -2.0;
        for (int m = 0; m < int(bank.size()); ++m) {
            const double s = ssim(bank.result(std::size_t(m)), refCrop).value;
            if (s > best) best = s, startMember = m;
        }
        composite = bank.result(std::size_t(startMember));
    }
    const auto t0 = Clock::now();
    const research::LocalArtistResult r = research::localArtist(bank, composite, refCrop, options);
    const double seconds = secondsSince(t0);
    json strokes = json::array();
    int kept = 0;
    for (const research::ArtistStroke& s : r.strokes) {
        kept += s.kept ? 1 : 0;
        strokes.push_back({{"stroke", s.stroke},
                           {"x", s.x},
                           {"y", s.y},
                           {"region", rectJson(s.region)},
                           {"member", memberJson(bank, s.member)},
                           {"choices", s.choices},
                           {"ssimIfKept", s.ssimIfKept},
                           {"kept", s.kept},
                           {"ssim", s.ssim}});
    }
    const double last = r.strokes.empty() ? r.startSsim : r.strokes.back().ssim;
    json startJson{{"kind", start}, {"ssim", r.startSsim}};
    if (startMember >= 0) startJson["member"] = memberJson(bank, startMember);
    json report{{"input", a.input},
                {"bank", a.bank},
                {"region", rectJson(bank.region())},
                {"pick", research::artistPickName(options.pick)},
                {"brush", {{"size", options.brush.size}, {"softness", options.brush.softness}}},
                {"keep", a.keepAll ? "all" : "helping"},
                {"start", startJson},
                {"strokes", strokes},
                {"kept", kept},
                {"ssim", last},
                {"seconds", seconds}};
    if (!leftOut.empty()) report["leftOut"] = leftOut;
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf("local artist from %s (SSIM %.4f), pick by %s, brush %.0f px:\n", start.c_str(),
                r.startSsim, research::artistPickName(options.pick), options.brush.size);
    for (const research::ArtistStroke& s : r.strokes)
        std::printf("  stroke %2d at (%.0f, %.0f): %d choices -> %-5s SSIM %.4f  %s\n", s.stroke,
                    s.x, s.y, s.choices, s.kept ? "kept," : "undone,", s.ssim,
                    memberText(bank, s.member).c_str());
    std::printf("%d of %zu strokes kept: SSIM %.4f -> %.4f in %.2f s\n", kept, r.strokes.size(),
                r.startSsim, last, seconds);
}

void runNavigate(const NavigateArgs& a) {
    if (!a.simulate)
        throw Error(ErrorKind::InvalidArgument,
                    "only the simulated user is scripted (--simulate); the studio navigates "
                    "interactively",
                    {}, "--simulate");
    TreeOptions options;
    options.k = parseInteger(a.k, "--k");
    options.p = a.p;
    if (a.distance == "ssim")
        options.distance = ImageDistance::Ssim;
    else if (a.distance != "mse")
        throw Error(ErrorKind::InvalidArgument,
                    "unknown distance '" + a.distance + "' (expected mse or ssim)", {},
                    "--distance");
    validate(options);
    if (a.local) {
        runLocalArtist(a, options);
        return;
    }
    for (const auto& [given, flag] :
         {std::pair{!a.strokes.empty(), "--strokes"}, std::pair{!a.start.empty(), "--start"},
          std::pair{!a.pick.empty(), "--pick"}, std::pair{!a.brushSize.empty(), "--brush-size"},
          std::pair{!a.brushSoftness.empty(), "--brush-softness"},
          std::pair{a.keepAll, "--keep-all"}})
        if (given) throw Error(ErrorKind::InvalidArgument, "given without --local", {}, flag);
    const FrameBuffers frame = readExr(a.input);
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
    Rect region = bank.region();
    if (!a.roi.empty()) {
        region = parseRegion(a.roi, frame.width(), frame.height(), a.input);
        if (intersect(region, bank.region()) != region)
            throw Error(ErrorKind::InvalidArgument, "the region lies outside the bank's region",
                        a.bank, "--roi");
    }
    // SSIM needs its 11x11 window: say whose region is too small, the --roi or the bank's.
    if (region.width() < 11 || region.height() < 11) {
        const std::string size =
            std::to_string(region.width()) + "x" + std::to_string(region.height());
        if (!a.roi.empty())
            throw Error(ErrorKind::InvalidArgument,
                        "the region is " + size + "; navigation needs at least 11x11 pixels (SSIM)",
                        a.input, "--roi");
        throw Error(ErrorKind::InvalidArgument,
                    "the bank covers " + size +
                        " pixels; navigation needs at least 11x11 (SSIM): build the bank over a "
                        "larger region",
                    a.bank, "--bank");
    }
    const auto t0 = Clock::now();
    const NavigationTree tree = NavigationTree::fromBank(bank, options, region);
    const double treeSeconds = secondsSince(t0);
    const Rect local{region.x0 - bank.region().x0, region.x1 - bank.region().x0,
                     region.y0 - bank.region().y0, region.y1 - bank.region().y0};
    std::vector<Image> crops;
    for (const Image& im : bank.results()) crops.push_back(im.crop(local));
    std::vector<const Image*> images;
    for (const Image& im : crops) images.push_back(&im);
    const Image refCrop = ref.color().crop(region);
    const std::vector<SimulatedChoice> steps = simulateUser(tree, images, refCrop);
    MetricOptions mo;
    const double noisy = ssim(frame.color().crop(region), refCrop, mo).value;
    double bestSingle = -1.0;
    int bestMember = -1;
    for (int m = 0; m < int(images.size()); ++m) {
        const double s = ssim(*images[std::size_t(m)], refCrop, mo).value;
        if (s > bestSingle) bestSingle = s, bestMember = m;
    }
    // The share of the best single member's gain reached after each choice.
    auto share = [&](double s) {
        return bestSingle > noisy ? (s - noisy) / (bestSingle - noisy) : 1.0;
    };
    json list = json::array();
    for (std::size_t i = 0; i < steps.size(); ++i)
        list.push_back({{"choice", i + 1},
                        {"option", steps[i].option},
                        {"member", memberJson(bank, steps[i].member)},
                        {"ssim", steps[i].ssim},
                        {"shareOfBestGain", share(steps[i].ssim)}});
    int within = -1;
    for (std::size_t i = 0; i < steps.size() && within < 0; ++i)
        if (share(steps[i].ssim) >= 0.9) within = int(i) + 1;
    json report{{"input", a.input},
                {"bank", a.bank},
                {"region", rectJson(region)},
                {"nodes", tree.nodeCount()},
                {"treeSeconds", treeSeconds},
                {"noisy", noisy},
                {"bestSingle", bestSingle},
                {"bestMember", memberJson(bank, bestMember)},
                {"choices", list},
                {"choicesTo90PercentOfBestGain", within < 0 ? json(nullptr) : json(within)}};
    if (!leftOut.empty()) report["leftOut"] = leftOut;
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf("navigation tree: %zu nodes over %zu members in %.3f s\n", tree.nodeCount(),
                tree.memberCount(), treeSeconds);
    std::printf("SSIM: noisy %.4f, best single %.4f (%s)\n", noisy, bestSingle,
                memberText(bank, bestMember).c_str());
    for (std::size_t i = 0; i < steps.size(); ++i)
        std::printf("  choice %zu: option %d -> %.4f (%3.0f%% of the best gain)  %s\n", i + 1,
                    steps[i].option, steps[i].ssim, 100.0 * share(steps[i].ssim),
                    memberText(bank, steps[i].member).c_str());
    if (within > 0)
        std::printf("90%% of the best single member's gain after %d choices\n", within);
    else
        std::printf("90%% of the best single member's gain not reached\n");
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
    bankCmd->add_option("--filter-param", bank->filterParams, kFilterParamHelp);
    bankCmd->add_flag("--prefilter", bank->prefilter, "Build on prefiltered features");
    bankCmd->add_option("--prefilter-param", bank->prefilterParams, "Prefilter parameter k=v");
    bankCmd->add_option("--roi", bank->roi, "Only this region x0,x1,y0,y1 (half-open)");
    bankCmd->add_option("--memory-limit", bank->memoryLimit,
                        "Refuse a bank needing more memory than this (e.g. 2G; default: what is "
                        "available)");
    bankCmd->add_option("--members", bank->members,
                        "Compute only members a:b (0-based, b excluded) into the shared folder; "
                        "the part that completes the bank writes index.json");
    bankCmd->add_flag("--json", bank->json, "Print one JSON object on stdout");

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

    auto nav = std::make_shared<NavigateArgs>();
    CLI::App* navCmd =
        app.add_subcommand("navigate", "Walk the navigation tree as a simulated user");
    navCmd->add_option("IN", nav->input, "Input layered EXR")->required();
    navCmd->add_option("--bank", nav->bank, "Bank folder of IN")->required();
    navCmd->add_option("--reference", nav->reference, "Reference EXR")->required();
    navCmd->add_flag("--simulate", nav->simulate, "Pick the child closest to the reference");
    navCmd->add_option("--roi", nav->roi, "Region x0,x1,y0,y1 (inside the bank's region)");
    navCmd->add_option("--k", nav->k, "Children per node (2 … 64)");
    navCmd->add_option("--p", nav->p, "Fraction of a node each child keeps, in (0, 1)");
    navCmd->add_option("--distance", nav->distance, "mse | ssim");
    navCmd->add_flag("--local", nav->local,
                     "The local artist: pick a region, navigate its bank, paint the choice with "
                     "the soft brush, repeat (SSIM after each stroke)");
    navCmd->add_option("--strokes", nav->strokes, "--local: strokes tried (1 … 10000; 30)");
    navCmd->add_option("--start", nav->start,
                       "--local: auto (auto's composite) | best (the best single member, chosen "
                       "with the reference); auto");
    navCmd->add_option("--pick", nav->pick,
                       "--local: where to stroke: variance (where the members disagree) | error "
                       "(where the composite is furthest from the reference); variance");
    navCmd->add_option("--brush-size", nav->brushSize,
                       "--local: brush diameter and side of the region navigated (>= 11 px; 24)");
    navCmd->add_option("--brush-softness", nav->brushSoftness,
                       "--local: inner radius / outer radius, in [0, 1]; 0.5");
    navCmd->add_flag("--alone", nav->alone,
                     "--local: compare the members alone over the region (default: as they would "
                     "look painted into the composite)");
    navCmd->add_flag("--keep-all", nav->keepAll,
                     "--local: keep every stroke (default: undo those that lower the SSIM)");
    navCmd->add_flag("--json", nav->json, "Print one JSON object on stdout");

    return {{bankCmd, [bank] { runBank(*bank); }},
            {oracleCmd, [orc] { runOracle(*orc); }},
            {navCmd, [nav] { runNavigate(*nav); }}};
}

}  // namespace glint::denoise::cli
