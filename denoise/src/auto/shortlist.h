// The shortlist of the automatic selection (docs/auto.md, "Shortlist"): with the halves on both
// sides, only the members that carry the most weight in a first, one-sided choice are filtered on
// B too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glint::denoise::detail {

struct Choice;

/// The `size` members that carry the largest weight at the most pixels in `first` (then by total
/// weight, then member order), ascending.
std::vector<std::size_t> shortlistOf(const Choice& first, std::size_t size);

}  // namespace glint::denoise::detail
