// The choice's window scores strip by strip (docs/auto-memory.md): the same values as
// windowScore over the whole maps, row after row, holding only a few rows of box sums.
#pragma once

#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// The score of one candidate (windowScore of a map `raw` against `base` at each of `radii`, the
/// lowest), produced in row order, strip after strip. Equal value for value to windowScore over
/// the whole maps: each row's horizontal box sums are computed as boxAveragesOfRows computes
/// them, and the vertical running sums carry from one strip to the next with the same additions
/// and subtractions in the same order (boxAveragesOfRows's per-column order). Holds 2·radius + 2
/// rows of horizontal sums per radius; the maps' rows are given strip by strip (rowsRead), so
/// that they may be read from a file rather than held.
class ScoreRows {
  public:
    /// A score of maps of width × height (1 channel).
    ScoreRows(int width, int height, std::vector<int> radii, double confidence);

    /// The rows of the maps that next(y0, y1, …) reads: [y0, min(height, y1 + the largest
    /// radius)).
    int rowsReadEnd(int y1) const;

    /// Rows [y0, y1) of the score into `out` (width × (y1 − y0) values); y0 is 0 on the first
    /// call and the previous call's y1 after. `rawRows` and `baseRows` (1 channel, of one size
    /// and the maps' width) hold the maps' rows from row `rowsY0` on, at least
    /// [y0, rowsReadEnd(y1)).
    void next(int y0, int y1, const Image& rawRows, const Image& baseRows, int rowsY0, float* out);

  private:
    struct Pass {
        int radius = 0;
        std::vector<double> sum;   // per column and plane: the vertical running sums
        std::vector<double> ring;  // the horizontal sums of rows y − radius − 1 … y + radius
        std::vector<double> prefix;  // one row's prefix sums
    };
    void horizontal(Pass& pass, int y);
    std::size_t ringOffset(const Pass& pass, int y) const;
    const float* rawRow(int y) const { return m_raw->row(y - m_rowsY0); }
    const float* baseRow(int y) const { return m_base->row(y - m_rowsY0); }

    int m_width, m_height;
    int m_reach = 0;  // the largest radius
    // The rows of next()'s call under way.
    const Image* m_raw = nullptr;
    const Image* m_base = nullptr;
    int m_rowsY0 = 0;
    double m_confidence;
    std::size_t m_planes;
    int m_next = 0;
    std::vector<Pass> m_passes;
};

}  // namespace glint::denoise::detail
