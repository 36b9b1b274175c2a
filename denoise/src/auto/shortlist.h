// The shortlist of the automatic selection (docs/auto.md, "Shortlist"): with the halves on both
// sides, only the members that carry the most weight in a first, one-sided choice are filtered on
// B too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace glint::denoise {
class WorkContext;
}

namespace glint::denoise::detail {

class HalvesEstimator;
struct Estimates;
struct Choice;

/// The `size` members that carry the largest weight at the most pixels in `first` (then by total
/// weight, then member order), ascending.
std::vector<std::size_t> shortlistOf(const Choice& first, std::size_t size);

/// Filters the `shortlist` members on B (members in parallel through `work`, `unitsPerMember`
/// units each), makes their maps the symmetric form — the average of the A-side and B-side
/// terms — and updates their map means and estimated MSEs in `estimates`. With `keepResults` the
/// other members' results on A are dropped first. Throws Error(Cancelled) once cancelled.
void filterShortlistOnB(HalvesEstimator& halves, const std::vector<std::size_t>& shortlist,
                        bool keepResults, Estimates& estimates, WorkContext& work,
                        std::int64_t unitsPerMember);

}  // namespace glint::denoise::detail
