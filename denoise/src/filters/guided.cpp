// guided — the guided filter of He, Sun and Tang (ECCV 2010; TPAMI 2013).
//
// In every (2r+1)^2 window w_k the output is a linear function of a guide image I:
// q_i = a_k^T I_i + b_k, with a_k = (Sigma_k + eps U)^-1 cov_k(I, p) and b_k = mean_k(p) - a_k^T
// mean_k(I) (TPAMI 2013, eqs. 5-6 for one guide channel, 19-20 for three); the output averages
// a and b over all windows covering the pixel (eq. 8). All window means are box sums in double
// with block prefix and suffix sums (no subtraction), so the cost does not depend on the radius.
// Windows are truncated at the image border; missing (NaN/Inf) colour or guide pixels are left out
// of every mean, so a constant image stays constant. A pixel whose guide is missing uses its
// window's guide mean. (Co)variances below 1e-12 of their second moment are rounding noise and
// count as 0, so a constant image of any radiance (1e-30 … 1e30) stays constant.
//
// Parameters:
//   radius  window radius r in pixels, 1 … 64 (outputs depend on the 2r pixels around the region).
//   eps     regulariser in guide units squared, 1e-8 … 1e2 (log); eps -> 0 reproduces every
//           component of the colour that is a linear function of the guide.
//   guide   color: colour luminance (0.2126 R + 0.7152 G + 0.0722 B); albedo (3 channels);
//           normal (3 channels); depth divided by the frame's mean |depth|. The albedo,
//           normal or depth layer must exist when chosen.
#include "filters/guided.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "filters/box_filter.h"
#include "filters/factories.h"
#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// The opening block of this file, verbatim (glint-denoise list prints it).
constexpr std::string_view kDescription =
    R"(guided — the guided filter of He, Sun and Tang (ECCV 2010; TPAMI 2013).

In every (2r+1)^2 window w_k the output is a linear function of a guide image I:
q_i = a_k^T I_i + b_k, with a_k = (Sigma_k + eps U)^-1 cov_k(I, p) and b_k = mean_k(p) - a_k^T
mean_k(I) (TPAMI 2013, eqs. 5-6 for one guide channel, 19-20 for three); the output averages
a and b over all windows covering the pixel (eq. 8). All window means are box sums in double
with block prefix and suffix sums (no subtraction), so the cost does not depend on the radius.
Windows are truncated at the image border; missing (NaN/Inf) colour or guide pixels are left out
of every mean, so a constant image stays constant. A pixel whose guide is missing uses its
window's guide mean. (Co)variances below 1e-12 of their second moment are rounding noise and
count as 0, so a constant image of any radiance (1e-30 … 1e30) stays constant.

Parameters:
  radius  window radius r in pixels, 1 … 64 (outputs depend on the 2r pixels around the region).
  eps     regulariser in guide units squared, 1e-8 … 1e2 (log); eps -> 0 reproduces every
          component of the colour that is a linear function of the guide.
  guide   color: colour luminance (0.2126 R + 0.7152 G + 0.0722 B); albedo (3 channels);
          normal (3 channels); depth divided by the frame's mean |depth|. The albedo,
          normal or depth layer must exist when chosen.)";

// Per-pixel guide of kind `kind` at (x, y); returns false when it is not finite.
struct GuideSource {
    GuideKind kind = GuideKind::ColorLuminance;
    const Image* color = nullptr;
    const Image* layer = nullptr;  // albedo, normal or depth
    double depthScale = 1.0;
    int channels = 1;

    bool read(int x, int y, double* g) const {
        if (kind == GuideKind::ColorLuminance) {
            const float* c = color->row(y) + std::size_t(x) * 3;
            g[0] = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        } else if (kind == GuideKind::Depth) {
            g[0] = double((*layer)(x, y, 0)) / depthScale;
        } else {
            const float* c = layer->row(y) + std::size_t(x) * 3;
            for (int i = 0; i < 3; ++i) g[i] = c[i];
        }
        for (int i = 0; i < channels; ++i)
            if (!std::isfinite(g[i])) return false;
        return true;
    }
};

// Mean |depth| over the finite pixels of the whole frame (1 when there are none or it is 0), so
// that a depth guide is scale-free and the same for any region of interest.
double meanAbsDepth(const Image& depth) {
    double sum = 0.0;
    std::size_t n = 0;
    for (float v : depth.data())
        if (std::isfinite(v)) {
            sum += std::fabs(double(v));
            ++n;
        }
    const double mean = n > 0 ? sum / double(n) : 0.0;
    return mean > 0.0 && std::isfinite(mean) ? mean : 1.0;
}

