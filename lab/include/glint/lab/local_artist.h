// The local artist: the thesis's workflow simulated as an artist does it. Repeat: pick a region
// (where the bank's members disagree, or where the composite looks wrong), navigate that
// region's bank (the navigation tree over the region's crop, the simulated user picking the
// child closest to the reference there), paint the chosen member into the composite with the
// soft brush, and keep the stroke if the whole composite got closer to the reference
// (glint-lab navigate --simulate --local; docs/lab/navigation.md, "The local artist in detail"): it
// measures the claim that local choices beat any global filter.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "glint/denoise/bank.h"
#include "glint/denoise/navigation.h"
#include "glint/denoise/paint.h"
#include "glint/image/image.h"

namespace glint::lab {

/// Where the artist strokes next.
enum class ArtistPick {
    /// Where the bank's members disagree most (filterVarianceMap averaged over the brush):
    /// needs no reference.
    Variance,
    /// Where the composite is furthest from the reference (1 − SSIM map averaged over the
    /// brush): the artist sees what looks wrong.
    Error,
};

/// Parses "variance" / "error"; throws glint::Error(InvalidArgument).
ArtistPick parseArtistPick(const std::string& name);
/// "variance" or "error".
const char* artistPickName(ArtistPick pick);

/// How the simulated artist works.
struct LocalArtistOptions {
    int strokes = 30;  ///< strokes tried, 1 … 10000 (a stroke undone still counts)
    /// The soft brush of every stroke (one dab): its diameter is also the side of the region
    /// navigated, so it must be at least 11 px (SSIM's window) and fit in the bank's region.
    denoise::Brush brush{24.0, 0.5};
    ArtistPick pick = ArtistPick::Variance;
    /// The simulated user compares the options as they would look painted into the composite
    /// (true), or the members alone over the region (false: simulateUser's plain choice).
    bool inContext = true;
    /// Undo a stroke that lowers the whole composite's SSIM (the artist sees it got worse); with
    /// false every stroke stays.
    bool keepOnlyHelping = true;
    denoise::TreeOptions tree;  ///< of each region's navigation tree (k, p, distance, seed)
    float exposure = 0.0f;      ///< stops, of the display values SSIM compares
};

/// Throws glint::Error(InvalidArgument) naming the first bad option (strokes, brush, tree).
void validate(const LocalArtistOptions& options);

/// One stroke.
struct ArtistStroke {
    int stroke = 0;           ///< 1, 2, …
    double x = 0.0, y = 0.0;  ///< the dab's centre, frame coordinates
    Rect region;              ///< the region navigated, frame coordinates
    int member = -1;          ///< the bank member painted
    int choices = 0;          ///< navigation choices made to reach it
    double ssim = 0.0;        ///< of the whole composite after the stroke (or its undo)
    double ssimIfKept = 0.0;  ///< of the whole composite with the stroke painted
    bool kept = true;
};

/// The strokes and the composite they leave.
struct LocalArtistResult {
    double startSsim = 0.0;  ///< of the starting composite
    std::vector<ArtistStroke> strokes;
    Image composite;  ///< 3 channels, bank-region-sized
};

/// Runs the artist over `bank`, starting from `start` (3 channels, the bank region's size: e.g.
/// the auto composite or the best member), towards `reference` (3 channels, bank-region-sized).
/// SSIM is of display values over the bank's region. Deterministic for fixed options. Throws
/// glint::Error(InvalidArgument) for bad options, mismatched sizes or an empty bank.
LocalArtistResult localArtist(const denoise::FilterBank& bank, const Image& start,
                              const Image& reference, const LocalArtistOptions& options = {});

}  // namespace glint::lab
