// nlmeans: non-local means with the variance-normalised patch distance of Rousselle et al. 2012.
#pragma once

#include <array>

#include "glint/denoise/filter.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// Per-channel noise variance of `image` (channels 0..2) estimated from the whole image with
/// Immerkær's Laplacian-difference estimator (CVIU 1996): sigma = sqrt(pi/2) / (6 N) *
/// sum |I * L| over interior pixels whose 3×3 neighbourhood is finite. 0 for images under 3×3.
std::array<double, 3> estimateNoiseVariance(const Image& image);

/// The registered "nlmeans" filter.
class NlMeansFilter final : public Filter {
  public:
    NlMeansFilter();
    std::string_view name() const override { return "nlmeans"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
