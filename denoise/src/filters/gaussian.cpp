// gaussian — isotropic Gaussian blur of the colour.
//
// Weight of a neighbour at offset (dx, dy): exp(-(dx^2 + dy^2) / (2 sigma^2)), over a square
// window of radius ceil(3 sigma) (at most 4096), truncated at the image border and renormalised,
// so a constant image stays constant. Computed separably: a horizontal pass over the region of
// interest plus the vertical margin, then a vertical pass. Missing (NaN/Inf) pixels get zero
// weight; a pixel whose window holds no finite pixel becomes 0.
//
// Parameters:
//   sigma   spatial standard deviation in pixels, 1e-6 … 1e6 (log); sigma -> 0 is the identity.
#include "filters/gaussian.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "filters/factories.h"
#include "filters/filter_util.h"

namespace glint::denoise {

namespace {

using detail::VecF;

constexpr std::string_view kDescription =
    "gaussian: isotropic Gaussian blur, separable, window radius ceil(3 sigma); the kernel is "
    "renormalised at borders and over missing (NaN/Inf) pixels, so a constant image stays "
    "constant.";

// out[i] = sum_k w[k] * in[i + k * step] for i in [0, n); k ascending in every lane and in the
// scalar tail, so every element is computed the same way wherever it falls.
GLINT_SIMD_CLONES
void convolveStrided(const float* in, std::size_t step, const float* w, int taps, float* out,
                     int n) {
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        VecF acc{};
        for (int k = 0; k < taps; ++k) {
            VecF v;
            detail::loadVec(v, in + i + std::size_t(k) * step);
            acc += w[k] * v;
        }
        detail::storeVec(out + i, acc);
    }
    for (; i < n; ++i) {
        float acc = 0.0f;
        for (int k = 0; k < taps; ++k) acc += w[k] * in[i + std::size_t(k) * step];
        out[i] = acc;
    }
}

// Normalised 1D Gaussian weights for offsets -radius … radius.
std::vector<float> gaussianWeights(double sigma, int radius) {
    std::vector<double> w(std::size_t(2 * radius + 1));
    double sum = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        // Scaled distance first so that tiny sigma underflows to 0 instead of overflowing.
        const double t = double(k) / sigma;
        w[std::size_t(k + radius)] = std::exp(-0.5 * t * t);
        sum += w[std::size_t(k + radius)];
    }
    std::vector<float> out(w.size());
    for (std::size_t i = 0; i < w.size(); ++i) out[i] = float(w[i] / sum);
    return out;
}

}  // namespace

int gaussianRadius(double sigma) {
    const double r = std::ceil(3.0 * std::max(sigma, 0.0));
    return int(std::clamp(r, 1.0, double(kGaussianMaxRadius)));
}

namespace {

// True when the n floats at p are all finite: x - x is 0 for finite x and NaN otherwise.
GLINT_SIMD_CLONES
bool allFinite(const float* p, std::size_t n) {
    VecF acc{};
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        VecF v;
        detail::loadVec(v, p + i);
        acc += v - v;
    }
    float tail = 0.0f;
    for (; i < n; ++i) tail += p[i] - p[i];
    for (int l = 0; l < 8; ++l) tail += acc[l];
    return tail == 0.0f;
}

// Sum of the kernel weights that fall inside [0, extent) around position p, for every p in
// [first, first + count): the renormalisation of the kernel truncated at the border.
std::vector<float> truncatedSums(const std::vector<float>& w, int radius, int first, int count,
                                 int extent) {
    std::vector<float> sums(static_cast<std::size_t>(count));
    for (int i = 0; i < count; ++i) {
        const int p = first + i;
        const int k0 = std::max(0, radius - p), k1 = std::min(int(w.size()), extent - p + radius);
        // The whole kernel inside: exactly 1 (the weights are normalised), no rescaling.
        float s = 0.0f;
        for (int k = k0; k < k1; ++k) s += w[std::size_t(k)];
        sums[std::size_t(i)] = k0 == 0 && k1 == int(w.size()) ? 1.0f : s;
    }
    return sums;
}

