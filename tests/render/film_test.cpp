// The film's statistics against a scalar Welford update written out here: Film::add updates two
// channels at a time (SSE2 lanes) and Film::resolve finds its layers once, so every channel of
// every layer, half B's included, must still hold the scalar update's bits.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "film/film.h"

namespace glint::render {
namespace {

/// One pixel's running statistics, updated one channel at a time (Welford 1962) as the film
/// did before its update ran on pairs of channels.
struct ScalarPixel {
    static constexpr int kChannels = 13;
    std::uint32_t n = 0;
    double mean[kChannels] = {}, m2[kChannels] = {};

    void add(const float (&v)[kChannels]) {
        ++n;
        const double inv = 1.0 / double(n);
        for (int c = 0; c < kChannels; ++c) {
            const double delta = double(v[c]) - mean[c];
            mean[c] += delta * inv;
            m2[c] += delta * (double(v[c]) - mean[c]);
        }
    }
    /// The variance of the mean of channel c as the film writes it.
    float variance(int c) const {
        const double scale = n > 1 ? 1.0 / (double(n - 1) * double(n)) : 0.0;
        return float(m2[c] * scale);
    }
};

/// The 13 film channels of a sample, in the film's order: colour, albedo, normal, depth,
/// position.
void channels(const FilmSample& s, float (&v)[ScalarPixel::kChannels]) {
    const float values[ScalarPixel::kChannels] = {
        s.color.x,  s.color.y,  s.color.z, s.albedo.x,   s.albedo.y,   s.albedo.z,  s.normal.x,
        s.normal.y, s.normal.z, s.depth,   s.position.x, s.position.y, s.position.z};
    for (int c = 0; c < ScalarPixel::kChannels; ++c) v[c] = values[c];
}

TEST(Film, EveryChannelHoldsTheScalarWelfordUpdatesBits) {
    // Three pixels, samples of every channel different and of magnitudes from 1e-6 to 1e6
    // (fixed seed), every second one also in half B: each layer must equal the scalar update
    // exactly (a swapped lane, a channel updated twice or a wrong layer would not).
    constexpr int kWidth = 3, kSamples = 257;
    Film film(kWidth, 1, /*halfBuffers=*/true);
    ScalarPixel whole[kWidth], half[kWidth];
    std::mt19937 rng(45);
    std::uniform_real_distribution<float> exponent(-6.0f, 6.0f), sign(-1.0f, 1.0f);
    auto value = [&] { return std::copysign(std::pow(10.0f, exponent(rng)), sign(rng)); };
    for (int i = 0; i < kSamples; ++i)
        for (int x = 0; x < kWidth; ++x) {
            FilmSample s;
            s.color = {value(), value(), value()};
            s.albedo = {value(), value(), value()};
            s.normal = {value(), value(), value()};
            s.depth = value();
            s.position = {value(), value(), value()};
            const bool odd = i % 2 == 1;
            film.add(x, 0, s, odd);
            float v[ScalarPixel::kChannels];
            channels(s, v);
            whole[x].add(v);
            if (odd) half[x].add(v);
        }
    const FrameBuffers frame = film.resolve(/*withPosition=*/true);
    struct Out {
        Layer mean, variance;
        int first, count;
    };
    const Out outs[] = {{Layer::Color, Layer::Variance, 0, 3},
                        {Layer::Albedo, Layer::AlbedoVariance, 3, 3},
                        {Layer::Normal, Layer::NormalVariance, 6, 3},
                        {Layer::Depth, Layer::DepthVariance, 9, 1}};
    for (int x = 0; x < kWidth; ++x) {
        EXPECT_EQ(frame.layer(Layer::SampleCount)(x, 0, 0), float(kSamples));
        EXPECT_EQ(frame.layer(Layer::HalfSampleCount)(x, 0, 0), float(kSamples / 2));
        for (const Out& o : outs)
            for (int c = 0; c < o.count; ++c) {
                const int k = o.first + c;
                EXPECT_EQ(frame.layer(o.mean)(x, 0, c), float(whole[x].mean[k])) << k;
                EXPECT_EQ(frame.layer(o.variance)(x, 0, c), whole[x].variance(k)) << k;
                EXPECT_EQ(frame.layer(*halfLayer(o.mean))(x, 0, c), float(half[x].mean[k])) << k;
                EXPECT_EQ(frame.layer(*halfLayer(o.variance))(x, 0, c), half[x].variance(k)) << k;
            }
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(frame.layer(Layer::Position)(x, 0, c), float(whole[x].mean[10 + c]));
    }
}

}  // namespace
}  // namespace glint::render
