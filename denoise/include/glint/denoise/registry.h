// The filter registry: every filter, found by name.
#pragma once

#include <string_view>
#include <vector>

#include "glint/denoise/filter.h"

namespace glint::denoise {

/// Every registered filter, in registration order. The registry is built once and immutable.
const std::vector<const Filter*>& allFilters();

/// The filters of a bank built without a filter list (BankOptions::filters empty): every
/// registered filter except the opt-in ones (nfor, external), which join a bank only when named.
const std::vector<const Filter*>& defaultBankFilters();

/// The filter called `name`; throws glint::Error(InvalidArgument) listing the valid names.
const Filter& findFilter(std::string_view name);

}  // namespace glint::denoise
