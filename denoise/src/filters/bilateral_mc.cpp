// PLACEHOLDER until the filter lands: replaced by the real implementation.
#include <stdexcept>

#include "filters/factories.h"

namespace glint::denoise {
std::unique_ptr<Filter> makeBilateralMcFilter() { throw std::logic_error("bilateral_mc filter not implemented yet"); }
}  // namespace glint::denoise
