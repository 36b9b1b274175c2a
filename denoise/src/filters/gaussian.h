// gaussian: isotropic Gaussian blur, separable, with missing (non-finite) pixels given zero weight.
#pragma once

#include "glint/denoise/filter.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// Window radius used for a Gaussian of standard deviation `sigma` pixels: ceil(3 sigma), at
/// least 1, at most kGaussianMaxRadius.
int gaussianRadius(double sigma);
inline constexpr int kGaussianMaxRadius = 4096;

/// Gaussian blur of every channel of `image` inside `roi` (returns an image of roi's size).
/// Separable: a horizontal pass over roi plus the vertical margin, then a vertical pass. The
/// kernel is truncated at the image border and renormalised; a pixel with a non-finite channel
/// is missing (zero weight), see filter_util.h. Usable by any filter or the prefilter. Work:
/// the rows of both passes.
Image gaussianBlur(const Image& image, double sigma, const Rect& roi, WorkContext& work);

/// The registered "gaussian" filter.
class GaussianFilter final : public Filter {
  public:
    GaussianFilter();
    std::string_view name() const override { return "gaussian"; }
    std::string_view description() const override;
    const std::vector<ParamSpec>& params() const override { return m_params; }
    int margin(const ParamValues& params) const override;
    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override;
    /// The centre weight of the kernel truncated at the border, w(0)² / (Σ_x w · Σ_y w).
    std::optional<Image> divergence(const FrameBuffers& frame, const ParamValues& params,
                                    const Rect& roi) const override;

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace glint::denoise
