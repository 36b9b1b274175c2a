// The stacking of the automatic selection (docs/auto.md, "Stacking"): the blend corrected per
// pixel by a local ridge regression, fitted on the halves, on the members of most weight and on
// the features' local deviations: the regressors and the regression (stack_regression.cpp); the
// pipeline (auto_composite.cpp) sets them up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// One member of the stacking (AutoOptions::stack): its results on all the samples, on half A
/// and on half B (region-sized, 3 channels). A feature regressor (featureRegressors) is one
/// too: its three images from the whole frame's features and each half's.
struct StackMember {
    const Image* full = nullptr;
    const Image* onA = nullptr;
    const Image* onB = nullptr;
};

/// The most members the stacking fits (AutoOptions::stack).
constexpr std::size_t kMaxStack = 16;
/// The most feature regressors (AutoOptions::stackFeatures: the albedo's one and the normal's
/// three), and so the most regressors stackComposite takes.
constexpr std::size_t kMaxStackFeatures = 4;
constexpr std::size_t kMaxStackRegressors = kMaxStack + kMaxStackFeatures;

/// The added albedo's floor in the relative albedo deviation (featureRegressors).
constexpr double kStackAlbedoFloor = 0.02;

/// The stacking's feature regressors (docs/auto.md, "Stacking"): for each feature channel g, the
/// image base · (1 + δ), whose deviation from `base` is base · δ, with δ g's deviation from its
/// box average over (2·radius + 1)² pixels (truncated at the border) — relative for the albedo,
/// (a_c − ā_c) / (|ā_c| + kStackAlbedoFloor) in colour channel c, one regressor; absolute for
/// each of the normal's three axes, (n_k − n̄_k) in every colour channel, three regressors. A
/// colour that is albedo times shading moves by c · Δa / a at an albedo edge and with the
/// normal as the shading does; the fit finds by how much. `albedo` and `normal` (3 channels,
/// base-sized) may be null: that feature adds nothing. A non-finite feature value counts as 0
/// in the averages, and a non-finite δ as 0. The order:
/// the albedo's, then the normal's x, y, z. Deterministic whatever the thread count.
/// `work`, if given, runs the box averages (2 units per row).
std::vector<Image> featureRegressors(const Image& base, const Image* albedo, const Image* normal,
                                     int radius, WorkContext* work = nullptr);

/// Receives rows [y0, y0 + rows[0].height()) of every feature regressor (featureRegressorStrips).
using RegressorStripSink = std::function<void(int y0, std::vector<Image>& rows)>;
/// featureRegressors strip after strip of `rows` rows, in row order, each handed to `sink`:
/// the same floats, holding 2·radius + 2 rows of box sums and one strip of regressors instead of
/// the frame's (RunningBoxAverages). `work`, if given, counts 2 units per row.
void featureRegressorStrips(const Image& base, const Image* albedo, const Image* normal, int radius,
                            int rows, const RegressorStripSink& sink, WorkContext* work = nullptr);

/// The stacking's gates: where the correction is not applied, the pixel keeps the composite,
/// clamped at 0. A correction is a model fitted in another part of its windows where it moves
///  - a pixel's display value (exposure, clamp, sRGB) by more than `gate` in a channel (auto
///    passes the feather gate; 0: no display gate), or
///  - a channel by more than `sigmas` standard errors of the render's own mean there and by more
///    than the composite's distance from that mean (the halves' mean): a pixel where the
///    composite agrees with the render has no error the stacking could have measured (0: no
///    noise gate). The standard error is the square root of `variance` (the frame's variance of
///    the mean, region-sized), or |A − B| / 2 from the halves when it is null.
/// Both catch the coefficients of a small bright light smoothed into its dark neighbours: the
/// display gate the bright ring, the noise gate the faint one of a frame of many samples.
struct StackGate {
    double gate = 0.0;
    float exposure = 0.0f;
    double sigmas = 0.0;
    const Image* variance = nullptr;
};

/// The stacking's regression (AutoOptions::stack; docs/auto.md, "Stacking"): per pixel,
/// composite + Σ_i a_i (full_i − composite), clamped at 0, over at most kMaxStackRegressors
/// members (the chosen members, then any feature regressors). The a_i minimise, over the
/// (2·radius + 1)² window (truncated at the border) and both sides,
///   Σ ω [ (blendA + Σ a_i (onA_i − blendA) − B)² + (blendB + Σ a_i (onB_i − blendB) − A)² ]
///   + (ridge · v + floor · tr(G) / K) Σ a_i²,
/// with A, B the halves' colour (region-sized), blendA / blendB the composite's weights applied
/// to the members' results on each half, ω `weight` per value (3 channels, region-sized; empty:
/// 1), G the window's normal matrix and v the window's mean of ½ Σ ω (A − B)² (the noise of
/// the targets); the floor bounds the coefficients of members that differ from the composite by
/// much less than the noise. With `smooth` = 0, a pixel whose system is zero or not positive
/// definite keeps the composite. With `smooth` > 0, the coefficients applied at a pixel are the
/// box average over (2·smooth + 1)² pixels (truncated at the border) of those fitted around
/// each pixel, a failed system counting as all 0: each window's model applied to every pixel it
/// covers, averaged. A pixel whose corrected value is not finite keeps the composite; one that a
/// gate (StackGate) stops keeps it clamped at 0.
/// Deterministic whatever the thread count. `work`, if given, runs the box averages (2 units
/// per row of each tile with its context rows, and 2 per row for the smoothing).
Image stackComposite(const Image& composite, const Image& blendA, const Image& blendB,
                     const std::vector<StackMember>& members, const Image& halfA,
                     const Image& halfB, const Image& weight, int radius, double ridge,
                     double floor, int smooth, WorkContext* work = nullptr,
                     const StackGate& gate = {});

/// Rows [y0, y1) of the stacking's regressors (StackMember's three images, each of those rows
/// only): `full` when asked for, `onA` and `onB` when the halves are.
struct StackRows {
    std::vector<Image> full, onA, onB;
};
/// Fills `rows` with rows [y0, y1) of every regressor, in stackComposite's order; `full` and
/// `halves` say which of the three are needed.
using LoadStackRows = std::function<void(int y0, int y1, bool full, bool halves, StackRows& rows)>;

/// stackComposite with the `count` regressors' results read by rows through `load` (the tiled
/// pipeline's: from the spill, the bank or the filter again) instead of held whole, and the
/// composite corrected in place: the same floats. The regression loads each tile of kStackTileRows
/// rows with its context rows once; the smoothing runs behind it, loading the results on all the
/// samples of the rows it reaches once, in row order, so that only the coefficients of rows not yet
/// smoothed are held.
Image stackComposite(Image composite, const Image& blendA, const Image& blendB, std::size_t count,
                     const LoadStackRows& load, const Image& halfA, const Image& halfB,
                     const Image& weight, int radius, double ridge, double floor, int smooth,
                     WorkContext* work = nullptr, const StackGate& gate = {});

/// The rows of the regression's tiles (each with `radius` rows of context on either side), so
/// that the sums of a 1024-wide frame with 10 regressors take about 75 MB, not ten times that.
constexpr int kStackTileRows = 128;

/// The bytes stackComposite holds besides its whole-frame images (the composite, its output
/// and the weights) for a `width`-wide region and `count` regressors: a regression tile's box
/// sums and regressors on the halves, the coefficients not yet smoothed, the smoothing's sums
/// and its rows of results on all the samples.
std::uint64_t stackTileBytes(int width, std::size_t count, int radius, int smooth);

}  // namespace glint::denoise::detail
