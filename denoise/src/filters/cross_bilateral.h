// cross-bilateral: joint bilateral filter steered by colour, albedo, normal and depth, with
// feature distances normalised by the per-pixel variances.
#pragma once

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// The registered "cross-bilateral" filter.
class CrossBilateralFilter final : public Filter {
  public:
    CrossBilateralFilter();
    std::string_view name() const override { return "cross-bilateral"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    std::vector<Layer> requiredLayers(const ParamValues& /*params*/) const override {
        return {Layer::Albedo, Layer::Normal, Layer::Depth};
    }
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
