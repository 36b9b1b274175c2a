// PLACEHOLDER until the filter lands: replaced by the real implementation.
#include <stdexcept>

#include "filters/factories.h"

namespace glint::denoise {
std::unique_ptr<Filter> makeGaussianFilter() { throw std::logic_error("gaussian filter not implemented yet"); }
}  // namespace glint::denoise
