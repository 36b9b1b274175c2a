// The height of the automatic selection's tiles from its memory budget (pipeline.h;
// docs/auto-memory.md, "Memory").
#include <algorithm>
#include <cmath>

#include "glint/image/memory.h"
#include "options.h"
#include "pipeline.h"

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

double autoMemberMemoryMB(const FilterBank&, const FrameBuffers& frame,
                          const AutoSettings& settings, std::uint64_t budget) {
    const std::uint64_t inputs = (settings.halves ? 1 : 2) * frameBytes(frame);
    const double room = budget > inputs ? double(budget - inputs) : 0.0;
    // Whole MiB: the parameter is an integer.
    return std::clamp(std::floor(0.6 * room / 1048576.0), 256.0, 1024.0);
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
    const std::uint64_t input = frameBytes(frame);
    const Rect& r = bank.region();
    const auto pixels = std::uint64_t(r.width()) * std::uint64_t(r.height());
    const std::uint64_t n = bank.size();
    // The halves (together about the input's layers), or SURE's input and its perturbed copy.
    const std::uint64_t inputs = settings.halves ? input : 2 * input;
    // Per pixel, held maps: the error maps (one float per member) or, after them, the stacking's
    // images (the features' regressors on three sides, its coefficients, the final weight
    // planes), and the median, the display weights, the noise, the composite and the blends on
    // the halves. Spilled maps: while the tiles run, the final candidates' weight planes and
    // their feathered copies (4 bytes each) and those 96 bytes; the stacking runs after the
    // tiles, by tiles of its own, whatever their height.
    const std::uint64_t finalCandidates =
        settings.shortlisted ? std::min<std::uint64_t>(n, std::uint64_t(settings.shortlist)) : n;
    const std::uint64_t perPixel =
        model.mapsSpilled ? 8 * finalCandidates + 96 : std::max<std::uint64_t>(4 * n, 320) + 64;
    // Banded: a band of results or, in the choice, a strip of its scores.
    const std::uint64_t bands = model.banded ? kBandBytes : 0;
    return saturatingAdd(saturatingAdd(inputs, bands), saturatingMul(pixels, perPixel));
}

int autoTileRows(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                 std::uint64_t budget, const TileModel& model) {
    const Rect& r = bank.region();
    const int height = r.height();
    const std::uint64_t fixed = autoFixedMemory(bank, frame, settings, model);
    // Per row of a tile: banded, the filters under way; else every member's result there on the
    // input at once (the median's pass), or, when the bank holds those, every candidate's window
    // scores (the choice's pass).
    const std::uint64_t n = bank.size();
    const std::uint64_t perPixel =
        model.banded ? std::uint64_t(std::max(1, model.concurrency)) * kApplyBytesPerPixel
        : bank.results().empty() ? 12 * n
                                 : 4 * n;
    const std::uint64_t perRow = std::uint64_t(r.width()) * (perPixel + 64);
    if (saturatingAdd(fixed, saturatingMul(perRow, std::uint64_t(height))) <= budget) return height;
    const std::uint64_t room = budget > fixed ? budget - fixed : 0;
    const int tallest = int(
        std::min<std::uint64_t>(room / std::max<std::uint64_t>(perRow, 1), std::uint64_t(height)));
    const int rows = std::min(height, std::max(kMinTileRows, tallest));
    // Tiles of one height: as many as `rows` needs, the rows shared out evenly.
    const int tiles = (height + rows - 1) / rows;
    return (height + tiles - 1) / tiles;
}

}  // namespace detail

}  // namespace glint::denoise
