// The SURE estimator of the automatic selection (docs/auto.md, "Error estimation by SURE"): each
// member's error from the render's variance layer and one more application of the member to a
// perturbed input. The building blocks (checkSureInput, perturbColor, sureMap …) are in sure.h.
#pragma once

#include <vector>

#include "estimator.h"
#include "glint/denoise/sure.h"

namespace glint::denoise::detail {

/// SURE of every member of `bank` (built from `frame`) over the bank's region, weighted per
/// value by `weight` (the tangent weights; null: 1).
class SureEstimator final : public ErrorEstimator {
  public:
    /// Prepares the input the members see (prefiltered as the bank's, options.prefilter) and its
    /// perturbed copy. `bank`, `frame` and `weight` must outlive the estimator.
    SureEstimator(const FilterBank& bank, const FrameBuffers& frame, const AutoOptions& options,
                  const Image* weight);
    MemberEstimate estimate(std::size_t member, const ProgressFn& going) override;
    double noiseVariance(int x, int y, int c) const override;

  private:
    const FilterBank& m_bank;
    const FrameBuffers& m_frame;
    SureOptions m_options;
    const Image* m_weight;
    FrameBuffers m_filterInput, m_perturbed;
    Image m_delta;
};

}  // namespace glint::denoise::detail
