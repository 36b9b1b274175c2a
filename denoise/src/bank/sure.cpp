// Per-pixel error estimates of the bank's members (SURE, cross-validation on the halves) and the
// auto composite (sure.h; docs/auto.md, whose stages are the step comments of autoComposite).
#include "glint/denoise/sure.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numeric>
#include <tuple>

#include "../filters/simd.h"
#include "box_averages.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/random.h"
#include "sure_detail.h"

namespace glint::denoise {

namespace {

std::string pixelText(int x, int y) {
    return "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

// ε of one value: epsilon · σ, but never below 1e-4 of |y| (or 1e-7), so that float rounding
// cannot swallow the perturbation (where σ is 0 the SURE term needs no divergence anyway).
float perturbationSize(float y, float variance, double epsilon) {
    const double floor = 1e-4 * std::max(std::fabs(double(y)), 1e-3);
    return float(std::max(epsilon * std::sqrt(double(variance)), floor));
}

// Slope of the display transform (exposure, clamp to [0, 1], sRGB) at linear value v; 0 where
// the value is clamped.
double displaySlope(double v, float exposure) {
    const double scale = std::exp2(double(exposure));
    const double x = v * scale;
    if (x <= 0.0 || x >= 1.0) return 0.0;
    // Derivative of the sRGB encoding (IEC 61966-2-1).
    const double d = x <= 0.0031308 ? 12.92 : 1.055 / 2.4 * std::pow(x, 1.0 / 2.4 - 1.0);
    return d * scale;
}

// The display transform (exposure, clamp to [0, 1], sRGB) of linear values, from a table of
// 4096 intervals with linear interpolation (within 2e-5 of the exact curve, plenty to rank
// filters, and a table lookup instead of a pow per value).
class DisplayCurve {
  public:
    explicit DisplayCurve(double scale) : m_table(table().data()), m_scale(scale) {}
    double operator()(double v) const {
        const double x = v * m_scale;
        if (!(x > 0.0)) return 0.0;
        if (x >= 1.0) return 1.0;
        const double f = x * 4096.0;
        const auto i = std::size_t(f);
        return m_table[i] + (f - double(i)) * (m_table[i + 1] - m_table[i]);
    }

  private:
    static const std::vector<double>& table() {
        static const std::vector<double> t = [] {
            std::vector<double> values(4097);
            for (std::size_t i = 0; i < values.size(); ++i) {
                const double x = double(i) / 4096.0;
                values[i] = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
            }
            return values;
        }();
        return t;
    }
    const double* m_table;
    double m_scale;
};

// Sorts `n` columns of 8 floats (column i at v + 8 i) lane-wise, ascending: Batcher's
// merge-exchange network for any n (Knuth, TAOCP vol. 3, 5.2.2, Algorithm M; about
// n log²n / 4 comparators), 8 values per comparator. Branch-free in the values, where a
// selection per value mispredicts about half its comparisons.
GLINT_SIMD_CLONES
void sortLanes(float* v, std::size_t n) {
    if (n < 2) return;
    std::size_t top = 1;  // 2^(t−1), t = ⌈log2 n⌉
    while (top * 2 < n) top *= 2;
    for (std::size_t p = top; p > 0; p >>= 1) {
        std::size_t q = top, r = 0, d = p;
        for (;;) {
            for (std::size_t i = 0; i + d < n; ++i) {
                if ((i & p) != r) continue;
                detail::VecF a, b;
                detail::loadVec(a, v + 8 * i);
                detail::loadVec(b, v + 8 * (i + d));
                detail::storeVec(v + 8 * i, a < b ? a : b);
                detail::storeVec(v + 8 * (i + d), a < b ? b : a);
            }
            if (q == p) break;
            d = q - p;
            q >>= 1;
            r = p;
        }
    }
}

// Per-pixel weights of SureSpace::DisplayTangent (and of Display for SURE): the squared display
// slope at the bank's median, floored at 1e-4 of the largest so saturated pixels still order
// the members.
Image tangentWeights(const Image& median, float exposure) {
    Image weights(median.width(), median.height(), 3);
    for (std::size_t i = 0; i < median.data().size(); ++i) {
        const double s = displaySlope(double(median.data()[i]), exposure);
        weights.data()[i] = float(s * s);
    }
    float largest = 0.0f;
    for (float v : weights.data()) largest = std::max(largest, v);
    const float floor = std::max(largest * 1e-4f, std::numeric_limits<float>::min());
    for (float& v : weights.data()) v = std::max(v, floor);
    return weights;
}

// Squared secant slope of the display transform between linear values f and m (the squared
// slope at m where they nearly agree); `displayM` is D(m).
inline double secantWeight(double f, double m, double displayM, const DisplayCurve& display,
                           float exposure) {
    const double d = f - m;
    const double s = std::fabs(d) <= 1e-6 * std::max(1.0, std::fabs(m))
                         ? displaySlope(m, exposure)
                         : (display(f) - displayM) / d;
    return s * s;
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

// The mean of a 1-channel map summed over RGB, per channel: rows summed in order.
double meanPerChannel(const Image& map) {
    double total = 0.0;
    for (int y = 0; y < map.height(); ++y) {
        double row = 0.0;
        for (int x = 0; x < map.width(); ++x) row += map(x, y, 0);
        total += row;
    }
    return total / double(map.pixelCount()) / 3.0;
}

// NaN or Inf in the colour or the half colour: glint::Error naming the first in scan order.
void checkHalvesFinite(const FrameBuffers& frame, const std::string& file) {
    for (Layer layer : {Layer::Color, Layer::HalfColor}) {
        const Image& image = frame.layer(layer);
        // Rows in parallel to find whether any value is bad; then, only if one is, the serial
        // scan that names the first in scan order.
        std::atomic<bool> bad{false};
        tbb::parallel_for(0, frame.height(), [&](int y) {
            const float* row = image.row(y);
            for (int i = 0; i < frame.width() * 3; ++i)
                if (!std::isfinite(row[i])) bad.store(true);
        });
        if (!bad.load()) continue;
        for (int y = 0; y < frame.height(); ++y)
            for (int x = 0; x < frame.width(); ++x)
                for (int c = 0; c < 3; ++c)
                    if (!std::isfinite(image(x, y, c)))
                        throw Error(ErrorKind::Numeric,
                                    std::string(std::isnan(image(x, y, c)) ? "NaN" : "Inf") +
                                        " in the " + std::string(layerDisplayName(layer)) +
                                        "; the error estimate needs finite values",
                                    file, pixelText(x, y) + ", channel " + channelName(layer, c));
    }
}

}  // namespace

Image bankMedian(const FilterBank& bank) {
    if (bank.size() == 0) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    const Rect& r = bank.region();
    Image median(r.width(), r.height(), 3);
    const std::size_t n = bank.size();
    // Per row, 8 values (pixels × channels) at a time: each member's 8 side by side, sorted
    // lane-wise; the median is the (n/2)-th smallest (as std::nth_element would give it).
    const std::size_t rowValues = std::size_t(r.width()) * 3;
    tbb::parallel_for(0, r.height(), [&](int y) {
        std::vector<float> v(n * 8);
        for (std::size_t x0 = 0; x0 < rowValues; x0 += 8) {
            const std::size_t count = std::min<std::size_t>(8, rowValues - x0);
            for (std::size_t m = 0; m < n; ++m) {
                const float* row = bank.result(m).row(y) + x0;
                std::copy(row, row + count, v.begin() + std::ptrdiff_t(8 * m));
            }
            sortLanes(v.data(), n);
            std::copy(v.begin() + std::ptrdiff_t(8 * (n / 2)),
                      v.begin() + std::ptrdiff_t(8 * (n / 2) + count), median.row(y) + x0);
        }
    });
    return median;
}

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
                        "emission, or with --half-buffers for the halves estimator",
                    file, "attribute glint:" + std::string(kVarianceUnderflowKey));
    const Image& color = frame.color();
    const Image& variance = frame.layer(Layer::Variance);
    // Rows in parallel to find whether any value is bad; then, only if one is, the serial scan
    // that reports the first in scan order (a clear, reproducible message).
    std::atomic<bool> bad{false};
    tbb::parallel_for(0, frame.height(), [&](int y) {
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
                    throw Error(ErrorKind::Numeric,
                                std::string(std::isnan(v) ? "NaN" : "Inf") +
                                    " in the colour; SURE needs finite values",
                                file,
                                pixelText(x, y) + ", channel " + channelName(Layer::Color, c));
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
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            const std::uint64_t pixel = std::uint64_t(y) * std::uint64_t(width) + std::uint64_t(x);
            const std::uint64_t bits = hash64(seed, pixel);
            for (int c = 0; c < 3; ++c) b(x, y, c) = (bits >> (17 * c + 5)) & 1u ? 1.0f : -1.0f;
        }
    });
    return b;
}

