#include "film/film.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>

namespace glint::render {

Film::Film(int width, int height, bool halfBuffers, bool keepHalf)
    : m_width(width),
      m_height(height),
      m_pixels(std::size_t(width) * std::size_t(height)),
      m_writeHalves(halfBuffers) {
    if (halfBuffers || keepHalf) m_half.resize(m_pixels.size());
}

double Film::adaptiveError(int x, int y, AdaptiveError from) const {
    const Pixel& whole = m_pixels[index(x, y)];
    const Pixel& p = from == AdaptiveError::Half ? m_half[index(x, y)] : whole;
    if (p.n < 2) return std::numeric_limits<double>::infinity();
    // Standard error of the mean per channel, s / sqrt(n); half B's scaled to the whole's
    // count: s_B / sqrt(n_B) * sqrt(n_B / n) = s_B / sqrt(n).
    const double n = double(p.n);
    const double perSample = 1.0 / ((n - 1.0) * double(whole.n));
    double se = 0.0, intensity = 0.0;
    for (int c = 0; c < 3; ++c) {
        se += std::sqrt(std::max(p.m2[c] * perSample, 0.0));
        intensity += p.mean[c];
    }
    // Cycles' |I - A| (the whole mean against the even half's) has the standard error of the
    // whole mean; its expectation is sqrt(2/pi) of it for Gaussian noise (Dammertz et al. 2010,
    // sec. 2.1, with Cycles' sqrt(intensity) normalisation).
    constexpr double kMeanAbs = 0.7978845608028654;
    return kMeanAbs * se / (1e-4 + std::sqrt(std::max(intensity, 0.0)));
}

namespace {
/// Two doubles in one SSE2 register (GCC's and Clang's vector extension), loaded from and
/// stored to 8-byte-aligned memory.
typedef double Double2 __attribute__((vector_size(16), aligned(8)));

// Welford's online update of mean and sum of squared deviations (Welford 1962), two channels
// at a time (an odd last one alone): each lane does the scalar update's operations in its
// order, so the bits are the scalar loop's, for about half its instructions (the film takes
// every sample).
template <class Pixel, int N>
void welford(Pixel& p, const float (&v)[N]) {
    ++p.n;
    const double inv = 1.0 / double(p.n);
    int c = 0;
    for (; c + 1 < N; c += 2) {
        const Double2 x = {double(v[c]), double(v[c + 1])};
        Double2 mean, m2;
        std::memcpy(&mean, &p.mean[c], sizeof mean);
        std::memcpy(&m2, &p.m2[c], sizeof m2);
        const Double2 delta = x - mean;
        mean += delta * inv;
        m2 += delta * (x - mean);
        std::memcpy(&p.mean[c], &mean, sizeof mean);
        std::memcpy(&p.m2[c], &m2, sizeof m2);
    }
    for (; c < N; ++c) {
        const double delta = double(v[c]) - p.mean[c];
        p.mean[c] += delta * inv;
        p.m2[c] += delta * (double(v[c]) - p.mean[c]);
    }
}
}  // namespace

void Film::add(int x, int y, const FilmSample& s, bool secondHalf) {
    const float v[kChannels] = {s.color.x,    s.color.y,    s.color.z,   s.albedo.x, s.albedo.y,
                                s.albedo.z,   s.normal.x,   s.normal.y,  s.normal.z, s.depth,
                                s.position.x, s.position.y, s.position.z};
    Pixel& p = m_pixels[index(x, y)];
    for (float value : v)
        if (!std::isfinite(value)) {
            ++p.nonFinite;
            return;
        }
    welford(p, v);
    if (secondHalf && !m_half.empty()) welford(m_half[index(x, y)], v);
}

void Film::continueFrom(const FrameBuffers& frame) {
    // The inverse of resolve(): m2 = variance of the mean × n × (n − 1).
    static constexpr Layer kMeans[4] = {Layer::Color, Layer::Albedo, Layer::Normal, Layer::Depth};
    static constexpr Layer kVariances[4] = {Layer::Variance, Layer::AlbedoVariance,
                                            Layer::NormalVariance, Layer::DepthVariance};
    static constexpr int kFirst[4] = {0, 3, 6, 9};
    auto take = [&](Pixels& pixels, bool half) {
        auto layer = [&](Layer l) -> const Image& { return frame.layer(half ? *halfLayer(l) : l); };
        const Image& count = layer(Layer::SampleCount);
        const Image* position =
            !half && frame.has(Layer::Position) ? &frame.layer(Layer::Position) : nullptr;
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x) {
                Pixel& p = pixels[index(x, y)];
                p = Pixel{};
                p.n = std::uint32_t(count(x, y, 0));
                const double scale = double(p.n) * (double(p.n) - 1.0);
                for (int i = 0; i < 4; ++i) {
                    const Image& mean = layer(kMeans[i]);
                    const Image& variance = layer(kVariances[i]);
                    for (int c = 0; c < mean.channels(); ++c) {
                        p.mean[kFirst[i] + c] = double(mean(x, y, c));
                        p.m2[kFirst[i] + c] = p.n > 1 ? double(variance(x, y, c)) * scale : 0.0;
                    }
                }
                if (position)
                    for (int c = 0; c < 3; ++c) p.mean[10 + c] = double((*position)(x, y, c));
            }
    };
    take(m_pixels, false);
    if (!m_half.empty()) take(m_half, true);
}

