// Stein's unbiased risk estimate of a member's error per pixel (sure_estimator.h;
// docs/auto.md, "Error estimation by SURE").
#include "sure_estimator.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/random.h"
#include "image_noise.h"

namespace glint::denoise::detail {

namespace {

// ε of one value: epsilon · σ, but never below 1e-4 of |y| (or 1e-7), so that float rounding
// cannot swallow the perturbation (where σ is 0 the SURE term needs no divergence anyway).
float perturbationSize(float y, float variance, double epsilon) {
    const double floor = 1e-4 * std::max(std::fabs(double(y)), 1e-3);
    return float(std::max(epsilon * std::sqrt(double(variance)), floor));
}

// The divergence of one member over `region`: the filter's own when it gives one (and the
// options allow), else Monte Carlo from one application to the perturbed input.
Image memberDivergence(const Filter& filter, const ParamValues& params, const Image& output,
                       const FrameBuffers& filterInput, const FrameBuffers& perturbed,
                       const Image& delta, const Rect& region, const SureOptions& options,
                       const ProgressFn& progress, bool& analytic) {
    std::optional<Image> div;
    if (options.analyticDivergence) div = filter.divergence(filterInput, params, region);
    analytic = bool(div);
    if (div) return std::move(*div);
    FilterOptions fo;
    fo.region = region;
    fo.progress = progress;
    const Image perturbedOutput = applyFilter(filter, perturbed, params, fo);
    return monteCarloDivergence(output, perturbedOutput, delta, region);
}

}  // namespace

void checkSureInput(const FrameBuffers& frame, const std::string& file) {
    if (!frame.has(Layer::Variance))
        throw Error(ErrorKind::Format,
                    "has no variance layer ('variance.R', 'variance.G', 'variance.B': the variance "
                    "of the mean of each pixel); SURE needs it to estimate a filter's error "
                    "without a reference",
                    file, "layer 'variance'");
    // The renderer counts the pixels whose variance fell below float's range and was written
    // as 0: SURE would take them for noise-free.
    if (const auto under = frame.metadata().extra.find(kVarianceUnderflowKey);
        under != frame.metadata().extra.end())
        throw Error(ErrorKind::Numeric,
                    "the variance of " + under->second +
                        " pixels is below float's range and was written as 0 (radiance about "
                        "1e-19 or less), so SURE would see no noise there; render with brighter "
                        "emission, or with --set halfBuffers=true for the halves estimator",
                    file, "attribute glint:" + std::string(kVarianceUnderflowKey));
    const Image& color = frame.color();
    const Image& variance = frame.layer(Layer::Variance);
    // Rows in parallel to find whether any value is bad; then, only if one is, the serial scan
    // that reports the first in scan order (a clear, reproducible message).
    std::atomic<bool> bad{false};
    WorkContext work;
    work.parallelFor(0, frame.height(), [&](int y) {
        const float* c = color.row(y);
        const float* s = variance.row(y);
        for (int i = 0; i < frame.width() * 3; ++i)
            if (!std::isfinite(c[i]) || !std::isfinite(s[i]) || s[i] < 0.0f) bad.store(true);
    });
    if (!bad.load()) return;
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = color(x, y, c);
                if (!std::isfinite(v))
                    throw Error(
                        ErrorKind::Numeric,
                        std::string(std::isnan(v) ? "NaN" : "Inf") + " in " +
                            layerInFile(frame, Layer::Color) + "; SURE needs finite values",
                        file,
                        pixelText(x, y) + ", channel " + channelInFile(frame, Layer::Color, c));
                const float s = variance(x, y, c);
                if (!std::isfinite(s) || s < 0.0f)
                    throw Error(ErrorKind::Numeric,
                                std::string(std::isnan(s)   ? "NaN"
                                            : std::isinf(s) ? "Inf"
                                                            : "negative value") +
                                    " in the variance; SURE needs a finite variance >= 0",
                                file,
                                pixelText(x, y) + ", channel " + channelName(Layer::Variance, c));
            }
}

Image rademacherField(int width, int height, std::uint64_t seed) {
    Image b(width, height, 3);
    WorkContext work;
    work.parallelFor(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const std::uint64_t pixel = std::uint64_t(y) * std::uint64_t(width) + std::uint64_t(x);
            const std::uint64_t bits = hash64(seed, pixel);
            for (int c = 0; c < 3; ++c) b(x, y, c) = (bits >> (17 * c + 5)) & 1u ? 1.0f : -1.0f;
        }
    });
    return b;
}

FrameBuffers perturbColor(const FrameBuffers& frame, const SureOptions& options, Image* delta,
                          const Image* variancePtr) {
    GLINT_CHECK(variancePtr || frame.has(Layer::Variance));
    FrameBuffers out = frame;
    const Image b = rademacherField(frame.width(), frame.height(), options.seed);
    const Image& y0 = frame.color();
    const Image& variance = variancePtr ? *variancePtr : frame.layer(Layer::Variance);
    Image& y1 = out.color();
    if (delta) *delta = Image(frame.width(), frame.height(), 3);
    WorkContext work;
    work.parallelFor(0, frame.height(), [&](int y) {
        for (int x = 0; x < frame.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = y0(x, y, c);
                const float eps = perturbationSize(v, variance(x, y, c), options.epsilon);
                y1(x, y, c) = v + eps * b(x, y, c);
                // The perturbation as applied, after rounding: exact (Sterbenz) and never 0,
                // since eps is at least 1e-4 |v|.
                if (delta) (*delta)(x, y, c) = y1(x, y, c) - v;
            }
    });
    return out;
}

