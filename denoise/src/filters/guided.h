// guided: the guided filter of He et al. (2010, 2013), O(1) in the radius.
#pragma once

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// Which image steers the guided filter (the index of its "guide" choice parameter).
enum class GuideKind : int { ColorLuminance = 0, Albedo = 1, Normal = 2, Depth = 3 };

/// The registered "guided" filter.
class GuidedFilter final : public Filter {
  public:
    GuidedFilter();
    std::string_view name() const override { return "guided"; }
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