std::int64_t Film::nonFiniteSamples() const {
    std::int64_t total = 0;
    for (const Pixel& p : m_pixels) total += p.nonFinite;
    return total;
}

FrameBuffers Film::resolve(bool withPosition) const {
    FrameBuffers frame(m_width, m_height);
    struct Out {
        Layer mean, variance;
        int first, channels;
    };
    constexpr int kOuts = 4;
    static constexpr Out outs[kOuts] = {{Layer::Color, Layer::Variance, 0, 3},
                                        {Layer::Albedo, Layer::AlbedoVariance, 3, 3},
                                        {Layer::Normal, Layer::NormalVariance, 6, 3},
                                        {Layer::Depth, Layer::DepthVariance, 9, 1}};
    // The whole, then half B into the half-buffer layers.
    const bool halves = m_writeHalves;
    for (const Out& o : outs) {
        frame.ensure(o.mean), frame.ensure(o.variance);
        if (halves) frame.ensure(*halfLayer(o.mean)), frame.ensure(*halfLayer(o.variance));
    }
    if (withPosition) frame.ensure(Layer::Position);
    frame.ensure(Layer::SampleCount);
    if (halves) frame.ensure(Layer::HalfSampleCount);
    // The layers one set of statistics (the whole, or half B) is written to, found once rather
    // than at every pixel.
    struct Target {
        Image* mean[kOuts];
        Image* variance[kOuts];
        Image* count;
    };
    auto targetOf = [&](bool half) {
        auto to = [&](Layer l) { return &frame.layer(half ? *halfLayer(l) : l); };
        Target t{};
        for (int i = 0; i < kOuts; ++i) {
            t.mean[i] = to(outs[i].mean);
            t.variance[i] = to(outs[i].variance);
        }
        t.count = to(Layer::SampleCount);
        return t;
    };
    const Target whole = targetOf(false);
    const Target halfB = halves ? targetOf(true) : Target{};
    Image* position = withPosition ? &frame.layer(Layer::Position) : nullptr;
    // Pixels whose variance of the mean, held in double here, is below float's normal range
    // (1.2e-38) in some channel: the float layer holds it as 0 or a denormal (radiance about
    // 1e-19 or less).
    std::int64_t underflow = 0;
    // Writes pixel (x, y) of `t`; true when some channel's variance underflows.
    auto write = [&](const Pixel& p, int x, int y, const Target& t) {
        bool under = false;
        (*t.count)(x, y, 0) = float(p.n);
        // Variance of the mean: unbiased sample variance / n.
        const double varScale = p.n > 1 ? 1.0 / (double(p.n - 1) * double(p.n)) : 0.0;
        for (int i = 0; i < kOuts; ++i) {
            const Out& o = outs[i];
            Image& mean = *t.mean[i];
            Image& var = *t.variance[i];
            for (int c = 0; c < o.channels; ++c) {
                mean(x, y, c) = float(p.mean[o.first + c]);
                const double v = p.m2[o.first + c] * varScale;
                var(x, y, c) = float(v);
                // Without a branch per channel: a test at every channel of every pixel.
                under |= (v > 0.0) & (v < double(FLT_MIN));
            }
        }
        return under;
    };
    for (int y = 0; y < m_height; ++y)
        for (int x = 0; x < m_width; ++x) {
            const Pixel& p = m_pixels[index(x, y)];
            if (write(p, x, y, whole)) ++underflow;
            if (halves) write(m_half[index(x, y)], x, y, halfB);
            if (position)
                for (int c = 0; c < 3; ++c) (*position)(x, y, c) = float(p.mean[10 + c]);
        }
    if (underflow > 0) frame.metadata().extra[kVarianceUnderflowKey] = std::to_string(underflow);
    return frame;
}

}  // namespace glint::render
