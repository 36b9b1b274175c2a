// Cross-validation of a member's error on the two halves of the samples (halves_estimator.h;
// docs/auto.md, "Error estimation by cross-validation on the halves").
#include "halves_estimator.h"

#include <atomic>
#include <cmath>
#include <cstdio>

#include "display_weights.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

Image crossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                         const Image* outputB, const Rect& region, const Image* weight,
                         std::optional<float> displayExposure) {
    GLINT_CHECK(outputA.width() == region.width() && outputA.height() == region.height() &&
                halfA.sameShape(halfB) && (!outputB || outputB->sameShape(outputA)) &&
                !(weight && displayExposure));
    const DisplayCurve display(displayExposure ? std::exp2(double(*displayExposure)) : 1.0);
    auto value = [&](float v) { return displayExposure ? display(double(v)) : double(v); };
    Image map(region.width(), region.height(), 1);
    WorkContext work;
    work.parallelFor(0, region.height(), [&](int y) {
        for (int x = 0; x < region.width(); ++x) {
            double s = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double a = value(halfA(x + region.x0, y + region.y0, c));
                const double b = value(halfB(x + region.x0, y + region.y0, c));
                const double ea = value(outputA(x, y, c)) - b;
                double term;
                if (outputB) {
                    const double eb = value((*outputB)(x, y, c)) - a;
                    term = 0.5 * (ea * ea + eb * eb - (a - b) * (a - b));
                } else {
                    term = ea * ea - 0.5 * (a - b) * (a - b);
                }
                s += weight ? double((*weight)(x, y, c)) * term : term;
            }
            map(x, y, 0) = storedError(s);
        }
    });
    return map;
}

Image secantCrossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                               const Image* outputB, const Rect& region, const Image& centre,
                               float exposure, SecantForm form, double* unbiasedMean) {
    GLINT_CHECK(centre.sameShape(outputA));
    return secantMap(halfA, halfB, outputA, outputB, region, centre, displayOf(centre, exposure),
                     exposure, form, unbiasedMean);
}

void checkHalvesFinite(const FrameBuffers& frame, const std::string& file) {
    // Finite, and within the ±kMaxRadiance the filters are held to (docs/denoise.md): half A is
    // the colour's double less half B, which a value near the float's largest would overflow.
    for (Layer layer : {Layer::Color, Layer::HalfColor}) {
        const Image& image = frame.layer(layer);
        // Rows in parallel to find whether any value is bad; then, only if one is, the serial
        // scan that names the first in scan order.
        std::atomic<bool> bad{false};
        WorkContext work;
        work.parallelFor(0, frame.height(), [&](int y) {
            const float* row = image.row(y);
            for (int i = 0; i < frame.width() * 3; ++i)
                if (!(std::fabs(row[i]) <= kMaxRadiance)) bad.store(true);
        });
        if (!bad.load()) continue;
        for (int y = 0; y < frame.height(); ++y)
            for (int x = 0; x < frame.width(); ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = image(x, y, c);
                    if (std::fabs(v) <= kMaxRadiance) continue;
                    char value[64];
                    std::snprintf(value, sizeof value, "a value of %g", double(v));
                    const std::string what = std::isnan(v)   ? "NaN"
                                             : std::isinf(v) ? "Inf"
                                                             : std::string(value);
                    throw Error(ErrorKind::Numeric,
                                what + " in " + layerInFile(frame, layer) +
                                    "; the error estimate needs finite values within ±1e30",
                                file,
                                pixelText(x, y) + ", channel " + channelInFile(frame, layer, c));
                }
    }
}