Image monteCarloDivergence(const Image& output, const Image& perturbedOutput, const Image& delta,
                           const Rect& region) {
    GLINT_CHECK(output.sameShape(perturbedOutput) && output.width() == region.width() &&
                output.height() == region.height());
    Image div(region.width(), region.height(), 3);
    WorkContext work;
    work.parallelFor(0, region.height(), [&](int y) {
        for (int x = 0; x < region.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                // Ramani, Blu & Unser 2008, eq. 8, per pixel: b_p (f(y+εb) − f(y))_p / ε_p.
                const double d = delta(x + region.x0, y + region.y0, c);
                div(x, y, c) =
                    float((double(perturbedOutput(x, y, c)) - double(output(x, y, c))) / d);
            }
    });
    return div;
}

Image sureMap(const Image& noisy, const Image& variance, const Image& output,
              const Image& divergence, const Rect& region, const Image* weight) {
    GLINT_CHECK(output.width() == region.width() && output.height() == region.height() &&
                output.sameShape(divergence));
    Image sure(region.width(), region.height(), 1);
    WorkContext work;
    work.parallelFor(0, region.height(), [&](int y) {
        for (int x = 0; x < region.width(); ++x) {
            double s = 0.0;
            for (int c = 0; c < 3; ++c) {
                // Stein 1981: E‖f(y) − x‖² = E[‖f(y) − y‖² − σ² + 2σ² ∂f/∂y] per pixel.
                const double yv = noisy(x + region.x0, y + region.y0, c);
                const double v = variance(x + region.x0, y + region.y0, c);
                const double d = double(output(x, y, c)) - yv;
                const double term = d * d - v + 2.0 * v * double(divergence(x, y, c));
                s += weight ? double((*weight)(x, y, c)) * term : term;
            }
            sure(x, y, 0) = storedError(s);
        }
    });
    return sure;
}

SureEstimate estimateSure(const Filter& filter, const FrameBuffers& frame,
                          const ParamValues& params, const SureOptions& options,
                          const std::optional<Rect>& region, const ProgressFn& progress) {
    checkSureInput(frame);
    const Rect r = region.value_or(Rect{0, frame.width(), 0, frame.height()});
    const ParamValues resolved = resolveParams(filter, params);
    FilterOptions fo;
    fo.region = r;
    fo.progress = progress;
    SureEstimate e;
    e.output = applyFilter(filter, frame, resolved, fo);
    Image delta;
    const FrameBuffers perturbed = perturbColor(frame, options, &delta);
    e.divergence = memberDivergence(filter, resolved, e.output, frame, perturbed, delta, r, options,
                                    progress, e.analytic);
    e.sure = sureMap(frame.color(), frame.layer(Layer::Variance), e.output, e.divergence, r);
    return e;
}

SureEstimator::SureEstimator(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoSettings& settings, const Image* weight)
    : m_bank(bank), m_frame(frame), m_options(settings.sure), m_weight(weight) {
    // The variance of the mean: the render's, or estimated from the image and its features.
    if (settings.estimator == AutoEstimator::Image) {
        WorkContext work;
        m_estimatedVariance = estimateImageNoise(frame, settings.imageNoise, work);
        m_variance = &m_estimatedVariance;
    } else {
        m_variance = &frame.layer(Layer::Variance);
    }
    // The input the filters see (prefiltered like the bank's) and its perturbed copy.
    m_filterInput = settings.prefilter ? prefilterFeatures(frame, settings.prefilterParams) : frame;
    m_perturbed = perturbColor(m_filterInput, m_options, &m_delta, m_variance);
}

MemberEstimate SureEstimator::estimate(std::size_t m, const ProgressFn& going) {
    const BankMember& member = m_bank.members()[m];
    MemberEstimate e;
    const Image div =
        memberDivergence(findFilter(member.filter), member.params, m_bank.result(m), m_filterInput,
                         m_perturbed, m_delta, m_bank.region(), m_options, going, e.analytic);
    e.map = sureMap(m_frame.color(), *m_variance, m_bank.result(m), div, m_bank.region(), m_weight);
    return e;
}

MemberEstimate SureEstimator::mapOver(std::size_t m, const Rect& region, const Image& output,
                                      const Image* weight, const ProgressFn& going) const {
    const BankMember& member = m_bank.members()[m];
    MemberEstimate e;
    const Image div =
        memberDivergence(findFilter(member.filter), member.params, output, m_filterInput,
                         m_perturbed, m_delta, region, m_options, going, e.analytic);
    e.map = sureMap(m_frame.color(), *m_variance, output, div, region, weight);
    return e;
}

double SureEstimator::noiseVariance(int x, int y, int c) const {
    return (*m_variance)(x, y, c);
}

}  // namespace glint::denoise::detail
