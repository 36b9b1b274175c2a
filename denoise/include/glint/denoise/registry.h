// The filter registry: every filter, found by name.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// Every registered filter, in registration order. The registry is built once and immutable.
const std::vector<const Filter*>& allFilters();

/// A filter the default bank leaves out because it cannot run here, and why (one line).
struct LeftOutFilter {
    std::string name;
    std::string reason;  ///< Filter::unavailable: unet's missing or corrupt weights file
};

/// The filters of a bank built without a filter list (BankOptions::filters empty): every
/// registered filter except the opt-in ones (nfor, external), which join a bank only when named,
/// and those unavailable with their defaults (Filter::unavailable: unet without its weights),
/// which are added to `leftOut` when given. Checked on every call (the weights folder may change).
std::vector<const Filter*> defaultBankFilters(std::vector<LeftOutFilter>* leftOut = nullptr);

/// The filter called `name`; throws glint::Error(InvalidArgument) listing the valid names.
const Filter& findFilter(std::string_view name);

}  // namespace glint::denoise