// Solves (S + eps U) a = c for a symmetric 3x3 S given as its upper triangle
// (s00, s01, s02, s11, s12, s22), by the adjugate.
void solveSym3(const double* s, double eps, const double* c, double* a) {
    const double m00 = s[0] + eps, m01 = s[1], m02 = s[2], m11 = s[3] + eps, m12 = s[4],
                 m22 = s[5] + eps;
    const double i00 = m11 * m22 - m12 * m12, i01 = m02 * m12 - m01 * m22,
                 i02 = m01 * m12 - m02 * m11, i11 = m00 * m22 - m02 * m02,
                 i12 = m01 * m02 - m00 * m12, i22 = m00 * m11 - m01 * m01;
    const double det = m00 * i00 + m01 * i01 + m02 * i02;
    if (!(det > 0.0) || !std::isfinite(det)) {
        a[0] = a[1] = a[2] = 0.0;
        return;
    }
    a[0] = (i00 * c[0] + i01 * c[1] + i02 * c[2]) / det;
    a[1] = (i01 * c[0] + i11 * c[1] + i12 * c[2]) / det;
    a[2] = (i02 * c[0] + i12 * c[1] + i22 * c[2]) / det;
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(a[i])) a[0] = a[1] = a[2] = 0.0;
}

// A (co)variance E[xy] - E[x]E[y] computed from sums of products cancels catastrophically
// when the data are nearly constant relative to their magnitude: results below 1e-12 of the
// second moment `moment` are rounding noise and read as 0 (so a constant image of any radiance
// gives a = 0, b = mean). Variances are also clamped at 0 (diagonal terms pass moment >= 0).
double roundoffToZero(double value, double moment) {
    return std::fabs(value) <= 1e-12 * std::fabs(moment) ? 0.0 : value;
}

// Channel layout of the two box-filtered stages (each padded to a multiple of 4 doubles, as
// box_filter.h requires).
struct Layout {
    int k = 1;  // guide channels
    // Stage 1: m, m I (k), m p (3), m I I^T (upper triangle), m I p^T (3k).
    int oI = 1, oP = 0, oII = 0, oIP = 0, c1 = 0;
    // Stage 2: window flag, a (3k), b (3).
    int oA = 1, oB = 0, c2 = 0;
    explicit Layout(int guideChannels) : k(guideChannels) {
        oP = oI + k;
        oII = oP + 3;
        oIP = oII + k * (k + 1) / 2;
        c1 = (oIP + 3 * k + 3) / 4 * 4;
        oB = oA + 3 * k;
        c2 = (oB + 3 + 3) / 4 * 4;
    }
};

// Stage-1 products of pixel (x, y) into e (c1 doubles, zero for a missing pixel).
void products(const Image& color, const GuideSource& guide, const Layout& L, int x, int y,
              double* e) {
    std::fill_n(e, L.c1, 0.0);
    std::array<double, 3> g{};
    const float* p = color.row(y) + std::size_t(x) * 3;
    if (!detail::isFinitePixel(p, 3) || !guide.read(x, y, g.data())) return;
    const int k = L.k;
    e[0] = 1.0;
    for (int i = 0; i < k; ++i) e[L.oI + i] = g[std::size_t(i)];
    for (int c = 0; c < 3; ++c) e[L.oP + c] = p[c];
    for (int i = 0, t = 0; i < k; ++i)
        for (int j = i; j < k; ++j) e[L.oII + t++] = g[std::size_t(i)] * g[std::size_t(j)];
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < k; ++i) e[L.oIP + c * k + i] = p[c] * g[std::size_t(i)];
}

