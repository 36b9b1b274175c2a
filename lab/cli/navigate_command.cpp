// glint-lab navigate --simulate [--local]: walks a bank's navigation tree as a simulated user
// who sees the reference, or works as the local artist who strokes regions with the soft brush
// (docs/lab/navigation.md, "The research tools in detail", "The local artist in detail").
#include <chrono>
#include <cstdio>
#include <memory>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/lab/local_artist.h"
#include "glint/lab/simulated_user.h"
#include "lab_commands.h"

namespace glint::lab::cli {

namespace {

using namespace glint::denoise;
using namespace glint::denoise::cli;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

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
// and painted with the soft brush (glint/lab/local_artist.h).
void runLocalArtist(const NavigateArgs& a, const TreeOptions& tree) {
    if (!a.roi.empty())
        throw Error(ErrorKind::InvalidArgument, "the local artist picks its own regions", {},
                    "--roi");
    LocalArtistOptions options;
    options.tree = tree;
    if (!a.strokes.empty()) options.strokes = parseInteger(a.strokes, "--strokes");
    if (!a.pick.empty()) options.pick = parseArtistPick(a.pick);
    options.keepOnlyHelping = !a.keepAll;
    options.inContext = !a.alone;
    if (!a.brushSize.empty()) options.brush.size = parseNumber(a.brushSize, "--brush-size");
    if (!a.brushSoftness.empty())
        options.brush.softness = parseNumber(a.brushSoftness, "--brush-softness");
    const std::string start = a.start.empty() ? "auto" : a.start;
    if (start != "auto" && start != "best")
        throw Error(ErrorKind::InvalidArgument,
                    "unknown start '" + start + "' (expected auto or best)", {}, "--start");
    validate(options);
    const InputFrame input = readInput(a.input);
    const FrameBuffers& frame = input.frame;
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
    sayInput(input);
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
    const LocalArtistResult r = localArtist(bank, composite, refCrop, options);
    const double seconds = secondsSince(t0);
    json strokes = json::array();
    int kept = 0;
    for (const ArtistStroke& s : r.strokes) {
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
                {"pick", artistPickName(options.pick)},
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
                r.startSsim, artistPickName(options.pick), options.brush.size);
    for (const ArtistStroke& s : r.strokes)
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
    const InputFrame input = readInput(a.input);
    const FrameBuffers& frame = input.frame;
    const FrameBuffers ref = readReference(a.reference, frame.width(), frame.height());
    const json leftOut = reportLeftOutFilters(readBankOptions(a.bank));
    const FilterBank bank = openBank(frame, a.bank);
    const json unavailable = reportUnavailableMembers(bank, a.bank);
    sayInput(input);
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

std::vector<Command> addNavigateCommand(CLI::App& app) {
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
    return {{navCmd, [nav] { runNavigate(*nav); }}};
}

}  // namespace glint::lab::cli
