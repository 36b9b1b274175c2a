#include "sampling/distribution.h"

#include <algorithm>

#include "glint/image/error.h"

namespace glint::render {

Distribution1D::Distribution1D(std::span<const float> values)
    : m_func(values.begin(), values.end()), m_cdf(values.size() + 1, 0.0) {
    GLINT_CHECK(!values.empty(), "a distribution needs at least one bin");
    const double n = double(values.size());
    // Running sum of bin integrals (bin width 1/n), in double so long tables do not drift.
    for (std::size_t i = 0; i < values.size(); ++i) {
        GLINT_CHECK(values[i] >= 0.0f && std::isfinite(values[i]),
                    "distribution values must be finite and non-negative");
        m_cdf[i + 1] = m_cdf[i] + double(values[i]) / n;
    }
    m_integral = m_cdf.back();
    if (m_integral == 0.0) {
        // Degenerate: fall back to a uniform density.
        std::fill(m_func.begin(), m_func.end(), 1.0f);
        for (std::size_t i = 0; i <= values.size(); ++i) m_cdf[i] = double(i) / n;
    } else {
        for (double& c : m_cdf) c /= m_integral;
    }
    m_cdf.back() = 1.0;
}

namespace {
// Last index i with cdf[i] <= u, clamped to [0, n-1].
int findBin(const std::vector<double>& cdf, double u) {
    // A few bins (the lights of most scenes) are found faster by a scan than by bisection.
    constexpr std::size_t kScanBelow = 9;
    int i;
    if (cdf.size() < kScanBelow) {
        i = 0;
        while (std::size_t(i) + 1 < cdf.size() && cdf[std::size_t(i) + 1] <= u) ++i;
    } else {
        i = int(std::upper_bound(cdf.begin(), cdf.end(), u) - cdf.begin()) - 1;
    }
    return std::clamp(i, 0, int(cdf.size()) - 2);
}
}  // namespace

float Distribution1D::sampleContinuous(float u, float* pdf, int* bin) const {
    const int i = findBin(m_cdf, u);
    if (bin) *bin = i;
    // Skip zero-probability bins chosen by rounding at their edges.
    const double width = m_cdf[i + 1] - m_cdf[i];
    double du = width > 0.0 ? (double(u) - m_cdf[i]) / width : 0.0;
    du = std::clamp(du, 0.0, 1.0);
    const double density = m_integral > 0.0 ? double(m_func[i]) / m_integral : 1.0;
    if (pdf) *pdf = float(density);
    const float x = float((double(i) + du) / double(size()));
    return std::min(x, 0x1.fffffep-1f);
}

int Distribution1D::sampleDiscrete(float u, float* probability, float* remapped) const {
    const int i = findBin(m_cdf, u);
    const double width = m_cdf[i + 1] - m_cdf[i];
    if (probability) *probability = float(width);
    if (remapped) {
        const double r = width > 0.0 ? (double(u) - m_cdf[i]) / width : 0.0;
        *remapped = std::min(float(std::clamp(r, 0.0, 1.0)), 0x1.fffffep-1f);
    }
    return i;
}

float Distribution1D::pdf(float x) const {
    const int i = std::clamp(int(x * float(size())), 0, size() - 1);
    return m_integral > 0.0 ? float(double(m_func[i]) / m_integral) : 1.0f;
}

float Distribution1D::discretePdf(int i) const {
    return float(m_cdf[i + 1] - m_cdf[i]);
}

float Distribution1D::invert(float x) const {
    const double xs = std::clamp(double(x), 0.0, 1.0) * double(size());
    const int i = std::clamp(int(xs), 0, size() - 1);
    const double t = xs - double(i);
    return float(m_cdf[i] + t * (m_cdf[i + 1] - m_cdf[i]));
}

Distribution2D::Distribution2D(std::span<const float> values, int nu, int nv) : m_nu(nu), m_nv(nv) {
    GLINT_CHECK(nu > 0 && nv > 0 && values.size() == std::size_t(nu) * std::size_t(nv));
    m_conditional.reserve(std::size_t(nv));
    std::vector<float> marginal(static_cast<std::size_t>(nv));
    for (int v = 0; v < nv; ++v) {
        m_conditional.emplace_back(values.subspan(std::size_t(v) * nu, std::size_t(nu)));
        marginal[v] = float(m_conditional.back().integral());
    }
    m_marginal = Distribution1D(marginal);
}

Vec2 Distribution2D::sample(Vec2 u, float* pdf) const {
    // Sample the row from the marginal, then the column from that row's conditional.
    float pdfV = 0.0f, pdfU = 0.0f;
    int row = 0;
    const float v = m_marginal.sampleContinuous(u.y, &pdfV, &row);
    const float x = m_conditional[row].sampleContinuous(u.x, &pdfU);
    if (pdf) *pdf = pdfV * pdfU;
    return {x, v};
}

float Distribution2D::pdf(Vec2 uv) const {
    const int row = std::clamp(int(uv.y * float(m_nv)), 0, m_nv - 1);
    return m_marginal.pdf(uv.y) * m_conditional[row].pdf(uv.x);
}

Vec2 Distribution2D::invert(Vec2 uv) const {
    const int row = std::clamp(int(uv.y * float(m_nv)), 0, m_nv - 1);
    return {m_conditional[row].invert(uv.x), m_marginal.invert(uv.y)};
}

}  // namespace glint::render
