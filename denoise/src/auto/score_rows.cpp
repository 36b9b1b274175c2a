// The choice's window scores strip by strip (score_rows.h).
#include "score_rows.h"

#include <algorithm>
#include <cmath>

#include "glint/image/error.h"

namespace glint::denoise::detail {

ScoreRows::ScoreRows(int width, int height, std::vector<int> radii, double confidence)
    : m_width(width),
      m_height(height),
      m_confidence(confidence),
      m_planes(confidence > 0.0 ? 2 : 1) {
    GLINT_CHECK(width > 0 && height > 0 && !radii.empty());
    const std::size_t w = std::size_t(width);
    for (int radius : radii) {
        m_reach = std::max(m_reach, radius);
        Pass p;
        p.radius = radius;
        if (radius > 0) {
            p.sum.assign(w * m_planes, 0.0);
            p.ring.assign(std::size_t(2 * radius + 2) * w * m_planes, 0.0);
            p.prefix.assign((w + 1) * m_planes, 0.0);
        }
        m_passes.push_back(std::move(p));
    }
}

std::size_t ScoreRows::ringOffset(const Pass& pass, int y) const {
    const std::size_t slot = std::size_t(y % (2 * pass.radius + 2));
    return slot * std::size_t(m_width) * m_planes;
}

int ScoreRows::rowsReadEnd(int y1) const {
    return std::min(m_height, y1 + m_reach);
}

// Row y's horizontal box averages into its ring slot (boxAveragesOfRows's first pass, with
// windowScore's terms).
void ScoreRows::horizontal(Pass& pass, int y) {
    const int w = m_width, radius = pass.radius;
    const std::size_t planes = m_planes;
    std::vector<double>& prefix = pass.prefix;
    std::fill(prefix.begin(), prefix.begin() + std::ptrdiff_t(planes), 0.0);
    const float* raw = rawRow(y);
    const float* base = baseRow(y);
    for (int x = 0; x < w; ++x) {
        const double v = double(raw[x]) - double(base[x]);
        double* t = prefix.data() + planes + std::size_t(x) * planes;
        t[0] = double(float(v));
        if (planes == 2) t[1] = double(float(v * v));
    }
    for (std::size_t i = planes; i < prefix.size(); ++i) prefix[i] += prefix[i - planes];
    double* out = pass.ring.data() + ringOffset(pass, y);
    const double inner = 1.0 / double(2 * radius + 1);
    for (int x = 0; x < w; ++x) {
        const auto x0 = std::size_t(std::max(0, x - radius)),
                   x1 = std::size_t(std::min(w, x + radius + 1));
        const double scale = x1 - x0 == std::size_t(2 * radius + 1) ? inner : 1.0 / double(x1 - x0);
        for (std::size_t k = 0; k < planes; ++k)
            out[std::size_t(x) * planes + k] =
                (prefix[x1 * planes + k] - prefix[x0 * planes + k]) * scale;
    }
}

void ScoreRows::next(int y0, int y1, const Image& rawRows, const Image& baseRows, int rowsY0,
                     float* out) {
    GLINT_CHECK(y0 == m_next && y1 >= y0 && y1 <= m_height);
    GLINT_CHECK(rawRows.sameShape(baseRows) && rawRows.channels() == 1 &&
                rawRows.width() == m_width && rowsY0 <= y0 &&
                rowsY0 + rawRows.height() >= rowsReadEnd(y1));
    m_raw = &rawRows, m_base = &baseRows, m_rowsY0 = rowsY0;
    m_next = y1;
    const int w = m_width, h = m_height;
    const std::size_t planes = m_planes;
    const std::size_t span = std::size_t(w) * planes;
    const double confidence = m_confidence;
    for (std::size_t q = 0; q < m_passes.size(); ++q) {
        Pass& pass = m_passes[q];
        const int radius = pass.radius;
        const double count = double((2 * radius + 1) * (2 * radius + 1));
        auto scoreOf = [&](float mean, float meanSq) {
            const double mu = mean;
            const double var = std::max(0.0, double(meanSq) - mu * mu);
            return float(mu + confidence * std::sqrt(var / count));
        };
        // The lowest score over the radii (the first pass writes, the others lower).
        auto put = [&](float* to, float score) { *to = q == 0 ? score : std::min(*to, score); };
        if (radius == 0) {  // windowScore's pointwise case
            for (int y = y0; y < y1; ++y) {
                const float* raw = rawRow(y);
                const float* base = baseRow(y);
                float* o = out + std::size_t(y - y0) * std::size_t(w);
                for (int x = 0; x < w; ++x) {
                    const double v = double(raw[x]) - double(base[x]);
                    put(o + x, planes == 1 ? float(v) : scoreOf(float(v), float(v * v)));
                }
            }
            continue;
        }
        std::vector<double>& sum = pass.sum;
        if (y0 == 0 && y1 > 0)
            for (int y = 0; y < std::min(h, radius); ++y) {
                horizontal(pass, y);
                const double* row = pass.ring.data() + ringOffset(pass, y);
                for (std::size_t i = 0; i < span; ++i) sum[i] += row[i];
            }
        for (int y = y0; y < y1; ++y) {
            const int entering = y + radius, leaving = y - radius - 1;
            if (entering < h) {
                horizontal(pass, entering);
                const double* row = pass.ring.data() + ringOffset(pass, entering);
                for (std::size_t i = 0; i < span; ++i) sum[i] += row[i];
            }
            if (leaving >= 0) {
                const double* row = pass.ring.data() + ringOffset(pass, leaving);
                for (std::size_t i = 0; i < span; ++i) sum[i] -= row[i];
            }
            const double scale =
                1.0 / double(std::min(h, y + radius + 1) - std::max(0, y - radius));
            float* o = out + std::size_t(y - y0) * std::size_t(w);
            for (int x = 0; x < w; ++x) {
                const double m0 = sum[std::size_t(x) * planes] * scale;
                const float score =
                    planes == 1
                        ? float(m0)
                        : scoreOf(float(m0), float(sum[std::size_t(x) * planes + 1] * scale));
                put(o + x, score);
            }
        }
    }
}

}  // namespace glint::denoise::detail
