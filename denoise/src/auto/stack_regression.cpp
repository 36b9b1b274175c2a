// The auto composite's stacking regression (stacking.h; docs/auto.md, "Stacking"): a local
// ridge regression of each half on the chosen members' results on the other half and on the
// features' local deviations, around the blend, its coefficients averaged over the windows that
// cover each pixel.
#include <algorithm>
#include <cmath>
#include <vector>

#include "box_averages.h"
#include "glint/image/display_curve.h"
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

namespace {

// The feature planes of featureRegressors: the albedo's three channels, then the normal's three
// axes; each value finite (a NaN must not spread through the sums).
struct FeaturePlanes {
    const Image& base;
    const Image* albedo;
    const Image* normal;
    std::vector<const Image*> sources;

    FeaturePlanes(const Image& b, const Image* a, const Image* n, int radius)
        : base(b), albedo(a), normal(n) {
        GLINT_CHECK(base.channels() == 3 && radius >= 1);
        GLINT_CHECK(!albedo || (albedo->sameShape(base)));
        GLINT_CHECK(!normal || (normal->sameShape(base)));
        if (albedo) sources.push_back(albedo);
        if (normal) sources.push_back(normal);
    }
    std::size_t planes() const { return 3 * sources.size(); }
    std::size_t regressors() const { return (albedo ? 1 : 0) + (normal ? 3 : 0); }
    double value(int x, int y, std::size_t p) const {
        const double v = (*sources[p / 3])(x, y, int(p % 3));
        return std::isfinite(v) ? v : 0.0;
    }
    // Pixel (x, y)'s regressors from its planes' box averages, into row `toY` of `out`.
    void write(int x, int y, const double* means, std::vector<Image>& out, int toY) const {
        std::size_t plane = 0, index = 0;
        if (albedo) {
            for (int c = 0; c < 3; ++c, ++plane) {
                const double mean = means[plane];
                double delta =
                    (double((*albedo)(x, y, c)) - mean) / (std::abs(mean) + kStackAlbedoFloor);
                if (!std::isfinite(delta)) delta = 0.0;
                out[index](x, toY, c) = float(double(base(x, y, c)) * (1.0 + delta));
            }
            ++index;
        }
        if (normal) {
            for (int axis = 0; axis < 3; ++axis, ++plane, ++index) {
                double delta = double((*normal)(x, y, axis)) - means[plane];
                if (!std::isfinite(delta)) delta = 0.0;
                for (int c = 0; c < 3; ++c)
                    out[index](x, toY, c) = float(double(base(x, y, c)) * (1.0 + delta));
            }
        }
    }
};

}  // namespace

std::vector<Image> featureRegressors(const Image& base, const Image* albedo, const Image* normal,
                                     int radius, WorkContext* work) {
    const FeaturePlanes f(base, albedo, normal, radius);
    std::vector<Image> out(f.regressors(), base);
    if (out.empty()) return out;
    boxAverages(
        base.width(), base.height(), radius, f.planes(),
        [&](int x, int y, std::size_t p) { return f.value(x, y, p); },
        [&](int x, int y, const double* means) { f.write(x, y, means, out, y); }, nullptr, work);
    return out;
}

void featureRegressorStrips(const Image& base, const Image* albedo, const Image* normal, int radius,
                            int rows, const RegressorStripSink& sink, WorkContext* work) {
    const FeaturePlanes f(base, albedo, normal, radius);
    const int w = base.width(), h = base.height();
    if (f.regressors() == 0) return;
    GLINT_CHECK(rows > 0);
    const std::size_t planes = f.planes();
    RunningBoxAverages sums(w, h, radius, planes);
    for (int y0 = 0; y0 < h; y0 += rows) {
        if (work) work->throwIfCancelled();
        const int y1 = std::min(h, y0 + rows);
        std::vector<Image> strip(f.regressors(), Image(w, y1 - y0, 3));
        sums.advance(
            y1,
            [&](int y, double* terms) {
                for (int x = 0; x < w; ++x)
                    for (std::size_t p = 0; p < planes; ++p)
                        terms[std::size_t(x) * planes + p] = f.value(x, y, p);
            },
            [&](int x, int y, const double* means) { f.write(x, y, means, strip, y - y0); });
        sink(y0, strip);
        if (work) work->addWork(2 * (y1 - y0));
    }
    if (work) work->throwIfCancelled();
}

