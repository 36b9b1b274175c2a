// The automatic selection's one pipeline (auto_composite.cpp; docs/auto-memory.md): its tiles
// (strips of rows) and their height from a memory budget, and the entry with both given, which
// the tests and benchmarks use to compare one tile with many.
#pragma once

#include <cstdint>
#include <string>

#include "glint/denoise/auto.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"

namespace glint::denoise::detail {

struct AutoSettings;

/// What the selection may allocate besides its input frame and a given bank's results when
/// AutoOptions::memoryLimit is 0: keeps 1920×1080 with a 64-member bank under 2 GB in all.
constexpr std::uint64_t kDefaultAutoMemory = std::uint64_t(1280) << 20;
/// The memory budget, in MiB, of a member that has one of its own (the learned member's
/// memoryMB, whose tiling does not change its output): 0.6 of what `budget` leaves beside the
/// halves (the wide members run before the error maps take their memory), within 256 … 1024.
double autoMemberMemoryMB(const FilterBank& bank, const FrameBuffers& frame,
                          const AutoSettings& settings, std::uint64_t budget);
/// The lowest tile height: below it the filters' margins, read again at every tile, cost more
/// than the rows themselves.
constexpr int kMinTileRows = 64;

/// The bytes the selection holds besides its tiles, whatever their height: the halves (or SURE's
/// input and its perturbed copy), the error maps, the median and the stages' frame-sized images.
std::uint64_t autoFixedMemory(const FilterBank& bank, const FrameBuffers& frame,
                              const AutoSettings& settings);

/// The tile height for `budget`: the region's height (one tile) when it fits, else the tallest
/// that does, at least kMinTileRows, evened out so that the tiles are alike.
int autoTileRows(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                 std::uint64_t budget);

/// Whether the members' results that a later pass reads again are kept in the spill file
/// (strip_spill.h): Auto when the disk has room for them, On without that check, Off never (they
/// are filtered again: the same floats).
enum class SpillMode { Auto, On, Off };

/// How the pipeline is cut: `rows` per tile (0: from the memory budget) and the spill.
struct TileControl {
    int rows = 0;
    SpillMode spill = SpillMode::Auto;
};

/// What the pipeline gives besides the result.
struct TiledAuto {
    AutoResult result;
    bool spilled = false;  ///< StreamedAuto::spilled
    std::string warning;   ///< StreamedAuto::warning
};

/// autoComposite with its tiles given: `bank` with its results (read by rows) or without them
/// (bankWithoutResults: the members are applied tile by tile).
TiledAuto autoCompositeTiled(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoOptions& options, const TileControl& control);

/// autoCompositeStreamed with its tiles given.
StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options, const TileControl& control);

}  // namespace glint::denoise::detail
