// The choice's window scores strip by strip (docs/auto-memory.md): the same values as
// windowScore over the whole maps, row after row, holding only a few rows of box sums.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// The score of one candidate (windowScore of `raw` against `base` at each of `radii`, the
/// lowest), produced in row order, strip after strip. Equal value for value to windowScore over
/// the whole maps: each row's horizontal box sums are computed as boxAveragesOfRows computes
/// them, and the vertical running sums carry from one strip to the next with the same additions
/// and subtractions in the same order (boxAveragesOfRows's per-column order). Holds 2·radius + 2
/// rows of horizontal sums per radius. `raw` and `base` (1 channel, of one size) must outlive it.
class ScoreRows {
  public:
    ScoreRows(const Image& raw, const Image& base, std::vector<int> radii, double confidence);

    /// Rows [y0, y1) of the score into `out` (width × (y1 − y0) values); y0 is 0 on the first
    /// call and the previous call's y1 after.
    void next(int y0, int y1, float* out);

  private:
    struct Pass {
        int radius = 0;
        std::vector<double> sum;   // per column and plane: the vertical running sums
        std::vector<double> ring;  // the horizontal sums of rows y − radius − 1 … y + radius
        std::vector<double> prefix;  // one row's prefix sums
    };
    void horizontal(Pass& pass, int y);
    std::size_t ringOffset(const Pass& pass, int y) const;

    const Image& m_raw;
    const Image& m_base;
    double m_confidence;
    std::size_t m_planes;
    int m_next = 0;
    std::vector<Pass> m_passes;
};

}  // namespace glint::denoise::detail
