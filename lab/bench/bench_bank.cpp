// bench_bank: the filter bank and navigation speed figures of docs/navigation.md. Renders
// scenes/cornell at SIZE×SIZE (default 1024) with SPP samples (default 4), then times on
// THREADS threads (default 2): a 64-member bank over the whole frame (no cache, then written to
// and reopened from a cache folder), a bank over a 256×256 region, and the navigation tree over
// the 64 (+ defaults) members, whole frame and region. Prints one JSON object.
//   bench_bank [--size 1024] [--spp 4] [--threads 2] [--members 64] [--reps 1]
//              [--retain-freed 1|0 (glint::retainFreedMemory, as glint-denoise; default 1)]
//              [--nfor 1 (the default filters and nfor)] [--halves 1 (render half buffers)]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "bench_options.h"
#include "cornell_input.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/denoise/registry.h"
#include "glint/image/memory.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsOf(const std::function<void()>& fn) {
    const auto t0 = Clock::now();
    fn();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    glint::bench::RenderBankOptions o;
    int withNfor = 0, halves = 0;
    const int parsed = glint::bench::parseOptions(
        "bench_bank", argc, argv, [&](const std::string& a, const std::string& text) {
            const int v = glint::bench::intOption(a, text);
            if (a == "--nfor")
                withNfor = v;
            else if (a == "--halves")
                halves = v;
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
    const glint::FrameBuffers frame = glint::bench::cornellInput(size, spp, threads, halves != 0);

    nlohmann::json out = {{"size", size},          {"spp", spp},
                          {"threads", threads},    {"members", members},
                          {"reps", reps},          {"retainFreed", retained},
                          {"nfor", withNfor != 0}, {"halves", halves != 0}};
    glint::denoise::BankOptions options;
    options.size = members;
    options.seed = 1;
    if (withNfor != 0) {  // the default filters and the opt-in nfor
        for (const glint::denoise::Filter* f : glint::denoise::defaultBankFilters())
            options.filters.emplace_back(f->name());
        options.filters.push_back("nfor");
    }

    std::vector<double> whole;
    glint::denoise::FilterBank bank;
    for (int r = 0; r < reps; ++r)
        whole.push_back(secondsOf([&] { bank = glint::denoise::buildBank(frame, options); }));
    out["bankMembers"] = bank.size();
    out["bankSeconds"] = median(whole);

    // With the cache: first build writes every member, the second reads them all.
    const fs::path dir =
        fs::temp_directory_path() / ("glint_bench_bank_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    glint::denoise::BankOptions cached = options;
    cached.cacheDir = dir;
    out["bankWithCacheWriteSeconds"] = secondsOf([&] { glint::denoise::buildBank(frame, cached); });
    std::size_t hits = 0;
    out["bankReopenSeconds"] =
        secondsOf([&] { hits = glint::denoise::buildBank(frame, cached).cacheHits(); });
    out["bankReopenHits"] = hits;
    std::uintmax_t bytes = 0;
    for (const auto& e : fs::directory_iterator(dir)) bytes += fs::file_size(e.path());
    out["cacheMegabytes"] = double(bytes) / 1e6;
    fs::remove_all(dir);

    // A 256² region (centred).
    glint::denoise::BankOptions region = options;
    const int r0 = std::max(0, size / 2 - 128);
    region.region = glint::Rect{r0, std::min(size, r0 + 256), r0, std::min(size, r0 + 256)};
    std::vector<double> part;
    glint::denoise::FilterBank regionBank;
    for (int r = 0; r < std::max(reps, 3); ++r)
        part.push_back(secondsOf([&] { regionBank = glint::denoise::buildBank(frame, region); }));
    out["regionBankSeconds"] = median(part);

    // Navigation trees over the members (MSE on downsampled display values, the default).
    std::vector<double> tree, regionTree;
    std::size_t nodes = 0;
    for (int r = 0; r < 5; ++r) {
        tree.push_back(secondsOf(
            [&] { nodes = glint::denoise::NavigationTree::fromBank(bank, {}).nodeCount(); }));
        regionTree.push_back(
            secondsOf([&] { glint::denoise::NavigationTree::fromBank(regionBank, {}); }));
    }
    out["treeSeconds"] = median(tree);
    out["treeNodes"] = nodes;
    out["regionTreeSeconds"] = median(regionTree);
    glint::denoise::TreeOptions ssim;
    ssim.distance = glint::denoise::ImageDistance::Ssim;
    out["treeSsimSeconds"] =
        secondsOf([&] { glint::denoise::NavigationTree::fromBank(bank, ssim); });
    std::cout << out.dump(2) << "\n";
    return 0;
}
