// The blend of the automatic selection (docs/auto.md, "Blend"): the composite Σ w·f of the
// members' results under their (feathered) weight planes, and the layers and choice map.
#pragma once

#include <cstddef>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise {
class WorkContext;
}  // namespace glint::denoise

namespace glint::denoise::detail {

/// One row of the blend Σ weight · result over the members that have a weight plane, in member
/// order, in double (3 values per pixel into `sum`, width × 3), `results` per member: the
/// composite, the unfeathered composite feathering gates against, and the blends on the halves
/// that the stacking corrects. The results may cover a strip of rows from `resultsY0` on (the
/// pipeline's tiles): row y of the planes is row y − resultsY0 of the results. A member
/// without a result (null) must have weight 0 in the row.
void blendRow(const std::vector<Image>& planes, const std::vector<const Image*>& results, int y,
              std::vector<double>& sum, int resultsY0 = 0);

/// The blend stage over rows [y0, y1) (one tile): blendRow of the `used` members' `results`
/// (rows from y0 on) into `out` (3 channels, region-sized) and, when given, the member of
/// largest weight per pixel into `choice` (1 channel, as float). Rows through `work`.
void blendRows(const std::vector<Image>& planes, const std::vector<std::size_t>& used,
               const std::vector<const Image*>& results, int y0, int y1, Image& out, Image* choice,
               WorkContext& work);

}  // namespace glint::denoise::detail
