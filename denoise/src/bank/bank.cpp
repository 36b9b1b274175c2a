// Building a bank: the usable filters, the Latin-hypercube members, their results computed in
// parallel (TBB, the caller's pool shared with the filters' own loops) or read from the cache.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <mutex>

#include "bank/bank_cache.h"
#include "bank/bank_detail.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "glint/image/random.h"

namespace glint::denoise {

FilterBank::FilterBank(std::vector<BankMember> members, std::vector<Image> results, Rect region,
                       int frameWidth, int frameHeight, std::uint64_t inputHash)
    : m_members(std::move(members)),
      m_results(std::move(results)),
      m_region(region),
      m_frameWidth(frameWidth),
      m_frameHeight(frameHeight),
      m_inputHash(inputHash) {
    GLINT_CHECK(m_members.size() == m_results.size() || m_results.empty(),
                "one result per bank member, or none (bankWithoutResults)");
}

void validate(const BankOptions& options) {
    auto bad = [](const std::string& what, const char* option) {
        throw Error(ErrorKind::InvalidArgument, what, {}, option);
    };
    if (options.size < 1 || options.size > kMaxBankSize)
        bad("bank size " + std::to_string(options.size) + " must be in [1, " +
                std::to_string(kMaxBankSize) + "]",
            "--size");
    for (const std::string& name : options.filters) {
        try {
            findFilter(name);
        } catch (const Error& e) {
            bad(e.message(), "--filters");
        }
    }
    // Fixed parameters: of one of the bank's filters, each known to it and in its range. A
    // default filter left out here (unet without its weights) is still one of the default
    // bank's: its parameters stay valid, and the bank goes on without it (usableFilters).
    std::vector<std::string> bankFilters = options.filters;
    if (options.filters.empty()) {
        std::vector<LeftOutFilter> leftOut;
        for (const Filter* f : defaultBankFilters(&leftOut)) bankFilters.emplace_back(f->name());
        for (LeftOutFilter& f : leftOut) bankFilters.push_back(std::move(f.name));
    }
    for (const auto& [name, params] : options.filterParams) {
        if (std::find(bankFilters.begin(), bankFilters.end(), name) == bankFilters.end())
            bad("parameters given to filter '" + name +
                    "', which is not one of the bank's filters (name it in --filters)",
                "--filter-param");
        try {
            resolveParams(findFilter(name), params);
        } catch (const Error& e) {
            bad(e.where() + ": " + e.message(), "--filter-param");
        }
    }
    if (options.prefilter)
        resolveParams(prefilterParams(), options.prefilterParams, "feature prefilter");
    if (options.region && options.region->empty()) bad("the region of interest is empty", "--roi");
    if (options.members) {
        const auto [first, end] = *options.members;
        if (first < 0 || end < first)
            bad("member range " + std::to_string(first) + ":" + std::to_string(end) +
                    " must be a:b with 0 <= a <= b",
                "--members");
        if (options.cacheDir.empty())
            bad("a range of members needs the bank folder its parts share", "--members");
    }
}

std::uint64_t hashFrame(const FrameBuffers& frame) {
    std::uint64_t h = hash64(std::uint64_t(frame.width()), std::uint64_t(frame.height()));
    for (int l = 0; l < kLayerCount; ++l) {
        const Image* layer = frame.find(Layer(l));
        if (!layer) continue;
        h = hash64(h, 0x6c61796572ULL + std::uint64_t(l));  // "layer" + index
        const std::span<const float> data = layer->data();
        const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
        const std::size_t n = data.size_bytes();
        std::size_t i = 0;
        for (; i + 8 <= n; i += 8) {
            std::uint64_t word;
            std::memcpy(&word, bytes + i, 8);
            h = mix64(h ^ word) + 0x9e3779b97f4a7c15ULL;
        }
        for (; i < n; ++i) h = mix64(h ^ bytes[i]);
    }
    return h;
}

namespace {

// The filters of the options (the default bank's when none are named) that can run on this
// frame with their default parameters.
std::vector<const Filter*> usableFilters(const FrameBuffers& frame, const BankOptions& options) {
    std::vector<const Filter*> chosen;
    if (options.filters.empty())
        chosen = defaultBankFilters();
    else
        for (const std::string& name : options.filters) chosen.push_back(&findFilter(name));
    std::vector<const Filter*> usable;
    std::string missing;
    for (const Filter* f : chosen) {
        bool ok = true;
        const ParamValues params =
            resolveParams(*f, detail::fixedParams(options.filterParams, f->name()));
        for (Layer l : f->requiredLayers(params)) ok = ok && frame.has(l);
        if (ok)
            usable.push_back(f);
        else
            missing += (missing.empty() ? "" : ", ") + std::string(f->name());
    }
    if (usable.empty())
        throw Error(ErrorKind::InvalidArgument,
                    "no selected filter can run on this frame (" + missing +
                        " need feature layers it lacks)",
                    {}, "--filters");
    return usable;
}

// Members whose parameters need a layer the frame lacks (a guide layer, say) are left out.
bool canRun(const FrameBuffers& frame, const BankMember& member) {
    const Filter& f = findFilter(member.filter);
    for (Layer l : f.requiredLayers(member.params))
        if (!frame.has(l)) return false;
    return true;
}

/// The region a bank covers, checked against the frame.
Rect bankRegion(const FrameBuffers& frame, const BankOptions& options) {
    const Rect bounds{0, frame.width(), 0, frame.height()};
    const Rect region = options.region.value_or(bounds);
    if (intersect(region, bounds) != region)
        throw Error(ErrorKind::InvalidArgument,
                    "region x [" + std::to_string(region.x0) + ", " + std::to_string(region.x1) +
                        "), y [" + std::to_string(region.y0) + ", " + std::to_string(region.y1) +
                        ") is outside the " + std::to_string(frame.width()) + "x" +
                        std::to_string(frame.height()) + " frame",
                    {}, "--roi");
    return region;
}

/// The members of a bank: those that can run on `frame` here, and those that cannot run in
/// this process (Filter::unavailable), which are never run.
struct Selection {
    std::vector<BankMember> members;
    std::vector<UnavailableMember> unavailable;
};

/// The members of the bank that can run on `frame`. Throws Error(InvalidArgument) with the
/// reasons when every member is unavailable.
Selection runnableMembers(const FrameBuffers& frame, const BankOptions& options) {
    Selection s;
    for (BankMember& m : detail::sampleBank(usableFilters(frame, options), options.size,
                                            options.seed, options.filterParams)) {
        if (!canRun(frame, m)) continue;
        if (std::string why = findFilter(m.filter).unavailable(m.params); !why.empty())
            s.unavailable.push_back({std::move(m), std::move(why)});
        else
            s.members.push_back(std::move(m));
    }
    if (s.members.empty() && !s.unavailable.empty()) {
        std::string reasons;
        for (const UnavailableMember& u : s.unavailable)
            reasons += (reasons.empty() ? "" : "; ") + u.member.filter + ": " + u.reason;
        throw Error(ErrorKind::InvalidArgument,
                    "no member of the bank can run here (" + reasons + ")", {}, "--filters");
    }
    return s;
}

/// Bytes of a bank of `members` results over `region` of `frame` (estimateMemory).
std::uint64_t bankBytes(const FrameBuffers& frame, const BankOptions& options, const Rect& region,
                        std::size_t members) {
    const std::uint64_t rgb = 3 * sizeof(float);
    const std::uint64_t regionPixels =
        std::uint64_t(region.width()) * std::uint64_t(region.height());
    const std::uint64_t framePixels = std::uint64_t(frame.width()) * std::uint64_t(frame.height());
    std::uint64_t bytes = saturatingMul(saturatingMul(members, regionPixels), rgb);
    if (options.prefilter) {
        std::uint64_t channels = 0;
        for (int l = 0; l < kLayerCount; ++l)
            if (frame.has(Layer(l))) channels += std::uint64_t(layerInfo(Layer(l)).channels);
        bytes = saturatingAdd(bytes, saturatingMul(framePixels, channels * sizeof(float)));
    }
    // A running filter holds about four frame-sized RGB images (input, output, scratch).
    const std::uint64_t running = std::max<std::uint64_t>(
        1, std::min<std::uint64_t>(members, tbb::this_task_arena::max_concurrency()));
    return saturatingAdd(bytes, saturatingMul(running, saturatingMul(framePixels, 4 * rgb)));
}

}  // namespace

std::uint64_t estimateMemory(const FrameBuffers& frame, const BankOptions& options) {
    validate(options);
    const Rect region = bankRegion(frame, options);
    return bankBytes(frame, options, region, runnableMembers(frame, options).members.size());
}

FilterBank detail::bankWithoutResults(const FrameBuffers& frame, const BankOptions& options) {
    validate(options);
    const Rect region = bankRegion(frame, options);
    Selection selection = runnableMembers(frame, options);
    FilterBank bank(std::move(selection.members), {}, region, frame.width(), frame.height(),
                    hashFrame(frame));
    detail::BankAccess::setUnavailable(bank, std::move(selection.unavailable));
    return bank;
}

FilterBank buildBank(const FrameBuffers& frame, const BankOptions& options) {
    return detail::buildBank(frame, options, detail::CacheMode::ReadWrite);
}

FilterBank detail::buildBank(const FrameBuffers& frame, const BankOptions& options,
                             CacheMode mode) {
    validate(options);
    const bool writes = mode == CacheMode::ReadWrite;
    GLINT_CHECK(writes || !options.members, "a bank built in parts writes its part");
    const Rect region = bankRegion(frame, options);
    Selection selection = runnableMembers(frame, options);
    std::vector<BankMember>& members = selection.members;
    // The members this build computes: all, or a range of them (a bank built in parts).
    std::size_t first = 0, end = members.size();
    if (options.members) {
        first = std::min(std::size_t(options.members->first), members.size());
        end = std::min(std::size_t(options.members->second), members.size());
    }
    const std::size_t count = end - first;
    // Refuse a bank the machine cannot hold before computing or allocating any member.
    checkMemory(bankBytes(frame, options, region, count), options.memoryLimit,
                "a bank of " + std::to_string(members.size()) + " members over " +
                    std::to_string(region.width()) + "x" + std::to_string(region.height()) +
                    " pixels",
                options.cacheDir.string(), "bank");

    const std::uint64_t inputHash = hashFrame(frame);
    detail::BankCache cache(options.cacheDir, inputHash, frame.width(), frame.height(), options);
    if (writes) cache.removeStaleTemporaries();  // of an interrupted build
    std::vector<Image> results(members.size());
    std::vector<std::uint64_t> keys(members.size());
    std::vector<char> hit(members.size(), 0);
    for (std::size_t i = 0; i < members.size(); ++i) keys[i] = cache.key(members[i], region);
    // Cached results are read in parallel (reopening a bank is mostly reading files).
    tbb::parallel_for(first, end, [&](std::size_t i) {
        if (cache.read(keys[i], region, results[i])) hit[i] = 1;
    });
    std::size_t hits = 0;
    for (char h : hit) hits += std::size_t(h);

    // Progress: members done (hits count as done) / total.
    std::mutex progressMutex;
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> done{hits};
    auto report = [&] {
        if (!options.progress) return;
        const std::lock_guard<std::mutex> lock(progressMutex);
        if (!stop.load() && !options.progress(count ? double(done.load()) / double(count) : 1.0))
            stop.store(true);
    };
    report();
    if (stop.load()) throw Error(ErrorKind::Cancelled, "bank cancelled");

    const bool needInput = hits < count;
    const FrameBuffers input = needInput && options.prefilter
                                   ? prefilterFeatures(frame, options.prefilterParams)
                                   : FrameBuffers{};
    const FrameBuffers& filterInput = options.prefilter ? input : frame;

    // Members in parallel; each filter's own loops share the same threads (FilterOptions::threads
    // = 0), and a stop reaches the running filters through their progress callbacks.
    tbb::parallel_for(first, end, [&](std::size_t i) {
        if (hit[i] || stop.load()) return;
        FilterOptions fo;
        fo.region = region;
        fo.progress = [&](double) { return !stop.load(); };
        try {
            results[i] =
                applyFilter(findFilter(members[i].filter), filterInput, members[i].params, fo);
        } catch (const Error& e) {
            if (e.kind() == ErrorKind::Cancelled) return;
            throw;
        }
        if (writes) cache.write(keys[i], members[i], region, results[i]);
        ++done;
        report();
    });
    if (stop.load()) throw Error(ErrorKind::Cancelled, "bank cancelled");
    if (!options.members) {
        if (writes) cache.writeIndex(members, keys, region, selection.unavailable);
        FilterBank bank(std::move(members), std::move(results), region, frame.width(),
                        frame.height(), inputHash);
        detail::BankAccess::setCacheHits(bank, hits);
        detail::BankAccess::setUnavailable(bank, std::move(selection.unavailable));
        return bank;
    }

    // A part of the bank: record it, and complete index.json when every part is there.
    cache.writePartialIndex(members, keys, first, end, region);
    const bool complete = cache.mergePartialIndices(members, keys, region, selection.unavailable);
    const std::size_t total = members.size();
    std::vector<BankMember> part(std::make_move_iterator(members.begin() + std::ptrdiff_t(first)),
                                 std::make_move_iterator(members.begin() + std::ptrdiff_t(end)));
    std::vector<Image> partResults(std::make_move_iterator(results.begin() + std::ptrdiff_t(first)),
                                   std::make_move_iterator(results.begin() + std::ptrdiff_t(end)));
    FilterBank bank(std::move(part), std::move(partResults), region, frame.width(), frame.height(),
                    inputHash);
    detail::BankAccess::setCacheHits(bank, hits);
    detail::BankAccess::setMemberRange(bank, first, total, complete);
    detail::BankAccess::setUnavailable(bank, std::move(selection.unavailable));
    return bank;
}

}  // namespace glint::denoise
