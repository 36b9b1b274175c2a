// Error metrics against a reference (docs/metrics.md).
#include "glint/image/metrics.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/flip.h"
#include "glint/image/io.h"
#include "shape_text.h"
#include "ssim.h"

namespace glint {
namespace {

/// pbrt-style relative MSE denominator offset: (x - r)^2 / (r^2 + 1e-2).
constexpr double kRelEpsilon = 1e-2;

std::string rectText(const Rect& r) {
    return std::to_string(r.x0) + "," + std::to_string(r.x1) + "," + std::to_string(r.y0) + "," +
           std::to_string(r.y1);
}

/// Checks shapes and the crop; returns the rectangle the metric covers.
Rect metricRect(const Image& image, const Image& reference, const MetricOptions& options,
                const char* metric) {
    const std::string where = metric;
    if (!image.sameShape(reference))
        throw Error(ErrorKind::InvalidArgument,
                    "image is " + detail::shapeText(image) +
                        " (width x height x channels) but the " + "reference is " +
                        detail::shapeText(reference) + "; they must match",
                    {}, where);
    if (image.empty())
        throw Error(ErrorKind::InvalidArgument,
                    "image and reference are empty (" + detail::shapeText(image) + ")", {}, where);
    if (!options.crop) return image.bounds();
    const Rect crop = *options.crop;
    if (crop.empty() || intersect(crop, image.bounds()) != crop)
        throw Error(ErrorKind::InvalidArgument,
                    "crop x0,x1,y0,y1 = " + rectText(crop) + " is empty or not inside the " +
                        std::to_string(image.width()) + "x" + std::to_string(image.height()) +
                        " image (expected 0 <= x0 < x1 <= width, 0 <= y0 < y1 <= height)",
                    {}, where);
    return crop;
}

/// True when every channel of both pixels (image and reference) is finite.
bool pixelFinite(const float* a, const float* b, int channels) {
    for (int c = 0; c < channels; ++c)
        if (!std::isfinite(a[c]) || !std::isfinite(b[c])) return false;
    return true;
}

/// Sums perChannel(x, r) over channels of the finite pixels of `rect`; counts the others.
/// Rows are summed in parallel and added in order, so the result is deterministic.
template <class PerChannel>
MetricResult meanOverFinitePixels(const Image& image, const Image& reference, const Rect& rect,
                                  const char* metric, PerChannel perChannel) {
    const int channels = image.channels();
    const std::size_t rows = std::size_t(rect.height());
    std::vector<double> rowSum(rows, 0.0);
    std::vector<std::size_t> rowNonFinite(rows, 0);
    tbb::parallel_for(tbb::blocked_range<int>(rect.y0, rect.y1, 16),
                      [&](const tbb::blocked_range<int>& range) {
                          for (int y = range.begin(); y != range.end(); ++y) {
                              const float* a = image.row(y);
                              const float* b = reference.row(y);
                              double sum = 0.0;
                              std::size_t bad = 0;
                              for (int x = rect.x0; x < rect.x1; ++x) {
                                  const float* pa = a + std::size_t(x) * channels;
                                  const float* pb = b + std::size_t(x) * channels;
                                  if (!pixelFinite(pa, pb, channels)) {
                                      ++bad;
                                      continue;
                                  }
                                  for (int c = 0; c < channels; ++c)
                                      sum += perChannel(double(pa[c]), double(pb[c]));
                              }
                              rowSum[std::size_t(y - rect.y0)] = sum;
                              rowNonFinite[std::size_t(y - rect.y0)] = bad;
                          }
                      });
    MetricResult result;
    result.pixels = std::size_t(rect.width()) * std::size_t(rect.height());
    double total = 0.0;
    for (std::size_t i = 0; i < rows; ++i) {
        total += rowSum[i];
        result.nonFinitePixels += rowNonFinite[i];
    }
    const std::size_t finite = result.pixels - result.nonFinitePixels;
    if (finite == 0)
        throw Error(ErrorKind::Numeric,
                    "all " + std::to_string(result.pixels) +
                        " pixels have NaN/Inf in the image or the reference; nothing to compare",
                    {}, metric);
    result.value = total / (double(finite) * channels);
    return result;
}

double squaredError(double x, double r) {
    return (x - r) * (x - r);
}
double relativeSquaredError(double x, double r) {
    return (x - r) * (x - r) / (r * r + kRelEpsilon);
}

/// One-channel map of mean_c perChannel(x, r) over `rect`; NaN where a value is not finite.
template <class PerChannel>
Image pixelMap(const Image& image, const Image& reference, const Rect& rect,
               PerChannel perChannel) {
    const int channels = image.channels();
    Image map(rect.width(), rect.height(), 1);
    tbb::parallel_for(tbb::blocked_range<int>(rect.y0, rect.y1, 16),
                      [&](const tbb::blocked_range<int>& range) {
                          for (int y = range.begin(); y != range.end(); ++y) {
                              float* out = map.row(y - rect.y0);
                              for (int x = rect.x0; x < rect.x1; ++x) {
                                  const float* pa = image.row(y) + std::size_t(x) * channels;
                                  const float* pb = reference.row(y) + std::size_t(x) * channels;
                                  if (!pixelFinite(pa, pb, channels)) {
                                      out[x - rect.x0] = std::numeric_limits<float>::quiet_NaN();
                                      continue;
                                  }
                                  double sum = 0.0;
                                  for (int c = 0; c < channels; ++c)
                                      sum += perChannel(double(pa[c]), double(pb[c]));
                                  out[x - rect.x0] = float(sum / channels);
                              }
                          }
                      });
    return map;
}

/// Validates an SSIM request: shapes, crop, the 11x11 minimum, the exposure.
detail::SsimRequest ssimRequest(const Image& image, const Image& reference,
                                const MetricOptions& options, const char* metric) {
    const Rect rect = metricRect(image, reference, options, metric);
    if (rect.width() < detail::kSsimMinSize || rect.height() < detail::kSsimMinSize)
        throw Error(ErrorKind::InvalidArgument,
                    "SSIM needs at least " + std::to_string(detail::kSsimMinSize) + "x" +
                        std::to_string(detail::kSsimMinSize) +
                        " pixels (its Gaussian window), got " + std::to_string(rect.width()) + "x" +
                        std::to_string(rect.height()) + (options.crop ? " (crop)" : ""),
                    {}, metric);
    if (!options.linear && !(std::fabs(options.exposure) <= kMaxExposure))
        throw Error(ErrorKind::InvalidArgument,
                    "exposure must be a number of stops in [-64, 64], got " +
                        std::to_string(options.exposure),
                    {}, metric);
    detail::SsimRequest request;
    request.image = &image;
    request.reference = &reference;
    request.rect = rect;
    request.display = !options.linear;
    request.scale = std::exp2(options.exposure);
    return request;
}

}  // namespace

Metric parseMetric(const std::string& name) {
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char ch) { return char(std::tolower(ch)); });
    if (lower == "mse") return Metric::Mse;
    if (lower == "relmse") return Metric::RelMse;
    if (lower == "psnr") return Metric::Psnr;
    if (lower == "ssim") return Metric::Ssim;
    if (lower == "flip-ldr") return Metric::FlipLdr;
    if (lower == "flip-hdr") return Metric::FlipHdr;
    throw Error(ErrorKind::InvalidArgument,
                "unknown metric '" + name +
                    "'; expected one of mse, relmse, psnr, ssim, flip-ldr, flip-hdr");
}

