// Error metrics against a reference: MSE, relMSE, PSNR, SSIM, FLIP (docs/metrics.md).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "glint/image/image.h"

namespace glint {

/// How metrics treat their inputs.
struct MetricOptions {
    /// SSIM only: compute on display values (exposure, clamp to [0,1], sRGB) unless linear.
    bool linear = false;
    float exposure = 0.0f;
    /// Restrict to this rectangle (must lie inside the image).
    std::optional<Rect> crop;
};

/// A metric value with what it did about non-finite pixels.
struct MetricResult {
    double value = 0.0;
    /// Pixels in which the image or the reference had a NaN/Inf in some channel. They are left
    /// out of MSE/relMSE/PSNR; for SSIM each non-finite value (only that channel) is replaced by
    /// 0 before filtering.
    std::size_t nonFinitePixels = 0;
    std::size_t pixels = 0;  ///< pixels considered (crop area)
};

enum class Metric { Mse, RelMse, Psnr, Ssim, FlipLdr, FlipHdr };
/// Parses "mse", "relmse", "psnr", "ssim", "flip-ldr", "flip-hdr"; throws
/// glint::Error(InvalidArgument).
Metric parseMetric(const std::string& name);
const char* metricName(Metric metric);

/// Mean squared error over pixels and channels (linear values).
MetricResult mse(const Image& image, const Image& reference, const MetricOptions& options = {});
/// pbrt-style relative MSE: mean of (x - r)^2 / (r^2 + 1e-2).
MetricResult relMse(const Image& image, const Image& reference, const MetricOptions& options = {});
/// PSNR in dB for data range 1 (linear values): 10 log10(1 / MSE); +infinity when MSE is 0.
MetricResult psnr(const Image& image, const Image& reference, const MetricOptions& options = {});
/// SSIM of Wang et al. 2004 as docs/metrics.md specifies (equal to scikit-image's with
/// gaussian_weights=True, sigma=1.5, use_sample_covariance=False, data_range=1).
MetricResult ssim(const Image& image, const Image& reference, const MetricOptions& options = {});
/// Dispatch by metric kind. FLIP (glint/image/flip.h) runs at its default viewing condition;
/// it throws on NaN/Inf rather than counting them.
MetricResult computeMetric(Metric metric, const Image& image, const Image& reference,
                           const MetricOptions& options = {});

/// Per-pixel maps (1 channel, mean over channels), of the crop if one is given.
Image absErrorMap(const Image& image, const Image& reference, const MetricOptions& options = {});
Image relErrorMap(const Image& image, const Image& reference, const MetricOptions& options = {});
Image ssimMap(const Image& image, const Image& reference, const MetricOptions& options = {});

}  // namespace glint
