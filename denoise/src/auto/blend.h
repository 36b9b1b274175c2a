// The blend of the automatic selection (docs/auto.md, "Blend"): the composite Σ w·f of the
// members' results under their (feathered) weight planes, and the layers and choice map.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// Each member's result in the bank, for blendRow.
std::vector<const Image*> bankResults(const FilterBank& bank);

/// One row of the blend Σ weight · result over the members that have a weight plane, in member
/// order, in double (3 values per pixel into `sum`, width × 3), `results` per member: the
/// composite, the unfeathered composite feathering gates against, and the blends on the halves
/// that the stacking corrects. The results may cover a strip of rows from `resultsY0` on (the
/// streamed selection's): row y of the planes is row y − resultsY0 of the results. A member
/// without a result (null) must have weight 0 in the row.
void blendRow(const std::vector<Image>& planes, const std::vector<const Image*>& results, int y,
              std::vector<double>& sum, int resultsY0 = 0);

/// The blend of the bank's results under `planes` (per member; empty: no weight).
struct Blend {
    Image composite;  ///< 3 channels, region-sized
    Image choice;     ///< 1 channel: per pixel, the member of largest weight (as float)
    /// The members with any weight, largest total weight first (ties in member order).
    std::vector<int> order;
};

/// The blend stage: rows through `work`.
Blend blend(const std::vector<Image>& planes, const FilterBank& bank, WorkContext& work);

}  // namespace glint::denoise::detail
