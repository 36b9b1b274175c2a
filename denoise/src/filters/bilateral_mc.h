// bilateral-mc: Monte Carlo bilateral filter by Poisson-disk subsampling of the window
// (Banterle et al. 2012).
#pragma once

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// Number of precomputed patterns each pixel picks one from.
inline constexpr int kBilateralMcPatterns = 64;

/// The registered "bilateral-mc" filter.
class BilateralMcFilter final : public Filter {
  public:
    BilateralMcFilter();
    std::string_view name() const override { return "bilateral-mc"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