Image secantMap(const Image& halfA, const Image& halfB, const Image& outputA, const Image* outputB,
                const Rect& region, const Image& centre, const std::vector<double>& displayCentre,
                float exposure, SecantForm form, double* unbiasedMean,
                std::vector<double>* unbiasedRows) {
    GLINT_CHECK(outputA.width() == region.width() && outputA.height() == region.height() &&
                halfA.sameShape(halfB) && (!outputB || outputB->sameShape(outputA)) &&
                centre.sameShape(outputA) && displayCentre.size() == centre.data().size() &&
                halfA.channels() == 3 && outputA.channels() == 3 && centre.channels() == 3);
    const DisplayCurve display(std::exp2(double(exposure)));
    const bool centred = form == SecantForm::Centred;
    Image map(region.width(), region.height(), 1);
    // Per row, the sum of the unbiased terms (added up in row order below: deterministic).
    std::vector<double> rowSums(std::size_t(region.height()), 0.0);
    WorkContext work;
    work.parallelFor(0, region.height(), [&](int y) {
        const float* rowA = halfA.row(y + region.y0) + std::size_t(region.x0) * 3;
        const float* rowB = halfB.row(y + region.y0) + std::size_t(region.x0) * 3;
        const float* rowFA = outputA.row(y);
        const float* rowFB = outputB ? outputB->row(y) : nullptr;
        const float* rowM = centre.row(y);
        const double* rowDM =
            displayCentre.data() + std::size_t(y) * std::size_t(region.width()) * 3;
        float* out = map.row(y);
        double rowSum = 0.0;
        for (int x = 0; x < region.width(); ++x) {
            double s = 0.0, unbiased = 0.0;
            for (std::size_t c = 0; c < 3; ++c) {
                const std::size_t i = std::size_t(x) * 3 + c;
                const double a = rowA[i];
                const double b = rowB[i];
                const double m = rowM[i];
                const double displayM = rowDM[i];
                const double halfNoise = 0.5 * (a - b) * (a - b);
                // One side: output f against the other half h.
                auto side = [&](double f, double h, double& unbiasedTerm) {
                    const double w = secantWeight(f, m, displayM, display, exposure);
                    unbiasedTerm = w * ((f - h) * (f - h) - halfNoise);
                    return centred ? w * (f - m) * (f + m - 2.0 * h) : unbiasedTerm;
                };
                double ua = 0.0, ub = 0.0;
                const double termA = side(rowFA[i], b, ua);
                if (rowFB) {
                    const double termB = side(rowFB[i], a, ub);
                    s += 0.5 * (termA + termB);
                    unbiased += 0.5 * (ua + ub);
                } else {
                    s += termA;
                    unbiased += ua;
                }
            }
            out[x] = storedError(s);
            rowSum += unbiased;
        }
        rowSums[std::size_t(y)] = rowSum;
    });
    if (unbiasedMean) {
        double total = 0.0;
        for (double v : rowSums) total += v;
        *unbiasedMean = total / double(map.pixelCount()) / 3.0;
    }
    if (unbiasedRows) *unbiasedRows = std::move(rowSums);
    return map;
}

HalvesEstimator::HalvesEstimator(const FilterBank& bank, const FrameBuffers& frame,
                                 const AutoSettings& settings, bool bothHalves, const Image* median,
                                 const std::vector<double>* displayMedian, const Image* weight)
    : m_bank(bank),
      m_settings(settings),
      m_bothHalves(bothHalves),
      m_secant(settings.space == SureSpace::Display),
      m_median(median),
      m_displayMedian(displayMedian),
      m_weight(weight) {
    GLINT_CHECK(!m_secant || (median && displayMedian));
    // The two halves, each prefiltered like the bank's input.
    auto split = splitHalves(frame);
    m_halfA = settings.prefilter ? prefilterFeatures(split.first, settings.prefilterParams)
                                 : std::move(split.first);
    m_halfB = settings.prefilter ? prefilterFeatures(split.second, settings.prefilterParams)
                                 : std::move(split.second);
}

Image HalvesEstimator::map(const FrameBuffers& on, const FrameBuffers& other, const Image& output,
                           const Image* outputOther, std::optional<double>& unbiasedMean) const {
    const Rect& region = m_bank.region();
    if (m_secant) {
        double mean = 0.0;
        Image out = secantMap(on.color(), other.color(), output, outputOther, region, *m_median,
                              *m_displayMedian, m_settings.exposure, SecantForm::Centred, &mean);
        unbiasedMean = mean;
        return out;
    }
    const bool exact = m_settings.space == SureSpace::DisplayExact;
    return crossValidationMap(on.color(), other.color(), output, outputOther, region, m_weight,
                              exact ? std::optional<float>(m_settings.exposure) : std::nullopt);
}

Image HalvesEstimator::mapOver(const Rect& region, bool onA, const Image& output,
                               const Image* outputOther, const Image* centre,
                               const std::vector<double>* displayCentre, const Image* weight,
                               std::vector<double>& unbiasedRows) const {
    const FrameBuffers& on = onA ? m_halfA : m_halfB;
    const FrameBuffers& other = onA ? m_halfB : m_halfA;
    if (m_secant) {
        GLINT_CHECK(centre && displayCentre);
        return secantMap(on.color(), other.color(), output, outputOther, region, *centre,
                         *displayCentre, m_settings.exposure, SecantForm::Centred, nullptr,
                         &unbiasedRows);
    }
    const bool exact = m_settings.space == SureSpace::DisplayExact;
    return crossValidationMap(on.color(), other.color(), output, outputOther, region, weight,
                              exact ? std::optional<float>(m_settings.exposure) : std::nullopt);
}

MemberEstimate HalvesEstimator::estimate(std::size_t m, const ProgressFn& going) {
    const BankMember& member = m_bank.members()[m];
    FilterOptions fo;
    fo.region = m_bank.region();
    fo.progress = going;
    const Filter& filter = findFilter(member.filter);
    const Image outA = applyFilter(filter, m_halfA, member.params, fo);
    const Image outB = m_bothHalves ? applyFilter(filter, m_halfB, member.params, fo) : Image{};
    MemberEstimate e;
    e.map = map(m_halfA, m_halfB, outA, m_bothHalves ? &outB : nullptr, e.unbiasedMean);
    return e;
}

double HalvesEstimator::noiseVariance(int x, int y, int c) const {
    // (A − B)²/4, the variance of the mean of equal halves.
    const double d = double(m_halfA.color()(x, y, c)) - m_halfB.color()(x, y, c);
    return 0.25 * d * d;
}

}  // namespace glint::denoise::detail
