// bench_auto_memory: the memory figure of `glint-denoise auto` without a bank folder
// (docs/auto-memory.md). Reads IN (a render with half buffers for the halves estimator), then runs
// the automatic selection over a bank of MEMBERS members (plus the defaults, no cache) once, either
// over a materialised bank — buildBank then autoComposite over the bank's results (--mode whole)
// — or applying the members tile by tile (--mode streamed, autoCompositeStreamed: what
// `glint-denoise auto IN --out OUT` runs); --rows: the tile height (0: from the memory budget,
// --memory-limit BYTES, 0: the default); --spill auto|on|off: whether the members' results read
// again are kept in a temporary file or filtered again. Prints one JSON object: the time, the tile
// height, the process's peak resident memory (getrusage), and with --against OTHER.exr (the other
// mode's --out) the largest difference between the two composites. Run from
// lab/bench/auto_memory.sh, one process per figure.
//   bench_auto_memory --in IN.exr [--mode whole|streamed] [--members 64] [--threads 2]
//                     [--rows 0] [--memory-limit 0] [--spill auto] [--out OUT.exr]
//                     [--against OTHER.exr]
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "auto/pipeline.h"
#include "bench_options.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/image/composite.h"
#include "glint/image/io.h"
#include "glint/image/memory.h"

int main(int argc, char** argv) {
    using Clock = std::chrono::steady_clock;
    std::string input, mode = "streamed", outPath, against, spill = "auto";
    int members = 64, threads = 2, rows = 0;
    long long memoryLimit = 0;
    const int parsed = glint::bench::parseOptions(
        "bench_auto_memory", argc, argv, [&](const std::string& a, const std::string& text) {
            if (a == "--in")
                input = text;
            else if (a == "--mode")
                mode = text;
            else if (a == "--out")
                outPath = text;
            else if (a == "--against")
                against = text;
            else if (a == "--spill")
                spill = text;
            else if (a == "--members")
                members = glint::bench::intOption(a, text);
            else if (a == "--threads")
                threads = glint::bench::intOption(a, text);
            else if (a == "--rows")
                rows = glint::bench::intOption(a, text);
            else if (a == "--memory-limit")
                memoryLimit = std::stoll(text);
            else
                return false;
            return true;
        });
    if (parsed != 0) return parsed;
    const char* spills[] = {"auto", "on", "off"};
    const auto spillIndex = std::find(std::begin(spills), std::end(spills), spill);
    if (input.empty() || (mode != "whole" && mode != "streamed") ||
        spillIndex == std::end(spills)) {
        std::fprintf(stderr,
                     "bench_auto_memory: needs --in IN.exr, --mode whole|streamed and "
                     "--spill auto|on|off\n");
        return 2;
    }
    glint::retainFreedMemory();  // as glint-denoise
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    glint::FrameBuffers frame = glint::readExr(input);
    glint::denoise::BankOptions bankOptions;
    bankOptions.size = members;
    glint::denoise::AutoOptions options;  // the defaults, as `glint-denoise auto IN --out OUT`
    options.memoryLimit = std::uint64_t(std::max(0LL, memoryLimit));
    const glint::denoise::detail::TileControl control{
        rows, glint::denoise::detail::SpillMode(spillIndex - std::begin(spills))};
    const auto t0 = Clock::now();
    glint::denoise::AutoResult result;
    glint::Rect region;
    std::size_t bankSize = 0;
    bool spilled = false;
    std::string warning;
    if (mode == "whole") {
        const glint::denoise::FilterBank bank = glint::denoise::buildBank(frame, bankOptions);
        glint::denoise::detail::TiledAuto t =
            glint::denoise::detail::autoCompositeTiled(bank, frame, options, control);
        result = std::move(t.result);
        region = bank.region(), bankSize = bank.size();
        spilled = t.spilled, warning = t.warning;
    } else {
        glint::denoise::StreamedAuto s =
            glint::denoise::detail::autoCompositeStreamed(frame, bankOptions, options, control);
        result = std::move(s.result);
        region = s.bank.region(), bankSize = s.bank.size();
        spilled = s.spilled, warning = s.warning;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double peakMiB = double(usage.ru_maxrss) / 1024.0;  // KiB on Linux

    nlohmann::json report = {
        {"input", input},           {"mode", mode},        {"width", frame.width()},
        {"height", frame.height()}, {"members", bankSize}, {"threads", threads},
        {"seconds", seconds},       {"peakMiB", peakMiB},  {"stacked", result.stacked},
        {"spill", spill},           {"spilled", spilled},  {"tileRows", result.tileRows}};
    if (!warning.empty()) report["warning"] = warning;
    if (!outPath.empty()) {
        glint::writeExr(glint::withColorPasted(frame, result.composite, region.x0, region.y0),
                        outPath);
    }
    // Only the composite is read from here on: the rest goes before the other output is read.
    frame = glint::FrameBuffers{};
    result.layers.clear();
    if (!against.empty()) {
        const glint::Image other = glint::readExr(against).color().crop(region);
        double largest = 0.0;
        std::size_t differ = 0;
        for (std::size_t i = 0; i < other.data().size(); ++i) {
            const double d =
                std::fabs(double(other.data()[i]) - double(result.composite.data()[i]));
            largest = std::max(largest, d);
            differ += d > 0.0 ? 1 : 0;
        }
        report["against"] = against;
        report["maxAbsDifference"] = largest;
        report["valuesDiffering"] = differ;
        report["values"] = other.data().size();
    }
    std::printf("%s\n", report.dump().c_str());
    return 0;
}
