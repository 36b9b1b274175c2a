// nfor: nonlinearly weighted first-order regression (Bitterli et al. 2016).
#pragma once

#include "glint/denoise/filter.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// The registered "nfor" filter.
class NforFilter final : public Filter {
  public:
    NforFilter();
    std::string_view name() const override { return "nfor"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    std::vector<Layer> requiredLayers(const ParamValues& params) const override;
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
