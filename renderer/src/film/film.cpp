#include "film/film.h"

#include <cfloat>
#include <cmath>

namespace glint::render {

Film::Film(int width, int height, bool halfBuffers)
    : m_width(width), m_height(height), m_pixels(std::size_t(width) * std::size_t(height)) {
    if (halfBuffers) m_half.resize(m_pixels.size());
}

namespace {
// Welford's online update of mean and sum of squared deviations.
template <class Pixel, int N>
void welford(Pixel& p, const float (&v)[N]) {
    ++p.n;
    const double inv = 1.0 / double(p.n);
    for (int c = 0; c < N; ++c) {
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
    const std::vector<Out> outs = {{Layer::Color, Layer::Variance, 0, 3},
                                   {Layer::Albedo, Layer::AlbedoVariance, 3, 3},
                                   {Layer::Normal, Layer::NormalVariance, 6, 3},
                                   {Layer::Depth, Layer::DepthVariance, 9, 1}};
    // The whole, then half B into the half-buffer layers.
    const bool halves = !m_half.empty();
    for (const Out& o : outs) {
        frame.ensure(o.mean), frame.ensure(o.variance);
        if (halves) frame.ensure(*halfLayer(o.mean)), frame.ensure(*halfLayer(o.variance));
    }
    if (withPosition) frame.ensure(Layer::Position);
    frame.ensure(Layer::SampleCount);
    if (halves) frame.ensure(Layer::HalfSampleCount);
    // Pixels whose variance of the mean, held in double here, is below float's normal range
    // (1.2e-38) in some channel: the float layer holds it as 0 or a denormal (radiance about
    // 1e-19 or less).
    std::int64_t underflow = 0;
    auto write = [&](const Pixel& p, int x, int y, bool half) {
        bool under = false;
        auto to = [&](Layer l) -> Image& { return frame.layer(half ? *halfLayer(l) : l); };
        to(Layer::SampleCount)(x, y, 0) = float(p.n);
        // Variance of the mean: unbiased sample variance / n.
        const double varScale = p.n > 1 ? 1.0 / (double(p.n - 1) * double(p.n)) : 0.0;
        for (const Out& o : outs) {
            Image& mean = to(o.mean);
            Image& var = to(o.variance);
            for (int c = 0; c < o.channels; ++c) {
                mean(x, y, c) = float(p.mean[o.first + c]);
                const double v = p.m2[o.first + c] * varScale;
                var(x, y, c) = float(v);
                under = under || (v > 0.0 && v < double(FLT_MIN));
            }
        }
        if (under && !half) ++underflow;
    };
    for (int y = 0; y < m_height; ++y)
        for (int x = 0; x < m_width; ++x) {
            const Pixel& p = m_pixels[index(x, y)];
            write(p, x, y, false);
            if (halves) write(m_half[index(x, y)], x, y, true);
            if (withPosition) {
                Image& pos = frame.layer(Layer::Position);
                for (int c = 0; c < 3; ++c) pos(x, y, c) = float(p.mean[10 + c]);
            }
        }
    if (underflow > 0) frame.metadata().extra[kVarianceUnderflowKey] = std::to_string(underflow);
    return frame;
}

}  // namespace glint::render