FrameBuffers perturbColor(const FrameBuffers& frame, const SureOptions& options, Image* delta) {
    GLINT_CHECK(frame.has(Layer::Variance));
    FrameBuffers out = frame;
    const Image b = rademacherField(frame.width(), frame.height(), options.seed);
    const Image& y0 = frame.color();
    const Image& variance = frame.layer(Layer::Variance);
    Image& y1 = out.color();
    if (delta) *delta = Image(frame.width(), frame.height(), 3);
    tbb::parallel_for(0, frame.height(), [&](int y) {
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
    tbb::parallel_for(0, region.height(), [&](int y) {
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
    tbb::parallel_for(0, region.height(), [&](int y) {
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
            sure(x, y, 0) = float(s);
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

Image boxSmooth(const Image& image, int radius) {
    GLINT_CHECK(image.channels() == 1 && radius >= 0);
    if (radius == 0 || image.empty()) return image;
    Image out(image.width(), image.height(), 1);
    detail::boxAverages(
        image.width(), image.height(), radius, 1,
        [&](int x, int y, std::size_t) { return double(image(x, y, 0)); },
        [&](int x, int y, const double* mean) { out(x, y, 0) = float(mean[0]); });
    return out;
}

void validate(const AutoOptions& options) {
    if (!(options.sure.epsilon > 0.0) || !std::isfinite(options.sure.epsilon) ||
        options.sure.epsilon > 1.0)
        throw Error(ErrorKind::InvalidArgument,
                    "epsilon " + std::to_string(options.sure.epsilon) +
                        " is not a number in (0, 1] (the perturbation relative to the pixel's "
                        "sigma)",
                    {}, "--epsilon");
    if (options.window && (*options.window < 0 || *options.window > 64))
        throw Error(ErrorKind::InvalidArgument,
                    "window " + std::to_string(*options.window) +
                        " is outside 0 … 64 (the SURE maps' smoothing radius in pixels)",
                    {}, "--window");
    if (options.temperature &&
        (!(*options.temperature >= 0.0) || !std::isfinite(*options.temperature)))
        throw Error(ErrorKind::InvalidArgument,
                    "temperature " + std::to_string(*options.temperature) +
                        " is not a finite number >= 0 (0: hard per-pixel choice)",
                    {}, "--temperature");
    if (options.confidence &&
        (!(*options.confidence >= 0.0) || !std::isfinite(*options.confidence)))
        throw Error(ErrorKind::InvalidArgument,
                    "confidence " + std::to_string(*options.confidence) +
                        " is not a finite number >= 0 (standard errors a local choice must win by)",
                    {}, "--confidence");
    if (options.finer && (*options.finer < 0 || *options.finer > 6))
        throw Error(ErrorKind::InvalidArgument,
                    "finer " + std::to_string(*options.finer) +
                        " is outside 0 … 6 (how many times the window is halved for the final "
                        "choice)",
                    {}, "--finer");
    if (options.feather && (*options.feather < 0 || *options.feather > 32))
        throw Error(ErrorKind::InvalidArgument,
                    "feather " + std::to_string(*options.feather) +
                        " is outside 0 … 32 (the weight planes' smoothing radius in pixels)",
                    {}, "--feather");
    if (!(options.featherGate > 0.0) || !std::isfinite(options.featherGate))
        throw Error(ErrorKind::InvalidArgument,
                    "feather gate " + std::to_string(options.featherGate) +
                        " is not a finite number > 0 (a display-value difference; 1 is the whole "
                        "range)",
                    {}, "--feather-gate");
    if (options.shortlist < 0 || options.shortlist > 4096)
        throw Error(ErrorKind::InvalidArgument,
                    "shortlist " + std::to_string(options.shortlist) +
                        " is outside 0 … 4096 (members filtered on both halves; 0: all)",
                    {}, "--shortlist");
    if (options.stack && (*options.stack < 0 || *options.stack > int(detail::kMaxStack)))
        throw Error(ErrorKind::InvalidArgument,
                    "stack " + std::to_string(*options.stack) + " is outside 0 … " +
                        std::to_string(detail::kMaxStack) + " (members in the stacking; 0: off)",
                    {}, "--stack");
    if (options.stackWindow < 1 || options.stackWindow > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack window " + std::to_string(options.stackWindow) +
                        " is outside 1 … 64 (the stacking's window radius in pixels)",
                    {}, "--stack-window");
    if (!(options.stackFloor >= 0.0) || !(options.stackFloor <= 100.0))
        throw Error(ErrorKind::InvalidArgument,
                    "stack floor " + std::to_string(options.stackFloor) +
                        " is not a number in 0 … 100 (the stacking's ridge floor, in units of the "
                        "members' mean squared difference from the composite)",
                    {}, "--stack-floor");
    if (options.stackSmooth < 0 || options.stackSmooth > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack smooth " + std::to_string(options.stackSmooth) +
                        " is outside 0 … 64 (the radius over which the stacking's coefficients "
                        "are averaged; 0: off)",
                    {}, "--stack-smooth");
    if (!(options.stackRidge >= 0.0) || !std::isfinite(options.stackRidge))
        throw Error(ErrorKind::InvalidArgument,
                    "stack ridge " + std::to_string(options.stackRidge) +
                        " is not a finite number >= 0 (in units of the halves' noise)",
                    {}, "--stack-ridge");
    if (options.stackFeatureWindow < 1 || options.stackFeatureWindow > 64)
        throw Error(ErrorKind::InvalidArgument,
                    "stack feature window " + std::to_string(options.stackFeatureWindow) +
                        " is outside 1 … 64 (the radius of the features' local average)",
                    {}, "--stack-feature-window");
    // 2^64 keeps every finite radiance finite on the display (as glint-image's --exposure).
    if (!(std::fabs(options.exposure) <= kMaxExposure)) {
        char got[32];
        std::snprintf(got, sizeof got, "%g", double(options.exposure));
        throw Error(ErrorKind::InvalidArgument,
                    std::string("exposure must be a number of stops in [-64, 64], got ") + got, {},
                    "--exposure");
    }
}

SureSpace parseSureSpace(const std::string& name) {
    if (name == "display") return SureSpace::Display;
    if (name == "display-tangent") return SureSpace::DisplayTangent;
    if (name == "display-exact") return SureSpace::DisplayExact;
    if (name == "linear") return SureSpace::Linear;
    throw Error(ErrorKind::InvalidArgument,
                "unknown error space '" + name +
                    "' (expected display, display-tangent, display-exact or linear)");
}

const char* sureSpaceName(SureSpace space) {
    switch (space) {
        case SureSpace::Display:
            return "display";
        case SureSpace::DisplayTangent:
            return "display-tangent";
        case SureSpace::DisplayExact:
            return "display-exact";
        case SureSpace::Linear:
            return "linear";
    }
    return "display";
}

AutoEstimator parseAutoEstimator(const std::string& name) {
    if (name == "auto") return AutoEstimator::Auto;
    if (name == "sure") return AutoEstimator::Sure;
    if (name == "halves") return AutoEstimator::Halves;
    throw Error(ErrorKind::InvalidArgument,
                "unknown error estimator '" + name + "' (expected auto, sure or halves)");
}

const char* autoEstimatorName(AutoEstimator estimator) {
    switch (estimator) {
        case AutoEstimator::Auto:
            return "auto";
        case AutoEstimator::Sure:
            return "sure";
        case AutoEstimator::Halves:
            return "halves";
    }
    return "?";
}

AutoDefaults autoDefaults(AutoEstimator estimator) {
    if (estimator == AutoEstimator::Halves) return {8, 1.0, 0.06, 1, 5, 6};
    return {4, 3.0, 0.0, 0, 4, 0};
}

AutoEstimator resolveEstimator(AutoEstimator estimator, const FrameBuffers& frame) {
    if (estimator != AutoEstimator::Auto) return estimator;
    return frame.has(Layer::HalfColor) ? AutoEstimator::Halves : AutoEstimator::Sure;
}

void checkAutoInput(const FrameBuffers& frame, AutoEstimator estimator, const std::string& file) {
    if (resolveEstimator(estimator, frame) == AutoEstimator::Sure) {
        checkSureInput(frame, file);
        return;
    }
    if (!frame.has(Layer::HalfColor))
        throw Error(ErrorKind::Format,
                    "has no halfColor layer: the halves estimator needs a render with half "
                    "buffers (glint-render --half-buffers)",
                    file, "layer 'halfColor'");
    splitHalves(frame, file);  // every half layer present, counts consistent
    checkHalvesFinite(frame, file);
}

Image crossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                         const Image* outputB, const Rect& region, const Image* weight,
                         std::optional<float> displayExposure) {
    GLINT_CHECK(outputA.width() == region.width() && outputA.height() == region.height() &&
                halfA.sameShape(halfB) && (!outputB || outputB->sameShape(outputA)) &&
                !(weight && displayExposure));
    const DisplayCurve display(displayExposure ? std::exp2(double(*displayExposure)) : 1.0);
    auto value = [&](float v) { return displayExposure ? display(double(v)) : double(v); };
    Image map(region.width(), region.height(), 1);
    tbb::parallel_for(0, region.height(), [&](int y) {
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
            map(x, y, 0) = float(s);
        }
    });
    return map;
}

namespace {

// D(m) of the centre, per pixel and channel in row order (computed once for all members; in
// double, as the maps use it).
std::vector<double> displayOf(const Image& centre, float exposure) {
    const DisplayCurve display(std::exp2(double(exposure)));
    const std::size_t rowValues = std::size_t(centre.width()) * 3;
    std::vector<double> out(rowValues * std::size_t(centre.height()));
    tbb::parallel_for(0, centre.height(), [&](int y) {
        const float* in = centre.row(y);
        double* o = out.data() + std::size_t(y) * rowValues;
        for (std::size_t i = 0; i < rowValues; ++i) o[i] = display(double(in[i]));
    });
    return out;
}

// secantCrossValidationMap with D(centre) given (`displayCentre`, from displayOf): the auto
// composite computes it once for the 86 maps it makes.
Image secantMap(const Image& halfA, const Image& halfB, const Image& outputA, const Image* outputB,
                const Rect& region, const Image& centre, const std::vector<double>& displayCentre,
                float exposure, SecantForm form, double* unbiasedMean) {
    GLINT_CHECK(outputA.width() == region.width() && outputA.height() == region.height() &&
                halfA.sameShape(halfB) && (!outputB || outputB->sameShape(outputA)) &&
                centre.sameShape(outputA) && displayCentre.size() == centre.data().size() &&
                halfA.channels() == 3 && outputA.channels() == 3 && centre.channels() == 3);
    const DisplayCurve display(std::exp2(double(exposure)));
    const bool centred = form == SecantForm::Centred;
    Image map(region.width(), region.height(), 1);
    // Per row, the sum of the unbiased terms (added up in row order below: deterministic).
    std::vector<double> rowSums(std::size_t(region.height()), 0.0);
    tbb::parallel_for(0, region.height(), [&](int y) {
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
            out[x] = float(s);
            rowSum += unbiased;
        }
        rowSums[std::size_t(y)] = rowSum;
    });
    if (unbiasedMean) {
        double total = 0.0;
        for (double v : rowSums) total += v;
        *unbiasedMean = total / double(map.pixelCount()) / 3.0;
    }
    return map;
}

}  // namespace

Image secantCrossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                               const Image* outputB, const Rect& region, const Image& centre,
                               float exposure, SecantForm form, double* unbiasedMean) {
    GLINT_CHECK(centre.sameShape(outputA));
    return secantMap(halfA, halfB, outputA, outputB, region, centre, displayOf(centre, exposure),
                     exposure, form, unbiasedMean);
}

// The score of autoComposite's step 2 in one pass over the candidate's map and the baseline's
// (sure_detail.h). The sums are boxSmooth's, term for term and in its order, so the score is the
// same as smoothing stored d and d² maps, without storing them (nor the two averages).
Image detail::windowScore(const Image& raw, const Image& base, int radius, double confidence) {
    const int w = raw.width(), h = raw.height();
    const std::size_t planes = confidence > 0.0 ? 2 : 1;
    Image score(w, h, 1);
    const double count = double((2 * radius + 1) * (2 * radius + 1));
    auto scoreOf = [&](float mean, float meanSq) {
        const double mu = mean;
        const double var = std::max(0.0, double(meanSq) - mu * mu);
        return float(mu + confidence * std::sqrt(var / count));
    };
    if (radius == 0) {  // boxSmooth returns the map itself
        for (std::size_t p = 0; p < score.data().size(); ++p) {
            const double v = double(raw.data()[p]) - double(base.data()[p]);
            score.data()[p] = planes == 1 ? float(v) : scoreOf(float(v), float(v * v));
        }
        return score;
    }
    detail::boxAverages(
        w, h, radius, planes,
        [&](int x, int y, std::size_t k) {
            const double v = double(raw(x, y, 0)) - double(base(x, y, 0));
            return double(k == 0 ? float(v) : float(v * v));
        },
        [&](int x, int y, const double* means) {
            score(x, y, 0) =
                planes == 1 ? float(means[0]) : scoreOf(float(means[0]), float(means[1]));
        });
    return score;
}

namespace {

// Each member's result in the bank, for blendRow.
std::vector<const Image*> bankResults(const FilterBank& bank) {
    std::vector<const Image*> out(bank.size());
    for (std::size_t m = 0; m < bank.size(); ++m) out[m] = &bank.result(m);
    return out;
}

// One row of the blend Σ weight · result over the members that have a weight plane, in member
// order, in double (3 values per pixel into `sum`, width × 3), `results` per member: the
// composite, the unfeathered composite feathering gates against, and the blends on the halves
// that the stacking corrects.
void blendRow(const std::vector<Image>& planes, const std::vector<const Image*>& results, int y,
              std::vector<double>& sum) {
    std::fill(sum.begin(), sum.end(), 0.0);
    for (std::size_t m = 0; m < planes.size(); ++m) {
        if (planes[m].empty()) continue;
        const float* w = planes[m].row(y);
        const float* value = results[m]->row(y);
        for (int x = 0; x < planes[m].width(); ++x) {
            if (w[x] == 0.0f) continue;
            for (std::size_t k = 0; k < 3; ++k)
                sum[std::size_t(x) * 3 + k] += double(w[x]) * double(value[std::size_t(x) * 3 + k]);
        }
    }
}

// Feathering of the final weight planes (AutoOptions::feather): each member's plane (the
// non-empty ones, those of the final candidates) box-averaged over `radius`, zero where the
// member's display value is more than `gate` from the unfeathered composite's in a channel,
// then renormalised per pixel; a pixel where every feathered weight is 0 takes the member with
// the largest unfeathered weight alone.
void featherWeights(std::vector<Image>& planes, const FilterBank& bank, int radius, double gate,
                    float exposure) {
    std::vector<std::size_t> used;
    for (std::size_t m = 0; m < planes.size(); ++m)
        if (!planes[m].empty()) used.push_back(m);
    if (used.empty()) return;
    const int width = planes[used.front()].width(), height = planes[used.front()].height();
    const DisplayCurve display(std::exp2(double(exposure)));
    // The unfeathered composite in display values (blended as step 4 blends the final one).
    Image composite(width, height, 3);
    const std::vector<const Image*> results = bankResults(bank);
    tbb::parallel_for(0, height, [&](int y) {
        std::vector<double> sum(std::size_t(width) * 3);
        blendRow(planes, results, y, sum);
        float* out = composite.row(y);
        for (std::size_t i = 0; i < sum.size(); ++i) out[i] = float(display(sum[i]));
    });
    // Each plane feathered and gated (members in parallel).
    std::vector<Image> feathered(used.size());
    tbb::parallel_for(std::size_t(0), used.size(), [&](std::size_t j) {
        const std::size_t m = used[j];
        Image f = boxSmooth(planes[m], radius);
        for (int y = 0; y < height; ++y) {
            float* w = f.row(y);
            const float* value = bank.result(m).row(y);
            const float* target = composite.row(y);
            for (int x = 0; x < width; ++x) {
                if (w[x] == 0.0f) continue;
                for (std::size_t k = 0; k < 3; ++k) {
                    const std::size_t i = std::size_t(x) * 3 + k;
                    if (std::fabs(display(double(value[i])) - double(target[i])) > gate) {
                        w[x] = 0.0f;
                        break;
                    }
                }
            }
        }
        feathered[j] = std::move(f);
    });
    // Renormalised per pixel (the members in order).
    tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
            double sum = 0.0;
            for (const Image& f : feathered) sum += f(x, y, 0);
            if (!(sum > 0.0)) {
                // Every member is gated: the members blended here differ by more than the gate
                // from their blend, so the one with the largest weight is taken alone.
                std::size_t top = 0;
                for (std::size_t j = 1; j < used.size(); ++j)
                    if (planes[used[j]](x, y, 0) > planes[used[top]](x, y, 0)) top = j;
                for (std::size_t j = 0; j < used.size(); ++j)
                    planes[used[j]](x, y, 0) = j == top ? 1.0f : 0.0f;
                continue;
            }
            for (std::size_t j = 0; j < used.size(); ++j)
                planes[used[j]](x, y, 0) = float(double(feathered[j](x, y, 0)) / sum);
        }
    });
}

}  // namespace