// a and b of one window from its stage-1 sums s (TPAMI 2013 eqs. 5-6 and 19-20) into e (c2
// doubles); mu receives the window's guide mean (0 for an empty window).
void windowCoefficients(const double* s, const Layout& L, double eps, double* e, double* mu) {
    std::fill_n(e, L.c2, 0.0);
    const int k = L.k;
    const double n = s[0];
    if (n < 0.5) {
        std::fill_n(mu, k, 0.0);
        return;
    }
    const double inv = 1.0 / n;
    std::array<double, 3> pm{};
    for (int t = 0; t < k; ++t) mu[t] = s[L.oI + t] * inv;
    for (int c = 0; c < 3; ++c) pm[std::size_t(c)] = s[L.oP + c] * inv;
    e[0] = 1.0;
    if (k == 1) {
        const double var =
            std::max(0.0, roundoffToZero(s[L.oII] * inv - mu[0] * mu[0], s[L.oII] * inv));
        for (int c = 0; c < 3; ++c) {
            const double cv =
                roundoffToZero(s[L.oIP + c] * inv - mu[0] * pm[std::size_t(c)], s[L.oIP + c] * inv);
            double a = cv / (var + eps);
            if (!std::isfinite(a)) a = 0.0;
            e[L.oA + c] = a;
            e[L.oB + c] = pm[std::size_t(c)] - a * mu[0];
        }
    } else {
        static constexpr std::array<int, 3> diag{0, 3, 5};  // upper-triangle index of (i, i)
        std::array<double, 6> sigma{};
        std::array<double, 3> cov{};
        for (int a = 0, t = 0; a < 3; ++a)
            for (int b = a; b < 3; ++b, ++t)
                sigma[std::size_t(t)] = roundoffToZero(
                    s[L.oII + t] * inv - mu[a] * mu[b],
                    std::sqrt(s[L.oII + diag[std::size_t(a)]] * s[L.oII + diag[std::size_t(b)]]) *
                        inv);
        for (int t : diag) sigma[std::size_t(t)] = std::max(0.0, sigma[std::size_t(t)]);
        for (int c = 0; c < 3; ++c) {
            for (int t = 0; t < 3; ++t)
                cov[std::size_t(t)] =
                    roundoffToZero(s[L.oIP + c * 3 + t] * inv - mu[t] * pm[std::size_t(c)],
                                   s[L.oIP + c * 3 + t] * inv);
            double* a = e + L.oA + c * 3;
            solveSym3(sigma.data(), eps, cov.data(), a);
            e[L.oB + c] = pm[std::size_t(c)] - (a[0] * mu[0] + a[1] * mu[1] + a[2] * mu[2]);
        }
    }
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(e[L.oB + c])) e[L.oB + c] = pm[std::size_t(c)];
}

// The guided filter for output columns [sx0, sx1) of roi, streaming down the rows: stage-1
// horizontal sums go to a ring of 2r+2 rows, vertical block sums give a and b one row at a
// time, whose horizontal sums go to a second ring, whose vertical sums give the output r rows
// later. Everything stays in cache whatever the image height.
void guidedStrip(const Image& color, const GuideSource& guide, const Layout& L, double eps, int r,
                 const Rect& roi, int sx0, int sx1, Image& out, WorkContext& work) {
    const int W = color.width(), H = color.height(), k = L.k;
    const int cA0 = std::max(0, sx0 - r), cA1 = std::min(W, sx1 + r);
    const int cI0 = std::max(0, cA0 - r), cI1 = std::min(W, cA1 + r);
    const int wA = cA1 - cA0, wI = cI1 - cI0, wO = sx1 - sx0;
    const int A2 = roi.y0;               // first stage-2 row
    const int A1 = std::max(0, A2 - r);  // first stage-1 row = first a, b row stage 2 reads
    const int abFirst = A1;
    const int R = 2 * r + 2;  // ring rows
    std::vector<double> ring1(std::size_t(R) * wA * L.c1), pre1(std::size_t(wA) * L.c1),
        sum1(pre1.size());
    std::vector<double> inRow(std::size_t(wI) * L.c1), abRow(std::size_t(wA) * L.c2);
    std::vector<double> ring2(std::size_t(R) * wO * L.c2), pre2(std::size_t(wO) * L.c2),
        sum2(pre2.size());
    std::vector<double> guideRing(std::size_t(R) * wO * k);
    std::array<double, 3> mu{}, g{};
    int h1Next = std::max(0, A1 - r);
    for (int j = A1; j < roi.y1 + r; ++j) {
        if (work.cancelled()) return;
        if (j < H) {
            // Stage-1 horizontal sums of the rows the vertical sums at j reach.
            for (; h1Next <= std::min(H - 1, j + r); ++h1Next) {
                for (int x = cI0; x < cI1; ++x)
                    products(color, guide, L, x, h1Next,
                             inRow.data() + std::size_t(x - cI0) * L.c1);
                detail::boxSums1D(inRow.data(), cI0, L.c1,
                                  ring1.data() + std::size_t(h1Next % R) * wA * L.c1, cA0, cA1,
                                  L.c1, L.c1, r, 0, W);
            }
            // Stage-1 vertical sums at row j, then a and b of the windows of row j.
            detail::verticalBoxStep(ring1.data(), R, wA * L.c1, pre1.data(), sum1.data(), j, r, H,
                                    j == A1);
            if (j >= abFirst) {
                for (int x = cA0; x < cA1; ++x) {
                    windowCoefficients(sum1.data() + std::size_t(x - cA0) * L.c1, L, eps,
                                       abRow.data() + std::size_t(x - cA0) * L.c2, mu.data());
                    if (x < sx0 || x >= sx1) continue;
                    // The centre's guide, or its window's guide mean where the guide is missing.
                    double* cg =
                        guideRing.data() + (std::size_t(j % R) * wO + std::size_t(x - sx0)) * k;
                    const bool ok = guide.read(x, j, g.data());
                    for (int t = 0; t < k; ++t) cg[t] = ok ? g[std::size_t(t)] : mu[std::size_t(t)];
                }
                detail::boxSums1D(abRow.data(), cA0, L.c2,
                                  ring2.data() + std::size_t(j % R) * wO * L.c2, sx0, sx1, L.c2,
                                  L.c2, r, 0, W);
            }
        }
        // Stage 2 at row y = j - r: average a and b over the covering windows (eq. 8).
        const int y = j - r;
        if (y < A2 || y >= roi.y1) continue;
        detail::verticalBoxStep(ring2.data(), R, wO * L.c2, pre2.data(), sum2.data(), y, r, H,
                                y == A2);
        if (y < roi.y0) continue;
        float* dst = out.row(y - roi.y0) + std::size_t(sx0 - roi.x0) * 3;
        for (int x = 0; x < wO; ++x) {
            const double* s = sum2.data() + std::size_t(x) * L.c2;
            const double* cg = guideRing.data() + (std::size_t(y % R) * wO + std::size_t(x)) * k;
            for (int c = 0; c < 3; ++c) {
                double q = 0.0;
                if (s[0] >= 0.5) {
                    q = s[L.oB + c];
                    for (int t = 0; t < k; ++t) q += s[L.oA + c * k + t] * cg[t];
                    q /= s[0];
                }
                constexpr double kMax = 3.4e38;  // keep within float range
                dst[std::size_t(x) * 3 + std::size_t(c)] =
                    std::isfinite(q) ? float(std::clamp(q, -kMax, kMax)) : 0.0f;
            }
        }
        work.addWork(1);
    }
}

}  // namespace

