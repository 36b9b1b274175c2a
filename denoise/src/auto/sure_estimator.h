// The SURE estimator of the automatic selection (docs/auto.md, "Error estimation by SURE"): each
// member's error from the render's variance layer and one more application of the member to a
// perturbed input: its building blocks (checkSureInput, perturbColor, sureMap …) and the
// estimator over a bank.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "estimator.h"
#include "glint/denoise/auto.h"
#include "options.h"

namespace glint::denoise::detail {

/// Throws glint::Error naming `file` and the place unless `frame` can be used for SURE: it needs
/// the variance layer (variance.R/G/B, the variance of the mean) and finite colour and finite,
/// non-negative variance at every pixel. Format for a missing layer, Numeric for bad values.
void checkSureInput(const FrameBuffers& frame, const std::string& file = {});

/// The ±1 field b: value (x, y, c) from hash(seed, pixel, channel), so any region or thread
/// count gets the same numbers. 3 channels, width × height.
Image rademacherField(int width, int height, std::uint64_t seed);

/// `frame` with its colour perturbed to y + ε·b (ε from the variance, see SureOptions: `variance`
/// when given, else the frame's variance layer). Other layers are unchanged (feature-guided
/// filters see the same guides). `delta`, when given, receives the perturbation actually applied
/// (after float rounding): (y + εb) − y.
FrameBuffers perturbColor(const FrameBuffers& frame, const SureOptions& options,
                          Image* delta = nullptr, const Image* variance = nullptr);

/// Per pixel and channel over `region`: (perturbedOutput − output) / delta (Ramani et al.'s
/// estimate with b/ε = 1/delta). `output` and `perturbedOutput` are region-sized, `delta`
/// frame-sized.
Image monteCarloDivergence(const Image& output, const Image& perturbedOutput, const Image& delta,
                           const Rect& region);

/// Per-pixel SURE over `region` summed over the channels (1 channel, region-sized):
/// Σ_c weight_c ((f − y)² − σ² + 2σ² div). `noisy` and `variance` are frame-sized; `output`,
/// `divergence` and `weight` (3 channels, optional: 1 everywhere) region-sized.
Image sureMap(const Image& noisy, const Image& variance, const Image& output,
              const Image& divergence, const Rect& region, const Image* weight = nullptr);

/// One filter's SURE: its output, its divergence (the filter's own or Monte Carlo) and the
/// per-pixel SURE map, over `region` (the whole frame when empty).
struct SureEstimate {
    Image output;           ///< 3 channels, region-sized
    Image divergence;       ///< 3 channels, region-sized
    Image sure;             ///< 1 channel, region-sized, summed over RGB
    bool analytic = false;  ///< the filter gave its divergence
};

/// Applies `filter` (resolved `params`) to `frame` and to its perturbed copy and returns the
/// SURE estimate. Throws like checkSureInput, and like applyFilter.
SureEstimate estimateSure(const Filter& filter, const FrameBuffers& frame,
                          const ParamValues& params, const SureOptions& options = {},
                          const std::optional<Rect>& region = std::nullopt,
                          const ProgressFn& progress = {});

/// SURE of every member of `bank` (built from `frame`) over the bank's region, weighted per
/// value by `weight` (the tangent weights; null: 1). The variance of the mean is the frame's
/// variance layer or, with the image-only estimator (settings.estimator == Image), the one
/// estimateImageNoise makes from the frame (image_noise.h).
class SureEstimator final : public ErrorEstimator {
  public:
    /// Prepares the input the members see (prefiltered as the bank's, settings.prefilter), the
    /// variance (estimated, with the image-only estimator) and the perturbed input. `bank`,
    /// `frame` and `weight` must outlive the estimator.
    SureEstimator(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                  const Image* weight);
    MemberEstimate estimate(std::size_t member, const ProgressFn& going) override;
    double noiseVariance(int x, int y, int c) const override;

    /// The input the members see (prefiltered like the bank's).
    const FrameBuffers& filterInput() const { return m_filterInput; }
    /// estimate()'s map over `region`, a part of the bank's, from the member's `output` there,
    /// weighted by `weight` (region-sized; null: 1): for the pipeline's tiles.
    MemberEstimate mapOver(std::size_t member, const Rect& region, const Image& output,
                           const Image* weight, const ProgressFn& going) const;

  private:
    const FilterBank& m_bank;
    const FrameBuffers& m_frame;
    SureOptions m_options;
    const Image* m_weight;
    FrameBuffers m_filterInput, m_perturbed;
    Image m_delta;
    Image m_estimatedVariance;  ///< the image-only estimator's (else empty)
    const Image* m_variance;    ///< the variance of the mean SURE uses
};

}  // namespace glint::denoise::detail
