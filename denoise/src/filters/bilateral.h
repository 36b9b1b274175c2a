// bilateral: exact brute-force bilateral filter of the colour (Tomasi & Manduchi 1998).
#pragma once

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// Largest window radius of the bilateral filters (a 201×201 window).
inline constexpr int kBilateralMaxRadius = 100;

/// Window radius of the bilateral filters: `radiusParam` when > 0 (d = 2 radius + 1, so d = 31 is
/// radius 15), else ceil(3 sigmaS); clamped to [1, kBilateralMaxRadius].
int bilateralRadius(double sigmaS, int radiusParam);

/// The shared ParamSpecs sigmaS, sigmaR and radius of "bilateral" and "bilateral-mc".
std::vector<ParamSpec> bilateralParamSpecs();

/// The registered "bilateral" filter: every pixel of the (2r+1)^2 window is visited.
class BilateralFilter final : public Filter {
  public:
    BilateralFilter();
    std::string_view name() const override { return "bilateral"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
