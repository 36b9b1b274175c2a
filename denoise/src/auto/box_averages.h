// Box averages of several planes at once (the automatic selection's window scores, smoothing and
// feathering, and the stacking's regression): one pass of prefix sums and running sums in double,
// deterministic whatever the thread count.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <vector>

#include "glint/denoise/progress.h"

namespace glint::denoise::detail {

// Box averages over (2·radius + 1)² pixels, truncated at the border, of `planes` values per
// pixel of a width × height grid: fillRow(y, terms) writes row y's terms (doubles of floats),
// pixel x's `planes` values at terms[x·planes …], and emit(x, y, means) receives each pixel's
// `planes` averages. Horizontal prefix differences, then vertical running sums, in double; each
// column's sum is updated in row order within a fixed block of columns, so every average is
// computed from the same terms in the same order whatever the thread count. radius ≥ 1.
// `scratch`, if given, holds the horizontal pass (so that repeated calls reuse its memory).
// `work`, if given, counts each row of each pass as one unit (2·h in all) and stops both passes
// once cancelled (then throws Error(Cancelled)).
template <class FillRow, class Emit>
void boxAveragesOfRows(int w, int h, int radius, std::size_t planes, FillRow fillRow, Emit emit,
                       std::vector<double>* scratch = nullptr, WorkContext* work = nullptr) {
    std::vector<double> own;
    std::vector<double>& horizontal = scratch ? *scratch : own;
    horizontal.resize(std::size_t(w) * std::size_t(h) * planes);
    if (work) work->throwIfCancelled();
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        if (work && work->cancelled()) return;
        std::vector<double> prefix((std::size_t(w) + 1) * planes);  // one per range, not per row
        for (int y = rows.begin(); y < rows.end(); ++y) {
            std::fill(prefix.begin(), prefix.begin() + std::ptrdiff_t(planes), 0.0);
            fillRow(y, prefix.data() + planes);
            for (std::size_t i = planes; i < prefix.size(); ++i) prefix[i] += prefix[i - planes];
            double* out = horizontal.data() + std::size_t(y) * std::size_t(w) * planes;
            const double inner = 1.0 / double(2 * radius + 1);
            for (int x = 0; x < w; ++x) {
                const auto x0 = std::size_t(std::max(0, x - radius)),
                           x1 = std::size_t(std::min(w, x + radius + 1));
                const double scale =
                    x1 - x0 == std::size_t(2 * radius + 1) ? inner : 1.0 / double(x1 - x0);
                for (std::size_t k = 0; k < planes; ++k)
                    out[std::size_t(x) * planes + k] =
                        (prefix[x1 * planes + k] - prefix[x0 * planes + k]) * scale;
            }
        }
        if (work) work->addWork(rows.size());
    });
    if (work) work->throwIfCancelled();
    constexpr int kBlock = 256;
    tbb::parallel_for(0, (w + kBlock - 1) / kBlock, [&](int block) {
        if (work && work->cancelled()) return;
        const int bx0 = block * kBlock, bx1 = std::min(w, bx0 + kBlock);
        const std::size_t span = std::size_t(bx1 - bx0) * planes;
        std::vector<double> sum(span, 0.0), means(planes);
        auto row = [&](int y) {
            return horizontal.data() +
                   (std::size_t(y) * std::size_t(w) + std::size_t(bx0)) * planes;
        };
        for (int y = 0; y < std::min(h, radius); ++y)
            for (std::size_t i = 0; i < span; ++i) sum[i] += row(y)[i];
        for (int y = 0; y < h; ++y) {
            const int entering = y + radius, leaving = y - radius - 1;
            if (entering < h)
                for (std::size_t i = 0; i < span; ++i) sum[i] += row(entering)[i];
            if (leaving >= 0)
                for (std::size_t i = 0; i < span; ++i) sum[i] -= row(leaving)[i];
            const double scale =
                1.0 / double(std::min(h, y + radius + 1) - std::max(0, y - radius));
            for (int x = bx0; x < bx1; ++x) {
                for (std::size_t k = 0; k < planes; ++k)
                    means[k] = sum[std::size_t(x - bx0) * planes + k] * scale;
                emit(x, y, means.data());
            }
        }
    });
    if (work) {
        work->addWork(h);
        work->throwIfCancelled();
    }
}