const char* metricName(Metric metric) {
    switch (metric) {
        case Metric::Mse:
            return "mse";
        case Metric::RelMse:
            return "relmse";
        case Metric::Psnr:
            return "psnr";
        case Metric::Ssim:
            return "ssim";
        case Metric::FlipLdr:
            return "flip-ldr";
        case Metric::FlipHdr:
            return "flip-hdr";
    }
    return "unknown";
}

MetricResult mse(const Image& image, const Image& reference, const MetricOptions& options) {
    const Rect rect = metricRect(image, reference, options, "mse");
    return meanOverFinitePixels(image, reference, rect, "mse", squaredError);
}

MetricResult relMse(const Image& image, const Image& reference, const MetricOptions& options) {
    const Rect rect = metricRect(image, reference, options, "relmse");
    return meanOverFinitePixels(image, reference, rect, "relmse", relativeSquaredError);
}

MetricResult psnr(const Image& image, const Image& reference, const MetricOptions& options) {
    const Rect rect = metricRect(image, reference, options, "psnr");
    MetricResult result = meanOverFinitePixels(image, reference, rect, "psnr", squaredError);
    // PSNR = 10 log10(L^2 / MSE) with data range L = 1; identical images give +infinity.
    result.value = result.value > 0.0 ? -10.0 * std::log10(result.value)
                                      : std::numeric_limits<double>::infinity();
    if (std::isnan(result.value))
        throw Error(ErrorKind::Numeric, "PSNR is not a number for these images", {}, "psnr");
    return result;
}

MetricResult ssim(const Image& image, const Image& reference, const MetricOptions& options) {
    const detail::SsimRequest request = ssimRequest(image, reference, options, "ssim");
    const detail::SsimOutcome outcome = detail::computeSsim(request, nullptr);
    MetricResult result;
    result.value = outcome.mean;
    result.nonFinitePixels = outcome.nonFinitePixels;
    result.pixels = std::size_t(request.rect.width()) * std::size_t(request.rect.height());
    // Never hand a NaN on as a number (a metric of NaN would read as a result).
    if (std::isnan(result.value))
        throw Error(ErrorKind::Numeric, "SSIM is not a number for these images", {}, "ssim");
    return result;
}

MetricResult computeMetric(Metric metric, const Image& image, const Image& reference,
                           const MetricOptions& options) {
    switch (metric) {
        case Metric::Mse:
            return mse(image, reference, options);
        case Metric::RelMse:
            return relMse(image, reference, options);
        case Metric::Psnr:
            return psnr(image, reference, options);
        case Metric::Ssim:
            return ssim(image, reference, options);
        case Metric::FlipLdr:
        case Metric::FlipHdr: {
            FlipOptions flipOptions;
            flipOptions.hdr = metric == Metric::FlipHdr;
            flipOptions.crop = options.crop;
            const FlipResult flipped = flip(image, reference, flipOptions);
            MetricResult result;
            result.value = flipped.mean;
            result.pixels = flipped.map.pixelCount();
            return result;
        }
    }
    throw Error(ErrorKind::InvalidArgument, "unknown metric kind");
}

Image absErrorMap(const Image& image, const Image& reference, const MetricOptions& options) {
    const Rect rect = metricRect(image, reference, options, "absolute error map");
    return pixelMap(image, reference, rect, [](double x, double r) { return std::abs(x - r); });
}

Image relErrorMap(const Image& image, const Image& reference, const MetricOptions& options) {
    const Rect rect = metricRect(image, reference, options, "relative error map");
    return pixelMap(image, reference, rect, relativeSquaredError);
}

Image ssimMap(const Image& image, const Image& reference, const MetricOptions& options) {
    Image map;
    detail::computeSsim(ssimRequest(image, reference, options, "ssim map"), &map);
    return map;
}

}  // namespace glint
