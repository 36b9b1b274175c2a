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
/// memoryMB, whose tiling does not change its output): what `budget` leaves beside the halves
/// (the wide members run before the error maps take their memory), within 256 … 1024.
double autoMemberMemoryMB(const FilterBank& bank, const FrameBuffers& frame,
                          const AutoSettings& settings, std::uint64_t budget);
/// The lowest tile height: below it the filters' margins, read again at every tile, cost more
/// than the rows themselves.
constexpr int kMinTileRows = 64;

/// What the reductions (the median, the blend) may hold at once when they read the members'
/// results by bands (autoBandRows), and the choice's window scores by strips (never both).
constexpr std::uint64_t kBandBytes = std::uint64_t(64) << 20;
/// The bytes per pixel of a tile that one member's application holds while it runs: its result,
/// the results on the halves and the error map the estimate makes of them, and the filter's
/// own buffers. Measured: at 1920×1080 the resident memory of the tiled passes grew by 64 bytes
/// a pixel per filter under way from 360-row tiles to one tile (docs/lab/auto-memory.md).
constexpr std::uint64_t kApplyBytesPerPixel = 64;

/// How a tile's members reach the reductions: every member's result on the tile held at once
/// (`banded` false), or each applied into the spill and the results read back by bands of
/// autoBandRows rows (then a tile holds the `concurrency` filters under way only).
/// `mapsSpilled`: the error maps are kept in a spill file, not held.
struct TileModel {
    bool banded = false;
    int concurrency = 1;
    bool mapsSpilled = false;
};

/// The model of a run: banded when the spill is on (`spillOn`), the bank holds no results and
/// `concurrency` filters under way cost less than every member's result; the maps spilled when
/// their spill is on (`mapSpillOn`).
TileModel autoTileModel(const FilterBank& bank, bool spillOn, bool mapSpillOn, int concurrency);

/// The bytes the selection holds besides its input frame and its tiles, whatever their height:
/// half A's own layers (half B and the rest are the frame's, shared; or SURE's input and its
/// perturbed copy), the error maps unless spilled, the most the stages' frame-sized images take
/// at once (the blend's, or the stacking's with a tile of its own) and with `model.banded` the
/// bands.
std::uint64_t autoFixedMemory(const FilterBank& bank, const FrameBuffers& frame,
                              const AutoSettings& settings, const TileModel& model = {});

/// The model's estimate of the selection's peak with `budget`: the input frame, the fixed part
/// and a tile of autoTileRows' height (what the process holds besides its code and libraries).
std::uint64_t autoMemoryEstimate(const FilterBank& bank, const FrameBuffers& frame,
                                 const AutoSettings& settings, std::uint64_t budget,
                                 const TileModel& model = {});

/// The rows of a band: the most with every member's result (three per final candidate when the
/// stacking blends the halves too) within kBandBytes, at least 1.
int autoBandRows(const FilterBank& bank, const AutoSettings& settings);

/// The tile height for `budget`: the region's height (one tile) when it fits, else the tallest
/// that does, at least kMinTileRows, evened out so that the tiles are alike.
int autoTileRows(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                 std::uint64_t budget, const TileModel& model = {});

/// Whether the members' results that a later pass reads again are kept in the spill file
/// (strip_spill.h): Auto when the disk has room for them, On without that check, Off never (they
/// are filtered again: the same floats).
enum class SpillMode { Auto, On, Off };

/// How the pipeline is cut: `rows` per tile (0: from the memory budget), the spill, and
/// `bandRows` (0: from the model; > 0: banded, with bands of that many rows, when the spill is
/// on and the bank holds no results).
struct TileControl {
    int rows = 0;
    SpillMode spill = SpillMode::Auto;
    int bandRows = 0;
};

/// What the pipeline gives besides the result.
struct TiledAuto {
    AutoResult result;
    bool spilled = false;          ///< StreamedAuto::spilled
    std::string warning;           ///< StreamedAuto::warning
    int bandRows = 0;              ///< the reductions' bands (0: not banded)
    bool mapsSpilled = false;      ///< the error maps were kept in a spill file
    std::uint64_t spillBytes = 0;  ///< written to the results' spill file (StripSpill)
};

/// autoComposite with its tiles given: `bank` with its results (read by rows) or without them
/// (bankWithoutResults: the members are applied tile by tile).
TiledAuto autoCompositeTiled(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoOptions& options, const TileControl& control);

/// autoCompositeStreamed with its tiles given.
StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options, const TileControl& control);

}  // namespace glint::denoise::detail