AutoResult autoComposite(const FilterBank& bank, const FrameBuffers& frame,
                         const AutoOptions& options) {
    validate(options);
    if (bank.size() == 0) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    if (frame.width() != bank.frameWidth() || frame.height() != bank.frameHeight() ||
        hashFrame(frame) != bank.inputHash())
        throw Error(ErrorKind::InvalidArgument,
                    "the bank was computed from another image than the one given");
    const AutoEstimator estimator = resolveEstimator(options.estimator, frame);
    const bool halves = estimator == AutoEstimator::Halves;
    if (options.space == SureSpace::DisplayExact && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "the exact display space needs the halves estimator (SURE needs a "
                    "differentiable error: use display or linear)",
                    {}, "--space");
    if (options.stack.value_or(0) > 0 && !halves)
        throw Error(ErrorKind::InvalidArgument,
                    "stacking fits each half on the other: it needs the halves estimator (an "
                    "input rendered with --half-buffers)",
                    {}, "--stack");
    if (options.stack.value_or(0) > 0 && !options.symmetric)
        throw Error(ErrorKind::InvalidArgument, "stacking fits both halves: it cannot be one-sided",
                    {}, "--stack");
    // The stacking's features (docs/auto.md, "Stacking"): those asked for must be in the input,
    // with their halves; unset, those it has.
    const auto hasFeature = [&](Layer layer) {
        return frame.has(layer) && frame.has(*halfLayer(layer));
    };
    const bool stackAlbedo = options.stackAlbedo.value_or(hasFeature(Layer::Albedo));
    const bool stackNormal = options.stackNormal.value_or(hasFeature(Layer::Normal));
    if (halves && options.symmetric && options.stack.value_or(autoDefaults(estimator).stack) > 0) {
        const std::pair<bool, Layer> features[] = {{stackAlbedo, Layer::Albedo},
                                                   {stackNormal, Layer::Normal}};
        for (const auto& [wanted, layer] : features) {
            if (!wanted) continue;
            for (Layer l : {layer, *halfLayer(layer)})
                if (!frame.has(l))
                    throw Error(ErrorKind::Format,
                                "has no " + std::string(layerDisplayName(l)) +
                                    " layer: the stacking's feature regressors need it "
                                    "(--stack-features names the ones to use; none: off)",
                                {}, "layer '" + std::string(layerDisplayName(l)) + "'");
        }
    }
    const int window = options.window.value_or(autoDefaults(estimator).window);
    const double confidence = options.confidence.value_or(autoDefaults(estimator).confidence);
    const double temperature = options.temperature.value_or(autoDefaults(estimator).temperature);
    const int finer = options.finer.value_or(autoDefaults(estimator).finer);
    const int feather = options.feather.value_or(autoDefaults(estimator).feather);
    // Validation as checkAutoInput's, without a second split (the halves' below checks them).
    if (!halves || !frame.has(Layer::HalfColor))
        checkAutoInput(frame, estimator);
    else
        checkHalvesFinite(frame, {});
    const Rect& region = bank.region();
    const std::size_t n = bank.size();
    const std::size_t pixels = std::size_t(region.width()) * std::size_t(region.height());

    // SURE: the input the filters see (prefiltered like the bank's) and its perturbed copy.
    // Halves: the two halves, each prefiltered like the bank's input.
    auto prepare = [&](const FrameBuffers& f) {
        return options.prefilter ? prefilterFeatures(f, options.prefilterParams) : f;
    };
    FrameBuffers filterInput, perturbed, halfA, halfB;
    Image delta;
    if (halves) {
        auto split = splitHalves(frame);
        halfA = options.prefilter ? prepare(split.first) : std::move(split.first);
        halfB = options.prefilter ? prepare(split.second) : std::move(split.second);
    } else {
        filterInput = prepare(frame);
        perturbed = perturbColor(filterInput, options.sure, &delta);
    }
    // The display spaces linearise around the bank's median: SURE and DisplayTangent by the
    // slope there (weight), the halves' Display by the secant to each output (secant).
    const bool secant = halves && options.space == SureSpace::Display;
    const bool tangent = options.space == SureSpace::DisplayTangent ||
                         (!halves && options.space == SureSpace::Display);
    const Image median = secant || tangent ? bankMedian(bank) : Image{};
    const std::vector<double> displayMedian =
        secant ? displayOf(median, options.exposure) : std::vector<double>{};
    // The tangent weights also scale the temperature's noise unit in both display spaces.
    const Image weight = secant || tangent ? tangentWeights(median, options.exposure) : Image{};
    const Image* weightPtr = tangent ? &weight : nullptr;

    // Halves with a shortlist: every member on A first (one-sided maps), both halves only for
    // the shortlisted members (below).
    const bool shortlisted =
        halves && options.symmetric && options.shortlist > 0 && std::size_t(options.shortlist) < n;
    const bool bothHalves = options.symmetric && !shortlisted;
    const std::size_t work = shortlisted ? n + std::size_t(options.shortlist) : n;

    // Stacking keeps each member's results on the halves (those not shortlisted are dropped
    // once the shortlist is known).
    const int stack = options.stack.value_or(options.symmetric ? autoDefaults(estimator).stack : 0);
    const bool stacking = stack > 0;
    std::vector<Image> onA(stacking ? n : 0), onB(stacking ? n : 0);

    // Step 1: every member's SURE map (members in parallel, like the bank).
    std::vector<Image> raws(n);
    std::vector<double> estimatedMse(n, 0.0);
    // The mean of each member's map: estimatedMse, except for the secant's centred maps.
    std::vector<double> mapMean(n, 0.0);
    std::vector<char> analytic(n, 0);
    std::mutex progressMutex;
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> done{0};
    auto report = [&] {
        if (!options.progress) return;
        const std::lock_guard<std::mutex> lock(progressMutex);
        if (!stop.load() && !options.progress(double(done.load()) / double(work))) stop.store(true);
    };
    report();
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t m) {
        if (stop.load()) return;
        const BankMember& member = bank.members()[m];
        bool isAnalytic = false;
        Image raw;
        std::optional<double> unbiased;  // the secant's unbiased mean (its map is centred)
        try {
            const ProgressFn going = [&](double) { return !stop.load(); };
            if (halves) {
                FilterOptions fo;
                fo.region = region;
                fo.progress = going;
                const Filter& filter = findFilter(member.filter);
                Image outA = applyFilter(filter, halfA, member.params, fo);
                Image outB = bothHalves ? applyFilter(filter, halfB, member.params, fo) : Image{};
                const bool exact = options.space == SureSpace::DisplayExact;
                const Image* outBPtr = bothHalves ? &outB : nullptr;
                double mean = 0.0;
                raw = secant
                          ? secantMap(halfA.color(), halfB.color(), outA, outBPtr, region, median,
                                      displayMedian, options.exposure, SecantForm::Centred, &mean)
                          : crossValidationMap(
                                halfA.color(), halfB.color(), outA, outBPtr, region, weightPtr,
                                exact ? std::optional<float>(options.exposure) : std::nullopt);
                if (secant) unbiased = mean;
                if (stacking) {
                    onA[m] = std::move(outA);
                    if (bothHalves) onB[m] = std::move(outB);
                }
            } else {
                const Image div = memberDivergence(findFilter(member.filter), member.params,
                                                   bank.result(m), filterInput, perturbed, delta,
                                                   region, options.sure, going, isAnalytic);
                raw = sureMap(frame.color(), frame.layer(Layer::Variance), bank.result(m), div,
                              region, weightPtr);
            }
        } catch (const Error& e) {
            if (e.kind() == ErrorKind::Cancelled) return;
            throw;
        }
        analytic[m] = isAnalytic ? 1 : 0;
        mapMean[m] = meanPerChannel(raw);
        estimatedMse[m] = unbiased.value_or(mapMean[m]);
        raws[m] = std::move(raw);
        ++done;
        report();
    });
    if (stop.load()) throw Error(ErrorKind::Cancelled, "auto composite cancelled");

    // The smoothed noise level per pixel (the temperature's unit).
    Image noiseLevel;
    if (temperature > 0.0) {
        Image v(region.width(), region.height(), 1);
        for (int y = 0; y < region.height(); ++y)
            for (int x = 0; x < region.width(); ++x) {
                double s = 0.0;
                for (int c = 0; c < 3; ++c) {
                    const int fx = x + region.x0, fy = y + region.y0;
                    // Halves: (A − B)²/4, the variance of the mean of equal halves.
                    double var;
                    if (halves) {
                        const double d =
                            double(halfA.color()(fx, fy, c)) - halfB.color()(fx, fy, c);
                        var = 0.25 * d * d;
                    } else {
                        var = frame.layer(Layer::Variance)(fx, fy, c);
                    }
                    s += var * (weight.empty() ? 1.0 : double(weight(x, y, c)));
                }
                v(x, y, 0) = float(s);
            }
        noiseLevel = boxSmooth(v, window);
    }

    // Steps 2 and 3, over `candidates` (member indices, ascending): per member, the pixels where
    // it has the largest weight, its total weight and, for the final choice, its weight plane
    // (0 and empty for the others).
    const int width = region.width();
    struct Choice {
        std::vector<Image> planes;
        std::vector<long> wins;
        std::vector<double> totals;
    };
    auto choose = [&](const std::vector<std::size_t>& candidates, bool final) {
        const std::size_t c = candidates.size();
        // Step 2: the score of each candidate per pixel. The baseline is the candidate with the
        // smallest map mean over the region; another scores the smoothed difference to it plus
        // `confidence` standard errors of that local mean (from the difference's spread in the
        // window), so a pixel leaves the baseline only where the estimate says, with that
        // confidence, that another member is better there. With confidence 0 it is the plain
        // smoothed estimate. In the final choice, with `finer` > 0, the same is done in the
        // window halved `finer` times too, and the score is the lowest of them: a member that
        // is better by that margin in a smaller window wins there (docs/auto.md, "Per-pixel
        // choice").
        std::size_t baseline = 0;  // position in candidates
        for (std::size_t j = 0; j < c; ++j)
            if (mapMean[candidates[j]] < mapMean[candidates[baseline]]) baseline = j;
        const Image& base = raws[candidates[baseline]];
        std::vector<int> radii{window};
        if (final)
            for (int k = 0; k < finer && radii.back() > 1; ++k) radii.push_back(radii.back() / 2);
        std::vector<Image> scores(c);
        tbb::parallel_for(std::size_t(0), c, [&](std::size_t j) {
            const Image& raw = raws[candidates[j]];
            Image score;
            for (int radius : radii) {
                Image mean =
                    detail::windowScore(raw, base, radius, j != baseline ? confidence : 0.0);
                if (score.empty()) {
                    score = std::move(mean);
                } else {
                    for (std::size_t p = 0; p < pixels; ++p)
                        score.data()[p] = std::min(score.data()[p], mean.data()[p]);
                }
            }
            scores[j] = std::move(score);
        });

        // Step 3: per-pixel weights over the candidates, in member order (deterministic). Rows
        // go in chunks of 64 pixels so that each candidate's scores are read and its weights
        // written as one run, not one value from each of c images per pixel. Only the final
        // choice keeps the weight planes; the first of a shortlist needs only each candidate's
        // pixels won and total weight (per row, then the rows in order).
        Choice out;
        if (final) {
            out.planes.resize(n);
            for (std::size_t m : candidates) out.planes[m] = Image(width, region.height(), 1);
        }
        std::vector<std::vector<int>> rowWins(std::size_t(region.height()));
        std::vector<std::vector<double>> rowTotals(std::size_t(region.height()));
        constexpr int kChunk = 64;
        tbb::parallel_for(0, region.height(), [&](int y) {
            std::vector<double> s(c * kChunk);
            std::vector<float> w(c * kChunk);
            std::vector<int>& wins = rowWins[std::size_t(y)];
            std::vector<double>& rowTotal = rowTotals[std::size_t(y)];
            wins.assign(c, 0);
            rowTotal.assign(c, 0.0);
            for (int x0 = 0; x0 < width; x0 += kChunk) {
                const int pixelsHere = std::min(kChunk, width - x0);
                for (std::size_t j = 0; j < c; ++j) {
                    const float* row = scores[j].row(y) + x0;
                    for (int k = 0; k < pixelsHere; ++k) s[j * kChunk + std::size_t(k)] = row[k];
                }
                std::fill(w.begin(), w.end(), 0.0f);
                for (int k = 0; k < pixelsHere; ++k) {
                    const auto at = [&](std::size_t j) { return j * kChunk + std::size_t(k); };
                    std::size_t best = baseline;
                    for (std::size_t j = 0; j < c; ++j)
                        if (s[at(j)] < s[at(best)]) best = j;
                    ++wins[best];
                    const double unit =
                        temperature > 0.0 ? temperature * double(noiseLevel(x0 + k, y, 0)) : 0.0;
                    if (!(unit > 0.0)) {
                        w[at(best)] = 1.0f;
                        continue;
                    }
                    double sum = 0.0;
                    for (std::size_t j = 0; j < c; ++j) {
                        // exp(−6.91) < 1e-3: no exp for the many candidates that get weight 0.
                        const double x = (s[at(j)] - s[at(best)]) / unit;
                        const double e = x > 6.91 ? 0.0 : std::exp(-x);
                        w[at(j)] = e < 1e-3 ? 0.0f : float(e);
                        sum += w[at(j)];
                    }
                    for (std::size_t j = 0; j < c; ++j) w[at(j)] = float(w[at(j)] / sum);
                }
                for (std::size_t j = 0; j < c; ++j) {
                    const float* run = w.data() + j * kChunk;
                    for (int k = 0; k < pixelsHere; ++k) rowTotal[j] += run[k];
                    if (final)
                        std::copy(run, run + pixelsHere, out.planes[candidates[j]].row(y) + x0);
                }
            }
        });
        // Pixels won: where a candidate has the smallest score (the largest weight).
        out.wins.assign(n, 0);
        out.totals.assign(n, 0.0);
        for (std::size_t y = 0; y < rowWins.size(); ++y)
            for (std::size_t j = 0; j < c; ++j) {
                out.wins[candidates[j]] += rowWins[y][j];
                out.totals[candidates[j]] += rowTotals[y][j];
            }
        return out;
    };

    std::vector<std::size_t> candidates(n);
    std::iota(candidates.begin(), candidates.end(), std::size_t(0));
    Choice chosen = choose(candidates, !shortlisted);
    if (shortlisted) {
        // The shortlist: the members that carry the largest weight at the most pixels in the
        // one-sided choice (then by total weight, then member order; by pixels won rather than
        // by total weight, so that a member that wins one region outright is not outranked by
        // members with a little weight everywhere), filtered on B too. Their maps become the
        // symmetric form, the average of the A-side and B-side terms, and the final choice is
        // among them.
        std::vector<std::size_t> order = candidates;
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            const auto& wins = chosen.wins;
            const auto& totals = chosen.totals;
            return wins[a] != wins[b] ? wins[a] > wins[b] : totals[a] > totals[b];
        });
        order.resize(std::size_t(options.shortlist));
        std::sort(order.begin(), order.end());
        if (stacking)
            for (std::size_t m = 0; m < n; ++m)
                if (!std::binary_search(order.begin(), order.end(), m)) onA[m] = Image{};
        tbb::parallel_for(std::size_t(0), order.size(), [&](std::size_t j) {
            if (stop.load()) return;
            const std::size_t m = order[j];
            const BankMember& member = bank.members()[m];
            Image rawB;
            double meanB = 0.0;
            try {
                FilterOptions fo;
                fo.region = region;
                fo.progress = [&](double) { return !stop.load(); };
                Image outB = applyFilter(findFilter(member.filter), halfB, member.params, fo);
                // B's term: the one-sided form with the halves' roles swapped.
                rawB = secant
                           ? secantMap(halfB.color(), halfA.color(), outB, nullptr, region, median,
                                       displayMedian, options.exposure, SecantForm::Centred, &meanB)
                           : crossValidationMap(halfB.color(), halfA.color(), outB, nullptr, region,
                                                weightPtr,
                                                options.space == SureSpace::DisplayExact
                                                    ? std::optional<float>(options.exposure)
                                                    : std::nullopt);
                if (stacking) onB[m] = std::move(outB);
            } catch (const Error& e) {
                if (e.kind() == ErrorKind::Cancelled) return;
                throw;
            }
            Image& raw = raws[m];
            for (std::size_t p = 0; p < pixels; ++p)
                raw.data()[p] = float(0.5 * (double(raw.data()[p]) + double(rawB.data()[p])));
            // The secant's: the mean of its unbiased form on both sides (A's from step 1).
            mapMean[m] = meanPerChannel(raw);
            estimatedMse[m] = secant ? 0.5 * (estimatedMse[m] + meanB) : mapMean[m];
            ++done;
            report();
        });
        if (stop.load()) throw Error(ErrorKind::Cancelled, "auto composite cancelled");
        candidates = std::move(order);
        chosen = choose(candidates, true);
    }

    std::vector<Image>& planes = chosen.planes;
    if (feather > 0) featherWeights(planes, bank, feather, options.featherGate, options.exposure);
    // Each member's weight summed over the region (after feathering; rows in order, scaled by
    // 1 / (3 · pixels), which keeps the order and which are 0).
    std::vector<double> totals(n, 0.0);
    for (std::size_t m = 0; m < n; ++m)
        if (!planes[m].empty()) totals[m] = meanPerChannel(planes[m]);
    // Step 4: the composite (member order, as the weights), the layers (members with any
    // weight, largest total first).
    AutoResult result;
    result.composite = Image(width, region.height(), 3);
    result.choice = Image(width, region.height(), 1);
    const std::vector<const Image*> results = bankResults(bank);
    tbb::parallel_for(0, region.height(), [&](int y) {
        std::vector<double> c(std::size_t(width) * 3);
        blendRow(planes, results, y, c);
        std::vector<float> topWeight(std::size_t(width), 0.0f);
        std::vector<int> top(std::size_t(width), 0);
        for (std::size_t m = 0; m < n; ++m) {
            if (totals[m] == 0.0) continue;  // weight 0 everywhere: never the top
            const float* w = planes[m].row(y);
            for (int x = 0; x < width; ++x)
                if (w[x] > topWeight[std::size_t(x)])
                    topWeight[std::size_t(x)] = w[x], top[std::size_t(x)] = int(m);
        }
        float* out = result.composite.row(y);
        for (std::size_t i = 0; i < c.size(); ++i) out[i] = float(c[i]);
        for (int x = 0; x < width; ++x) result.choice(x, y, 0) = float(top[std::size_t(x)]);
    });
    std::vector<int> order;
    for (std::size_t m = 0; m < n; ++m)
        if (totals[m] > 0.0) order.push_back(int(m));
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return totals[std::size_t(a)] > totals[std::size_t(b)]; });
    result.estimatedMse = estimatedMse;
    std::size_t best = candidates.front();
    for (std::size_t m : candidates)
        if (estimatedMse[m] < estimatedMse[best]) best = m;
    result.bestMember = int(best);
    for (char a : analytic) result.analytic.push_back(a != 0);
    result.estimator = estimator;
    if (stacking) {
        // Step 5: the stacking (docs/auto.md, "Stacking"), around the blend on each half.
        Image blendA(width, region.height(), 3), blendB(width, region.height(), 3);
        std::vector<const Image*> resultsA(n, nullptr), resultsB(n, nullptr);
        for (std::size_t m = 0; m < n; ++m)
            if (!planes[m].empty()) resultsA[m] = &onA[m], resultsB[m] = &onB[m];
        tbb::parallel_for(0, region.height(), [&](int y) {
            std::vector<double> a(std::size_t(width) * 3), b(std::size_t(width) * 3);
            blendRow(planes, resultsA, y, a);
            blendRow(planes, resultsB, y, b);
            std::copy(a.begin(), a.end(), blendA.row(y));
            std::copy(b.begin(), b.end(), blendB.row(y));
        });
        std::vector<detail::StackMember> stacked;
        for (int m : order) {
            if (stacked.size() == std::size_t(stack)) break;
            const std::size_t i = std::size_t(m);
            stacked.push_back({&bank.result(i), &onA[i], &onB[i]});
        }
        // The features' regressors (docs/auto.md, "Stacking"), from the whole frame's features
        // around the composite and from each half's around its blend.
        std::vector<Image> features[3];
        if (stackAlbedo || stackNormal) {
            // As the filters saw them: prefiltered when the bank was.
            const FrameBuffers prefiltered = options.prefilter ? prepare(frame) : FrameBuffers{};
            const FrameBuffers* sources[3] = {options.prefilter ? &prefiltered : &frame, &halfA,
                                              &halfB};
            const Image* bases[3] = {&result.composite, &blendA, &blendB};
            for (int side = 0; side < 3; ++side) {
                const Image albedo =
                    stackAlbedo ? sources[side]->layer(Layer::Albedo).crop(region) : Image{};
                const Image normal =
                    stackNormal ? sources[side]->layer(Layer::Normal).crop(region) : Image{};
                features[side] = detail::featureRegressors(
                    *bases[side], stackAlbedo ? &albedo : nullptr, stackNormal ? &normal : nullptr,
                    options.stackFeatureWindow);
            }
            for (std::size_t q = 0; q < features[0].size(); ++q)
                stacked.push_back({&features[0][q], &features[1][q], &features[2][q]});
        }
        const Image weightAtC = options.space == SureSpace::Linear
                                    ? Image{}
                                    : tangentWeights(result.composite, options.exposure);
        result.composite = detail::stackComposite(
            result.composite, blendA, blendB, stacked, halfA.color().crop(region),
            halfB.color().crop(region), weightAtC, options.stackWindow, options.stackRidge,
            options.stackFloor, options.stackSmooth);
        result.stacked = int(stacked.size() - features[0].size());
        result.stackFeatures = int(features[0].size());
    }
    for (int m : order) result.layers.push_back({m, std::move(planes[std::size_t(m)])});
    return result;
}