// Divides the channels of pixel x of a row by sums[x] (a kernel truncated at the border).
void rescale(float* row, int x, const std::vector<float>& sums, int channels) {
    const float s = sums[std::size_t(x)];
    if (s == 1.0f) return;
    for (int c = 0; c < channels; ++c) row[std::size_t(x) * channels + c] /= s;
}

// Common case: no missing pixel within reach, so the normaliser of the 2D kernel truncated at the
// border is the product of the two 1D ones; plain separable convolution on the channels.
Image blurClean(const Image& image, const std::vector<float>& w, int radius, const Rect& roi,
                int hy0, int hy1, WorkContext& work) {
    const int channels = image.channels();
    const int taps = int(w.size());
    const int outW = roi.width();
    const std::size_t rowFloats = std::size_t(outW) * channels;
    const std::vector<float> colSums = truncatedSums(w, radius, roi.x0, outW, image.width());
    const std::vector<float> rowSums =
        truncatedSums(w, radius, roi.y0, roi.height(), image.height());
    // Horizontal pass over roi rows plus the vertical margin.
    std::unique_ptr<float[]> horizontal(new float[rowFloats * std::size_t(hy1 - hy0)]);
    work.parallelFor(hy0, hy1, [&](int y) {
        std::vector<float> padded(std::size_t(outW + 2 * radius) * channels, 0.0f);
        const int x0 = std::max(0, roi.x0 - radius), x1 = std::min(image.width(), roi.x1 + radius);
        std::copy_n(image.row(y) + std::size_t(x0) * channels, std::size_t(x1 - x0) * channels,
                    padded.data() + std::size_t(x0 - roi.x0 + radius) * channels);
        float* dst = horizontal.get() + std::size_t(y - hy0) * rowFloats;
        convolveStrided(padded.data(), std::size_t(channels), w.data(), taps, dst, int(rowFloats));
        for (int x = 0; x < std::min(outW, radius); ++x) rescale(dst, x, colSums, channels);
        for (int x = std::max(radius, outW - radius); x < outW; ++x)
            rescale(dst, x, colSums, channels);
    });
    // Vertical pass straight into the output rows.
    Image out(outW, roi.height(), channels);
    work.parallelFor(roi.y0, roi.y1, [&](int y) {
        const int k0 = std::max(0, hy0 - (y - radius));
        const int k1 = std::min(taps, hy1 - (y - radius));
        float* dst = out.row(y - roi.y0);
        convolveStrided(horizontal.get() + std::size_t(y - radius + k0 - hy0) * rowFloats,
                        rowFloats, w.data() + k0, k1 - k0, dst, int(rowFloats));
        const float s = rowSums[std::size_t(y - roi.y0)];
        if (s != 1.0f)
            for (std::size_t i = 0; i < rowFloats; ++i) dst[i] = dst[i] / s;
    });
    return out;
}

}  // namespace