Image stackComposite(const Image& composite, const Image& blendA, const Image& blendB,
                     const std::vector<StackMember>& members, const Image& halfA,
                     const Image& halfB, const Image& weight, int radius, double ridge,
                     double floor, int smooth, WorkContext* work, const StackGate& gate) {
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
    return stackComposite(Image(composite), blendA, blendB, members.size(), load, halfA, halfB,
                          weight, radius, ridge, floor, smooth, work, gate);
}

Image stackComposite(Image composite, const Image& blendA, const Image& blendB, std::size_t count,
                     const LoadStackRows& load, const Image& halfA, const Image& halfB,
                     const Image& weight, int radius, double ridge, double floor, int smooth,
                     WorkContext* work, const StackGate& gate) {
    const int w = composite.width(), h = composite.height();
    const std::size_t k = count;
    GLINT_CHECK(composite.channels() == 3 && blendA.sameShape(composite) &&
                blendB.sameShape(composite) && halfA.sameShape(composite) &&
                halfB.sameShape(composite) && (weight.empty() || weight.sameShape(composite)) &&
                (!gate.variance || gate.variance->sameShape(composite)) && radius >= 1 &&
                floor >= 0.0 && smooth >= 0 && k > 0 && k <= kMaxStackRegressors);
    // Corrected in place: a pixel's value is read before it is written, and nothing else reads
    // the composite.
    Image& out = composite;
    // Loaded rows (`into`, from row `intoY0` on), checked as they come: the regression's, and
    // with `smooth` the smoothing's results on all the samples.
    StackRows rows, fullRows;
    int rowsY0 = 0, fullY0 = 0;
    const auto loadRows = [&](int y0, int y1, bool full, bool halves, StackRows& into,
                              int& intoY0) {
        load(y0, y1, full, halves, into);
        intoY0 = y0;
        GLINT_CHECK(into.full.size() == (full ? k : 0) && into.onA.size() == (halves ? k : 0) &&
                    into.onB.size() == (halves ? k : 0));
        for (const auto* list : {&into.full, &into.onA, &into.onB})
            for (const Image& r : *list)
                GLINT_CHECK(r.width() == w && r.height() == y1 - y0 && r.channels() == 3);
    };
    // c + Σ a_i (f_i − c) at one pixel, clamped at 0; the composite where it is not finite, and
    // past a gate the composite clamped at 0.
    const StackRows& fullOf = smooth > 0 ? fullRows : rows;
    const int& fullOfY0 = smooth > 0 ? fullY0 : rowsY0;
    const DisplayCurve display(std::exp2(double(gate.exposure)));
    // Whether moving channel c of (x, y) from `base` to `value` passes the noise gate.
    const auto withinNoise = [&](int x, int y, int c, double base, double value) {
        if (!(gate.sigmas > 0.0)) return true;
        const double a = halfA(x, y, c), b = halfB(x, y, c);
        const double sigma = gate.variance
                                 ? std::sqrt(std::max(0.0, double((*gate.variance)(x, y, c))))
                                 : 0.5 * std::fabs(a - b);
        const double moved = std::fabs(value - base);
        // NaN-safe: a non-finite σ or mean lets the correction through.
        return !(moved > gate.sigmas * sigma && moved > std::fabs(base - 0.5 * (a + b)));
    };
    const auto correct = [&](int x, int y, const double* a) {
        float value[3];
        for (int c = 0; c < 3; ++c) {
            const double base = composite(x, y, c);
            double v = base;
            for (std::size_t i = 0; i < k; ++i)
                v += a[i] * (double(fullOf.full[i](x, y - fullOfY0, c)) - base);
            if (!std::isfinite(v)) return;
            value[c] = float(std::max(0.0, v));
            if ((gate.gate > 0.0 &&
                 std::fabs(display(double(value[c])) - display(base)) > gate.gate) ||
                !withinNoise(x, y, c, base, double(value[c]))) {
                for (int g = 0; g < 3; ++g) value[g] = std::max(0.0f, composite(x, y, g));
                break;
            }
        }
        for (int c = 0; c < 3; ++c) out(x, y, c) = value[c];
    };
    // With `smooth`, the pixels' coefficients (0 where the system failed) of rows
    // [coefficientsY0, …) that the smoothing has yet to read, k a pixel.
    std::vector<float> coefficients;
    int coefficientsY0 = 0;
    const std::size_t rowValues = std::size_t(w) * k;
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
    // With `smooth`: every window's model applied to each pixel it covers, averaged (the guided
    // filter's aggregation), the same as applying the coefficients box-averaged over the
    // window. It runs behind the regression, up to row `until` once the coefficients it reads
    // (to `until` − 1 + smooth) are fitted, with those rows' results on all the samples; each
    // coefficient row is read once, in row order, and dropped.
    RunningBoxAverages smoothed(w, h, std::max(smooth, 1), smooth > 0 ? k : 1);
    const auto smoothUntil = [&](int until) {
        const int from = smoothed.next();
        if (until <= from) return;
        loadRows(from, until, true, false, fullRows, fullY0);
        smoothed.advance(
            until,
            [&](int y, double* terms) {
                const float* row =
                    coefficients.data() + std::size_t(y - coefficientsY0) * rowValues;
                for (std::size_t i = 0; i < rowValues; ++i) terms[i] = double(row[i]);
            },
            correct);
        const int read = std::min(h, until + smooth);
        coefficients.erase(coefficients.begin(),
                           coefficients.begin() +
                               std::ptrdiff_t(read - coefficientsY0) * std::ptrdiff_t(rowValues));
        coefficientsY0 = read;
        if (work) work->addWork(2 * (until - from));
    };
    for (int t0 = 0; t0 < h; t0 += kStackTileRows) {
        const int t1 = std::min(h, t0 + kStackTileRows);
        const int y0 = std::max(0, t0 - radius), y1 = std::min(h, t1 + radius);
        if (work) work->throwIfCancelled();
        loadRows(y0, y1, smooth == 0, true, rows, rowsY0);
        if (smooth > 0) coefficients.resize(std::size_t(t1 - coefficientsY0) * rowValues, 0.0f);
        // The tile's window sums row after row (2·radius + 2 rows of horizontal sums, not the
        // tile's): boxAveragesOfRows' averages over its rows, value for value.
        RunningBoxAverages sums(w, y1 - y0, radius, planes);
        sums.advance(
            y1 - y0, [&](int yy, double* terms) { fillTerms(y0 + yy, terms); },
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
                float* to = coefficients.data() + std::size_t(y - coefficientsY0) * rowValues +
                            std::size_t(x) * k;
                for (std::size_t i = 0; i < k; ++i) to[i] = float(a[i]);
            });
        if (work) work->addWork(2 * (y1 - y0));
        if (smooth > 0) {
            rows = StackRows{};
            if (work) work->throwIfCancelled();
            smoothUntil(t1 == h ? h : t1 - smooth);
        }
    }
    if (work) work->throwIfCancelled();
    return out;
}

std::uint64_t stackTileBytes(int width, std::size_t count, int radius, int smooth) {
    const auto w = std::uint64_t(std::max(0, width));
    const std::uint64_t k = count, planes = k * (k + 1) / 2 + k + 1;
    const auto tile = std::uint64_t(kStackTileRows), context = tile + 2 * std::uint64_t(radius);
    // The tile's regressors on the halves, and its window sums: a ring of 2·radius + 2 rows, the
    // running sums and a row's prefix sums.
    const std::uint64_t regression =
        w * context * 2 * k * 12 + w * planes * sizeof(double) * (2 * std::uint64_t(radius) + 4);
    const std::uint64_t smoothing = w * k *
                                    ((tile + std::uint64_t(smooth)) * sizeof(float) +
                                     (2 * std::uint64_t(smooth) + 2) * sizeof(double) + tile * 12);
    return regression + smoothing;
}

}  // namespace glint::denoise::detail
