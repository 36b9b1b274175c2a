// The height of the automatic selection's tiles from its memory budget (pipeline.h;
// docs/auto-memory.md, "Memory").
#include <algorithm>
#include <cmath>

#include "glint/image/memory.h"
#include "options.h"
#include "pipeline.h"
#include "stacking.h"

namespace glint::denoise {

std::uint64_t autoMemoryBudget(std::uint64_t limit) {
    return std::min(detail::kDefaultAutoMemory, limit > 0 ? limit : availableMemory());
}

namespace detail {

// Bytes of the frame's layers.
std::uint64_t frameBytes(const FrameBuffers& frame) {
    std::uint64_t bytes = 0;
    for (int l = 0; l < kLayerCount; ++l)
        if (const Image* layer = frame.find(Layer(l)))
            bytes += std::uint64_t(layer->data().size()) * sizeof(float);
    return bytes;
}

// Bytes of the layers splitHalves makes for half A: the mean layers, their variances and the
// counts (B and A's other layers are the frame's, shared).
std::uint64_t halfABytes(const FrameBuffers& frame) {
    std::uint64_t bytes = 0;
    for (Layer mean : {Layer::Color, Layer::Albedo, Layer::Normal, Layer::Depth}) {
        if (!frame.has(mean)) continue;
        for (Layer l : {mean, *varianceLayer(mean)})
            if (const Image* layer = frame.find(l))
                bytes += std::uint64_t(layer->data().size()) * sizeof(float);
    }
    if (const Image* counts = frame.find(Layer::SampleCount))
        bytes += std::uint64_t(counts->data().size()) * sizeof(float);
    return bytes;
}

// What the members' inputs hold besides the frame: half A's own layers (prefiltered: both
// halves' copies, about the input's layers), or SURE's input and its perturbed copy.
std::uint64_t memberInputBytes(const FrameBuffers& frame, const AutoSettings& settings) {
    if (!settings.halves) return 2 * frameBytes(frame);
    return settings.prefilter ? frameBytes(frame) : halfABytes(frame);
}

double autoMemberMemoryMB(const FilterBank&, const FrameBuffers& frame,
                          const AutoSettings& settings, std::uint64_t budget) {
    const std::uint64_t inputs = memberInputBytes(frame, settings);
    const double room = budget > inputs ? double(budget - inputs) : 0.0;
    // All of it: a learned member's smaller tiles, each with its receptive field's overlap, cost
    // CPU time (at 1920×1080, 0.6 of the room cut the U-Net into 6 tiles of 2.9 Mpx in all
    // against 2 of 2.3 Mpx; docs/lab/auto-memory.md), and the peak is the stacking's, after the
    // members. Whole MiB: the parameter is an integer.
    return std::clamp(std::floor(room / 1048576.0), 256.0, 1024.0);
}

TileModel autoTileModel(const FilterBank& bank, bool spillOn, bool mapSpillOn, int concurrency) {
    TileModel model;
    model.concurrency = std::max(1, concurrency);
    model.banded = spillOn && bank.results().empty() &&
                   std::uint64_t(model.concurrency) * kApplyBytesPerPixel < 12 * bank.size();
    model.mapsSpilled = mapSpillOn;
    return model;
}

int autoBandRows(const FilterBank& bank, const AutoSettings& settings) {
    const std::uint64_t n = bank.size();
    const std::uint64_t finalCandidates =
        settings.shortlisted ? std::min<std::uint64_t>(n, std::uint64_t(settings.shortlist)) : n;
    const std::uint64_t results =
        std::max<std::uint64_t>(1, std::max(n, (settings.stack > 0 ? 3 : 1) * finalCandidates));
    const std::uint64_t rowBytes = std::uint64_t(bank.region().width()) * 3 * sizeof(float);
    return int(
        std::clamp<std::uint64_t>(kBandBytes / (results * std::max<std::uint64_t>(rowBytes, 1)), 1,
                                  std::uint64_t(std::max(1, bank.region().height()))));
}

std::uint64_t autoFixedMemory(const FilterBank& bank, const FrameBuffers& frame,
                              const AutoSettings& settings, const TileModel& model) {
    const Rect& r = bank.region();
    const auto pixels = std::uint64_t(r.width()) * std::uint64_t(r.height());
    const std::uint64_t n = bank.size();
    const std::uint64_t inputs = memberInputBytes(frame, settings);
    const std::uint64_t finalCandidates =
        settings.shortlisted ? std::min<std::uint64_t>(n, std::uint64_t(settings.shortlist)) : n;
    // Per pixel, held maps: the error maps (one float per member) or, after them, the stacking's
    // images (the features' regressors on three sides, its coefficients, the final weight
    // planes), and the median, the display weights, the noise, the composite and the blends on
    // the halves. Spilled maps: the most of the blend's (the final candidates' weight planes and
    // their feathered copies, 4 bytes each, the composite, the blends on the halves and the
    // choice: 40) and the stacking's (the weight planes, those 40 and its weights: 52). Either
    // way, with the stacking, its tile (stackTileBytes) and the frame's variance over the region
    // (its noise gate: 12).
    std::uint64_t stackTile = 0;
    if (settings.stack > 0) {
        const std::size_t regressors = std::size_t(settings.stack) +
                                       (settings.stackAlbedo ? 1 : 0) +
                                       (settings.stackNormal ? 3 : 0);
        stackTile = saturatingAdd(
            stackTileBytes(r.width(), regressors, settings.stackWindow, settings.stackSmooth),
            saturatingMul(pixels, 12));
    }
    std::uint64_t held = 0;
    if (model.mapsSpilled) {
        const std::uint64_t blend = saturatingMul(pixels, 8 * finalCandidates + 40);
        const std::uint64_t stack =
            settings.stack > 0
                ? saturatingAdd(saturatingMul(pixels, 4 * finalCandidates + 52), stackTile)
                : 0;
        held = std::max(blend, stack);
    } else {
        held = saturatingAdd(saturatingMul(pixels, std::max<std::uint64_t>(4 * n, 320) + 64),
                             stackTile);
    }
    // Banded: a band of results or, in the choice, a strip of its scores.
    const std::uint64_t bands = model.banded ? kBandBytes : 0;
    return saturatingAdd(saturatingAdd(inputs, bands), held);
}

// Per row of a tile: banded, the filters under way; else every member's result there on the
// input at once (the median's pass), or, when the bank holds those, every candidate's window
// scores (the choice's pass).
std::uint64_t tileRowBytes(const FilterBank& bank, const TileModel& model) {
    const std::uint64_t n = bank.size();
    const std::uint64_t perPixel =
        model.banded ? std::uint64_t(std::max(1, model.concurrency)) * kApplyBytesPerPixel
        : bank.results().empty() ? 12 * n
                                 : 4 * n;
    return std::uint64_t(bank.region().width()) * (perPixel + 64);
}

int autoTileRows(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                 std::uint64_t budget, const TileModel& model) {
    const Rect& r = bank.region();
    const int height = r.height();
    const std::uint64_t fixed = autoFixedMemory(bank, frame, settings, model);
    const std::uint64_t perRow = tileRowBytes(bank, model);
    if (saturatingAdd(fixed, saturatingMul(perRow, std::uint64_t(height))) <= budget) return height;
    const std::uint64_t room = budget > fixed ? budget - fixed : 0;
    const int tallest = int(
        std::min<std::uint64_t>(room / std::max<std::uint64_t>(perRow, 1), std::uint64_t(height)));
    const int rows = std::min(height, std::max(kMinTileRows, tallest));
    // Tiles of one height: as many as `rows` needs, the rows shared out evenly.
    const int tiles = (height + rows - 1) / rows;
    return (height + tiles - 1) / tiles;
}

std::uint64_t autoMemoryEstimate(const FilterBank& bank, const FrameBuffers& frame,
                                 const AutoSettings& settings, std::uint64_t budget,
                                 const TileModel& model) {
    const int rows = autoTileRows(bank, frame, settings, budget, model);
    return saturatingAdd(
        saturatingAdd(frameBytes(frame), autoFixedMemory(bank, frame, settings, model)),
        saturatingMul(tileRowBytes(bank, model), std::uint64_t(rows)));
}

}  // namespace detail

}  // namespace glint::denoise