Image gaussianBlur(const Image& image, double sigma, const Rect& roi, WorkContext& work) {
    GLINT_CHECK(sigma > 0.0 && std::isfinite(sigma));
    GLINT_CHECK(!roi.empty() && intersect(roi, image.bounds()) == roi);
    const int channels = image.channels();
    const int c1 = channels + 1;  // values premultiplied by validity, then the validity
    // A radius beyond the image size reads nothing more.
    const int radius = std::min(gaussianRadius(sigma), std::max(image.width(), image.height()));
    const std::vector<float> w = gaussianWeights(sigma, radius);
    const int taps = int(w.size());
    const int outW = roi.width();
    const std::size_t rowFloats = std::size_t(outW) * c1;
    const int hy0 = std::max(0, roi.y0 - radius), hy1 = std::min(image.height(), roi.y1 + radius);
    work.expectWork((hy1 - hy0) + roi.height());

    // Take the fast path unless a missing pixel lies within reach.
    {
        const int x0 = std::max(0, roi.x0 - radius), x1 = std::min(image.width(), roi.x1 + radius);
        std::atomic<bool> clean{true};
        work.parallelFor(
            hy0, hy1,
            [&](int y) {
                if (!allFinite(image.row(y) + std::size_t(x0) * channels,
                               std::size_t(x1 - x0) * channels))
                    clean = false;
            },
            0);
        if (clean) return blurClean(image, w, radius, roi, hy0, hy1, work);
    }

    // Masked path. Horizontal pass over the rows the vertical pass reads (roi plus margin).
    std::vector<float> horizontal(rowFloats * std::size_t(hy1 - hy0));
    work.parallelFor(hy0, hy1, [&](int y) {
        // Padded row: columns roi.x0 - radius … roi.x1 + radius - 1, zero outside the image and
        // for missing pixels.
        std::vector<float> padded(std::size_t(outW + 2 * radius) * c1, 0.0f);
        const float* src = image.row(y);
        const int x0 = std::max(0, roi.x0 - radius), x1 = std::min(image.width(), roi.x1 + radius);
        for (int x = x0; x < x1; ++x) {
            const float* px = src + std::size_t(x) * channels;
            if (!detail::isFinitePixel(px, channels)) continue;
            float* dst = padded.data() + std::size_t(x - roi.x0 + radius) * c1;
            std::copy_n(px, channels, dst);
            dst[channels] = 1.0f;
        }
        convolveStrided(padded.data(), std::size_t(c1), w.data(), taps,
                        horizontal.data() + std::size_t(y - hy0) * rowFloats, int(rowFloats));
    });

    // Vertical pass, then divide by the accumulated weight of the finite pixels reached.
    Image out(outW, roi.height(), channels);
    work.parallelFor(roi.y0, roi.y1, [&](int y) {
        const int k0 = std::max(0, hy0 - (y - radius));     // first tap inside the image
        const int k1 = std::min(taps, hy1 - (y - radius));  // one past the last
        std::vector<float> acc(rowFloats);
        convolveStrided(horizontal.data() + std::size_t(y - radius + k0 - hy0) * rowFloats,
                        rowFloats, w.data() + k0, k1 - k0, acc.data(), int(rowFloats));
        float* dst = out.row(y - roi.y0);
        for (int x = 0; x < outW; ++x) {
            const float* a = acc.data() + std::size_t(x) * c1;
            const float weight = a[channels];
            for (int c = 0; c < channels; ++c)
                dst[std::size_t(x) * channels + c] = weight > 0.0f ? a[c] / weight : 0.0f;
        }
    });
    return out;
}

GaussianFilter::GaussianFilter()
    : m_params{ParamSpec{"sigma", "sigma (px)", 1e-6, 1e6, 2.0, ParamScale::Log, false,
                         "Spatial standard deviation of the Gaussian in pixels."}
                   .soft(0.5, 8.0)} {}

std::string_view GaussianFilter::description() const {
    return kDescription;
}

int GaussianFilter::margin(const ParamValues& params) const {
    return gaussianRadius(detail::paramValue(params, "sigma"));
}

Image GaussianFilter::apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                            WorkContext& work) const {
    return gaussianBlur(frame.color(), detail::paramValue(params, "sigma"), roi, work);
}

std::optional<Image> GaussianFilter::divergence(const FrameBuffers& frame,
                                                const ParamValues& params, const Rect& roi) const {
    // The output is linear in the input: out(p) = Σ_q wx wy in(q) / (Σ wx · Σ wy) with the kernel
    // truncated at the border, so ∂out(p)/∂in(p) is the normalised centre weight, the same
    // weights and radius as gaussianBlur.
    const double sigma = detail::paramValue(params, "sigma");
    const int radius = std::min(gaussianRadius(sigma), std::max(frame.width(), frame.height()));
    const std::vector<float> w = gaussianWeights(sigma, radius);
    const std::vector<float> colSums = truncatedSums(w, radius, roi.x0, roi.width(), frame.width());
    const std::vector<float> rowSums =
        truncatedSums(w, radius, roi.y0, roi.height(), frame.height());
    const double centre = w[std::size_t(radius)];
    Image div(roi.width(), roi.height(), 3);
    for (int y = 0; y < roi.height(); ++y)
        for (int x = 0; x < roi.width(); ++x) {
            const float d =
                float(centre * centre /
                      (double(colSums[std::size_t(x)]) * double(rowSums[std::size_t(y)])));
            for (int c = 0; c < 3; ++c) div(x, y, c) = d;
        }
    return div;
}

std::unique_ptr<Filter> makeGaussianFilter() {
    return std::make_unique<GaussianFilter>();
}

}  // namespace glint::denoise