// boxAveragesOfRows row after row, strip after strip: the same averages, value for value (each
// row's horizontal sums as boxAveragesOfRows computes them, and each column's vertical running
// sum carried from one call to the next with the same additions and subtractions in the same
// order), holding 2·radius + 2 rows of horizontal sums instead of the grid's. For a pipeline
// that produces the terms and consumes the averages a strip at a time.
class RunningBoxAverages {
  public:
    RunningBoxAverages(int w, int h, int radius, std::size_t planes)
        : m_w(w),
          m_h(h),
          m_radius(radius),
          m_planes(planes),
          m_sum(std::size_t(w) * planes, 0.0),
          m_ring(std::size_t(2 * radius + 2) * std::size_t(w) * planes, 0.0),
          m_prefix((std::size_t(w) + 1) * planes, 0.0),
          m_means(planes) {}

    /// The row the next call starts at (0 at first).
    int next() const { return m_next; }

    /// Emits rows [next(), y1): fillRow(y, terms) is called once per row, in row order, as the
    /// row enters a window (up to row y1 − 1 + radius), and emit(x, y, means) for each pixel of
    /// the emitted rows, row after row.
    template <class FillRow, class Emit>
    void advance(int y1, FillRow fillRow, Emit emit) {
        const std::size_t span = std::size_t(m_w) * m_planes;
        if (m_next == 0 && y1 > 0)
            for (int y = 0; y < std::min(m_h, m_radius); ++y) {
                const double* row = horizontal(y, fillRow);
                for (std::size_t i = 0; i < span; ++i) m_sum[i] += row[i];
            }
        for (int y = m_next; y < y1; ++y) {
            const int entering = y + m_radius, leaving = y - m_radius - 1;
            if (entering < m_h) {
                const double* row = horizontal(entering, fillRow);
                for (std::size_t i = 0; i < span; ++i) m_sum[i] += row[i];
            }
            if (leaving >= 0) {
                const double* row = m_ring.data() + ringOffset(leaving);
                for (std::size_t i = 0; i < span; ++i) m_sum[i] -= row[i];
            }
            const double scale =
                1.0 / double(std::min(m_h, y + m_radius + 1) - std::max(0, y - m_radius));
            for (int x = 0; x < m_w; ++x) {
                for (std::size_t k = 0; k < m_planes; ++k)
                    m_means[k] = m_sum[std::size_t(x) * m_planes + k] * scale;
                emit(x, y, m_means.data());
            }
        }
        m_next = std::max(m_next, y1);
    }

  private:
    std::size_t ringOffset(int y) const {
        return std::size_t(y % (2 * m_radius + 2)) * std::size_t(m_w) * m_planes;
    }
    // Row y's horizontal box averages into its ring slot (boxAveragesOfRows's first pass).
    template <class FillRow>
    const double* horizontal(int y, FillRow& fillRow) {
        const std::size_t planes = m_planes;
        std::fill(m_prefix.begin(), m_prefix.begin() + std::ptrdiff_t(planes), 0.0);
        fillRow(y, m_prefix.data() + planes);
        for (std::size_t i = planes; i < m_prefix.size(); ++i) m_prefix[i] += m_prefix[i - planes];
        double* out = m_ring.data() + ringOffset(y);
        const double inner = 1.0 / double(2 * m_radius + 1);
        for (int x = 0; x < m_w; ++x) {
            const auto x0 = std::size_t(std::max(0, x - m_radius)),
                       x1 = std::size_t(std::min(m_w, x + m_radius + 1));
            const double scale =
                x1 - x0 == std::size_t(2 * m_radius + 1) ? inner : 1.0 / double(x1 - x0);
            for (std::size_t k = 0; k < planes; ++k)
                out[std::size_t(x) * planes + k] =
                    (m_prefix[x1 * planes + k] - m_prefix[x0 * planes + k]) * scale;
        }
        return out;
    }

    int m_w, m_h, m_radius;
    std::size_t m_planes;
    int m_next = 0;
    std::vector<double> m_sum, m_ring, m_prefix, m_means;
};

// The same with value(x, y, k) giving each term (the window scores, smoothing and features).
template <class Value, class Emit>
void boxAverages(int w, int h, int radius, std::size_t planes, Value value, Emit emit,
                 std::vector<double>* scratch = nullptr, WorkContext* work = nullptr) {
    boxAveragesOfRows(
        w, h, radius, planes,
        [&](int y, double* terms) {
            for (int x = 0; x < w; ++x)
                for (std::size_t k = 0; k < planes; ++k)
                    terms[std::size_t(x) * planes + k] = value(x, y, k);
        },
        emit, scratch, work);
}

}  // namespace glint::denoise::detail