GuidedFilter::GuidedFilter()
    : m_params{
          ParamSpec{"radius", "radius (px)", 1, 64, 5, ParamScale::Linear, true,
                    "Window radius in pixels."}
              .soft(1, 16),
          ParamSpec{"eps", "epsilon", 1e-8, 1e2, 5e-2, ParamScale::Log, false,
                    "Regulariser (guide units squared): larger smooths more."}
              .soft(1e-4, 1.0),
          ParamSpec::choice("guide", "guide image", {"color", "albedo", "normal", "depth"}, 0,
                            "Image that steers the filter: colour luminance, or the albedo, "
                            "normal or depth layer."),
      } {}

std::string_view GuidedFilter::description() const {
    return kDescription;
}

std::vector<Layer> GuidedFilter::requiredLayers(const ParamValues& params) const {
    switch (GuideKind(detail::paramInt(params, "guide"))) {
        case GuideKind::Albedo:
            return {Layer::Albedo};
        case GuideKind::Normal:
            return {Layer::Normal};
        case GuideKind::Depth:
            return {Layer::Depth};
        case GuideKind::ColorLuminance:
            break;
    }
    return {};
}

int GuidedFilter::margin(const ParamValues& params) const {
    return 2 * detail::paramInt(params, "radius");
}

Image GuidedFilter::apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                          WorkContext& work) const {
    const int r = detail::paramInt(params, "radius");
    const double eps = detail::paramValue(params, "eps");
    GuideSource guide;
    guide.kind = GuideKind(detail::paramInt(params, "guide"));
    guide.color = &frame.color();
    // applyFilter has checked requiredLayers(): the guide layer is there.
    const std::vector<Layer> guideLayer = requiredLayers(params);
    if (!guideLayer.empty()) guide.layer = &frame.layer(guideLayer[0]);
    if (guide.kind == GuideKind::Depth) guide.depthScale = meanAbsDepth(*guide.layer);
    const int k = (guide.kind == GuideKind::Albedo || guide.kind == GuideKind::Normal) ? 3 : 1;
    guide.channels = k;
    const Layout layout(k);

    // Column strips, in parallel; each streams down the rows. Every value depends only on its
    // position (box_filter.h), never on the strip boundaries, so the strip width only balances
    // the load (about four strips) against the horizontal overlap (at least 128 columns).
    const int strip = std::clamp((roi.width() / 4 + 63) / 64 * 64, 128, 512);
    const int strips = (roi.width() + strip - 1) / strip;
    Image out(roi.width(), roi.height(), 3);
    // Each strip counts its output rows; cancellation is checked on every row of every strip.
    work.expectWork(std::int64_t(strips) * roi.height());
    work.parallelFor(
        0, strips,
        [&](int s) {
            const int sx0 = roi.x0 + s * strip, sx1 = std::min(roi.x1, sx0 + strip);
            guidedStrip(frame.color(), guide, layout, eps, r, roi, sx0, sx1, out, work);
        },
        0);
    return out;
}

std::unique_ptr<Filter> makeGuidedFilter() {
    return std::make_unique<GuidedFilter>();
}

}  // namespace glint::denoise
