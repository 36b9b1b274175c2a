// PLACEHOLDER until the filter lands: replaced by the real implementation.
#include <stdexcept>

#include "filters/factories.h"

namespace glint::denoise {
std::unique_ptr<Filter> makeBilateralFilter() { throw std::logic_error("bilateral filter not implemented yet"); }
}  // namespace glint::denoise
