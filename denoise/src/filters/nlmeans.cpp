// PLACEHOLDER until the filter lands: replaced by the real implementation.
#include <stdexcept>

#include "filters/factories.h"

namespace glint::denoise {
std::unique_ptr<Filter> makeNlMeansFilter() { throw std::logic_error("nlmeans filter not implemented yet"); }
}  // namespace glint::denoise
