// The auto composite's stacking regression (stacking.h; docs/auto.md, "Stacking"): a local
// ridge regression of each half on the chosen members' results on the other half and on the
// features' local deviations, around the blend, its coefficients averaged over the windows that
// cover each pixel.
#include <algorithm>
#include <cmath>
#include <vector>

#include "box_averages.h"
#include "glint/image/error.h"
#include "stacking.h"

namespace glint::denoise::detail {

namespace {

// Solves (G + ridge·I) a = r for a symmetric k × k G (row-major, overwritten: its lower
// triangle becomes the Cholesky factor) into `a`; false when a pivot is not positive and finite.
bool solveRidge(double* g, const double* r, std::size_t k, double ridge, double* a) {
    for (std::size_t i = 0; i < k; ++i) g[i * k + i] += ridge;
    for (std::size_t i = 0; i < k; ++i)
        for (std::size_t j = 0; j <= i; ++j) {
            double v = g[i * k + j];
            for (std::size_t m = 0; m < j; ++m) v -= g[i * k + m] * g[j * k + m];
            if (i == j) {
                if (!(v > 0.0) || !std::isfinite(v)) return false;
                g[i * k + i] = std::sqrt(v);
            } else {
                g[i * k + j] = v / g[j * k + j];
            }
        }
    double z[kMaxStackRegressors];
    for (std::size_t i = 0; i < k; ++i) {
        double v = r[i];
        for (std::size_t m = 0; m < i; ++m) v -= g[i * k + m] * z[m];
        z[i] = v / g[i * k + i];
    }
    for (std::size_t i = k; i-- > 0;) {
        double v = z[i];
        for (std::size_t m = i + 1; m < k; ++m) v -= g[m * k + i] * a[m];
        a[i] = v / g[i * k + i];
    }
    return true;
}

}  // namespace

std::vector<Image> featureRegressors(const Image& base, const Image* albedo, const Image* normal,
                                     int radius, WorkContext* work) {
    const int w = base.width(), h = base.height();
    GLINT_CHECK(base.channels() == 3 && radius >= 1);
    GLINT_CHECK(!albedo || (albedo->sameShape(base)));
    GLINT_CHECK(!normal || (normal->sameShape(base)));
    // The features' planes: the albedo's three channels, then the normal's three axes.
    std::vector<const Image*> sources;
    if (albedo) sources.push_back(albedo);
    if (normal) sources.push_back(normal);
    const std::size_t planes = 3 * sources.size();
    const std::size_t count = (albedo ? 1 : 0) + (normal ? 3 : 0);
    std::vector<Image> out(count, base);
    if (count == 0) return out;
    boxAverages(
        w, h, radius, planes,
        [&](int x, int y, std::size_t p) {
            const double v = (*sources[p / 3])(x, y, int(p % 3));
            return std::isfinite(v) ? v : 0.0;  // a NaN must not spread through the sums
        },
        [&](int x, int y, const double* means) {
            std::size_t plane = 0, index = 0;
            if (albedo) {
                for (int c = 0; c < 3; ++c, ++plane) {
                    const double mean = means[plane];
                    double delta =
                        (double((*albedo)(x, y, c)) - mean) / (std::abs(mean) + kStackAlbedoFloor);
                    if (!std::isfinite(delta)) delta = 0.0;
                    out[index](x, y, c) = float(double(base(x, y, c)) * (1.0 + delta));
                }
                ++index;
            }
            if (normal) {
                for (int axis = 0; axis < 3; ++axis, ++plane, ++index) {
                    double delta = double((*normal)(x, y, axis)) - means[plane];
                    if (!std::isfinite(delta)) delta = 0.0;
                    for (int c = 0; c < 3; ++c)
                        out[index](x, y, c) = float(double(base(x, y, c)) * (1.0 + delta));
                }
            }
        },
        nullptr, work);
    return out;
}

Image stackComposite(const Image& composite, const Image& blendA, const Image& blendB,
                     const std::vector<StackMember>& members, const Image& halfA,
                     const Image& halfB, const Image& weight, int radius, double ridge,
                     double floor, int smooth, WorkContext* work) {
    for (const StackMember& m : members)
        GLINT_CHECK(m.full && m.onA && m.onB && m.full->sameShape(composite) &&
                    m.onA->sameShape(composite) && m.onB->sameShape(composite));
    const int w = composite.width();
    // The members' rows, cropped from their whole images.
    const LoadStackRows load = [&](int y0, int y1, bool full, bool halves, StackRows& rows) {
        const Rect rect{0, w, y0, y1};
        rows = StackRows{};
        for (const StackMember& m : members) {
            if (full) rows.full.push_back(m.full->crop(rect));
            if (halves) {
                rows.onA.push_back(m.onA->crop(rect));
                rows.onB.push_back(m.onB->crop(rect));
            }
        }
    };
    return stackComposite(composite, blendA, blendB, members.size(), load, halfA, halfB, weight,
                          radius, ridge, floor, smooth, work);
}

Image stackComposite(const Image& composite, const Image& blendA, const Image& blendB,
                     std::size_t count, const LoadStackRows& load, const Image& halfA,
                     const Image& halfB, const Image& weight, int radius, double ridge,
                     double floor, int smooth, WorkContext* work) {
    const int w = composite.width(), h = composite.height();
    const std::size_t k = count;
    GLINT_CHECK(composite.channels() == 3 && blendA.sameShape(composite) &&
                blendB.sameShape(composite) && halfA.sameShape(composite) &&
                halfB.sameShape(composite) && (weight.empty() || weight.sameShape(composite)) &&
                radius >= 1 && floor >= 0.0 && smooth >= 0 && k > 0 && k <= kMaxStackRegressors);
    Image out = composite;
    // The loaded rows (from row rowsY0 on), checked as they come.
    StackRows rows;
    int rowsY0 = 0;
    const auto loadRows = [&](int y0, int y1, bool full, bool halves) {
        load(y0, y1, full, halves, rows);
        rowsY0 = y0;
        GLINT_CHECK(rows.full.size() == (full ? k : 0) && rows.onA.size() == (halves ? k : 0) &&
                    rows.onB.size() == (halves ? k : 0));
        for (const auto* list : {&rows.full, &rows.onA, &rows.onB})
            for (const Image& r : *list)
                GLINT_CHECK(r.width() == w && r.height() == y1 - y0 && r.channels() == 3);
    };
    // c + Σ a_i (f_i − c) at one pixel, clamped at 0; the composite where it is not finite.
    const auto correct = [&](int x, int y, const double* a) {
        float value[3];
        for (int c = 0; c < 3; ++c) {
            const double base = composite(x, y, c);
            double v = base;
            for (std::size_t i = 0; i < k; ++i)
                v += a[i] * (double(rows.full[i](x, y - rowsY0, c)) - base);
            if (!std::isfinite(v)) return;
            value[c] = float(std::max(0.0, v));
        }
        for (int c = 0; c < 3; ++c) out(x, y, c) = value[c];
    };
    // With `smooth`, each pixel's coefficients (0 where its system failed), averaged below.
    std::vector<float> coefficients(smooth > 0 ? std::size_t(w) * std::size_t(h) * k : 0, 0.0f);
    // The window sums: G's upper triangle (pairs), r, and the noise v.
    const std::size_t pairs = k * (k + 1) / 2, planes = pairs + k + 1;
    std::vector<std::pair<std::size_t, std::size_t>> pairOf;
    for (std::size_t i = 0; i < k; ++i)
        for (std::size_t j = i; j < k; ++j) pairOf.emplace_back(i, j);
    // Per pixel: the planes' terms (G's upper triangle, r, v), each a sum over both sides and
    // the channels, computed from ω, the members' deviations from the blend on each half and
    // each half's deviation from the blend on the other; written row by row into the box sums.
    const auto fillTerms = [&](int y, double* terms) {
        const float *fa[kMaxStackRegressors], *fb[kMaxStackRegressors];
        for (std::size_t i = 0; i < k; ++i)
            fa[i] = rows.onA[i].row(y - rowsY0), fb[i] = rows.onB[i].row(y - rowsY0);
        const float *ha = halfA.row(y), *hb = halfB.row(y), *ba = blendA.row(y),
                    *bb = blendB.row(y), *om = weight.empty() ? nullptr : weight.row(y);
        double wd[kMaxStackRegressors][6], d[kMaxStackRegressors + 1][6];  // ω·deviation
        for (int x = 0; x < w; ++x) {
            const std::size_t at = std::size_t(x) * 3;
            double noise = 0.0;
            for (std::size_t c = 0; c < 3; ++c) {
                const double o = om ? double(om[at + c]) : 1.0;
                const double a = ha[at + c], b = hb[at + c];
                const double ca = ba[at + c], cb = bb[at + c];
                for (std::size_t i = 0; i < k; ++i) {
                    d[i][c] = double(fa[i][at + c]) - ca;
                    d[i][c + 3] = double(fb[i][at + c]) - cb;
                    wd[i][c] = o * d[i][c];
                    wd[i][c + 3] = o * d[i][c + 3];
                }
                d[k][c] = b - ca;
                d[k][c + 3] = a - cb;
                noise += 0.5 * o * (a - b) * (a - b);
            }
            double* t = terms + std::size_t(x) * planes;
            std::size_t p = 0;
            for (std::size_t i = 0; i < k; ++i)
                for (std::size_t j = i; j < k; ++j, ++p) {
                    double s = 0.0;
                    for (std::size_t c = 0; c < 6; ++c) s += wd[i][c] * d[j][c];
                    t[p] = s;
                }
            for (std::size_t i = 0; i < k; ++i, ++p) {
                double s = 0.0;
                for (std::size_t c = 0; c < 6; ++c) s += wd[i][c] * d[k][c];
                t[p] = s;
            }
            t[p] = noise;
        }
    };
    std::vector<double> horizontal;  // reused by every tile
    for (int t0 = 0; t0 < h; t0 += kStackTileRows) {
        const int t1 = std::min(h, t0 + kStackTileRows);
        const int y0 = std::max(0, t0 - radius), y1 = std::min(h, t1 + radius);
        loadRows(y0, y1, smooth == 0, true);
        boxAveragesOfRows(
            w, y1 - y0, radius, planes, [&](int yy, double* terms) { fillTerms(y0 + yy, terms); },
            [&](int x, int yy, const double* means) {
                const int y = y0 + yy;
                if (y < t0 || y >= t1) return;  // context rows: another tile's
                double g[kMaxStackRegressors * kMaxStackRegressors], a[kMaxStackRegressors];
                double trace = 0.0;
                for (std::size_t p = 0; p < pairs; ++p) {
                    const auto [i, j] = pairOf[p];
                    g[i * k + j] = g[j * k + i] = means[p];
                    if (i == j) trace += means[p];
                }
                const double lambda =
                    ridge * std::max(0.0, means[planes - 1]) + floor * trace / double(k);
                if (!(lambda > 0.0) || !solveRidge(g, means + pairs, k, lambda, a)) return;
                if (smooth == 0) {
                    correct(x, y, a);
                    return;
                }
                float* to =
                    coefficients.data() + (std::size_t(y) * std::size_t(w) + std::size_t(x)) * k;
                for (std::size_t i = 0; i < k; ++i) to[i] = float(a[i]);
            },
            &horizontal, work);
    }
    if (smooth > 0) {
        // Every window's model applied to each pixel it covers, averaged (the guided filter's
        // aggregation): the same as applying the coefficients box-averaged over the window.
        // Tile after tile, with each tile's results on all the samples.
        horizontal = {};
        RunningBoxAverages smoothed(w, h, smooth, k);
        for (int t0 = 0; t0 < h; t0 += kStackTileRows) {
            if (work) work->throwIfCancelled();
            const int t1 = std::min(h, t0 + kStackTileRows);
            loadRows(t0, t1, true, false);
            smoothed.advance(
                t1,
                [&](int y, double* terms) {
                    const float* from = coefficients.data() + std::size_t(y) * std::size_t(w) * k;
                    for (std::size_t i = 0; i < std::size_t(w) * k; ++i) terms[i] = double(from[i]);
                },
                correct);
            if (work) work->addWork(2 * (t1 - t0));
        }
        if (work) work->throwIfCancelled();
    }
    return out;
}

}  // namespace glint::denoise::detail