std::size_t startFromAuto(Session& session, const FilterBank& bank, const AutoResult& result) {
    const Rect whole{0, session.width(), 0, session.height()};
    if (bank.region() != whole || bank.frameWidth() != session.width() ||
        bank.frameHeight() != session.height())
        throw Error(ErrorKind::InvalidArgument, "an automatic start needs a bank over the whole " +
                                                    std::to_string(session.width()) + "x" +
                                                    std::to_string(session.height()) + " frame");
    if (bank.inputHash() != hashFrame(session.input()))
        throw Error(ErrorKind::InvalidArgument,
                    "the bank was computed from another image than the session's input");
    if (result.stacked > 0)
        throw Error(ErrorKind::InvalidArgument,
                    "a stacked auto composite is not a blend of the members' results, so a "
                    "session cannot start from it: start from auto without --stack");
    for (const AutoLayer& l : result.layers)
        if (l.member < 0 || std::size_t(l.member) >= bank.size() ||
            l.weights.width() != whole.width() || l.weights.height() != whole.height())
            throw Error(ErrorKind::InvalidArgument, "the auto result is not of this bank");
    // Sequential blending: with S_k the sum of the first k layers' weights, layer k shows with
    // a_k = w_k / S_k, so that composite_k = Σ_{j≤k} w_j f_j / S_k and the last one Σ w f.
    const std::size_t pixels = std::size_t(whole.width()) * std::size_t(whole.height());
    std::vector<double> cumulative(pixels, 0.0);
    std::size_t edits = 0;
    for (const AutoLayer& l : result.layers) {
        Image a(whole.width(), whole.height(), 1);
        for (std::size_t p = 0; p < pixels; ++p) {
            const double w = l.weights.data()[p];
            cumulative[p] += w;
            a.data()[p] = cumulative[p] > 0.0 ? float(std::min(1.0, w / cumulative[p])) : 0.0f;
        }
        const BankMember& member = bank.members()[std::size_t(l.member)];
        const std::size_t index =
            session.addLayer(member.filter, member.params, bank.result(std::size_t(l.member)));
        session.setWeights(index, a);
        edits += 2;
    }
    return edits;
}

}  // namespace glint::denoise
