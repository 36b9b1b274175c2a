// Factory functions of the built-in filters (one per filter file pair); used by registry.cpp only.
#pragma once

#include <memory>

#include "glint/denoise/filter.h"

namespace glint::denoise {

std::unique_ptr<Filter> makeGaussianFilter();
std::unique_ptr<Filter> makeBilateralFilter();
std::unique_ptr<Filter> makeBilateralMcFilter();
std::unique_ptr<Filter> makeCrossBilateralFilter();
std::unique_ptr<Filter> makeGuidedFilter();
std::unique_ptr<Filter> makeNlMeansFilter();
std::unique_ptr<Filter> makeNforFilter();
std::unique_ptr<Filter> makeUNetFilter();  // src/learned/unet_filter.cpp
std::unique_ptr<Filter> makeExternalFilter();
std::unique_ptr<Filter> makeIdentityFilter();

}  // namespace glint::denoise
