// Synthetic frames with half buffers and small banks for the tests of the automatic selection
// by the halves (halves_*_test.cpp): a clean image known exactly, two independent halves of one
// "sample" each with Gaussian, skewed or firefly noise.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise::halves_test {

// Smooth shading with a sharp disc and, for x >= w/2, a fine checkerboard (where only a tiny
// blur is right).
inline Image cleanImage(int w, int h) {
    Image x(w, h, 3);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double dx = i - 0.3 * w, dy = j - 0.5 * h;
            double v = 0.3 + 0.2 * std::sin(6.0 * i / w) * std::cos(4.0 * j / h) +
                       (dx * dx + dy * dy < 0.04 * w * w ? 0.3 : 0.0);
            if (i >= w / 2) v += ((i / 2 + j / 2) % 2 ? 0.25 : -0.25);
            for (int c = 0; c < 3; ++c) x(i, j, c) = float(v * (1.0 - 0.2 * c));
        }
    return x;
}

// The noise of one half: Gaussian, or skewed like radiance (an exponential with the same
// standard deviation, shifted to mean 0: rare large positive values), or Gaussian with
// fireflies (one value in 100 is 30 sigma higher; shifted to mean 0).
enum class Noise { Gaussian, Skewed, Fireflies };

// A frame with half buffers made of two independent halves of one "sample" each:
// A = x + n_A, B = x + n_B, colour (A + B)/2, halfColor B, sampleCount 2, halfSampleCount 1, and
// the variance layers those samples give. `halfA`/`halfB` receive the halves' colours.
inline FrameBuffers halvesFrame(const Image& clean, double sigma, Noise noise, std::uint32_t seed,
                                Image* halfA = nullptr, Image* halfB = nullptr) {
    const int w = clean.width(), h = clean.height();
    std::mt19937 rng(seed);
    std::normal_distribution<double> gauss(0.0, sigma);
    std::exponential_distribution<double> expo(1.0 / sigma);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    auto draw = [&] {
        switch (noise) {
            case Noise::Gaussian:
                return gauss(rng);
            case Noise::Skewed:
                return expo(rng) - sigma;
            case Noise::Fireflies:
                return gauss(rng) + (uniform(rng) < 0.01 ? 30.0 * sigma : 0.0) - 0.3 * sigma;
        }
        return 0.0;
    };
    FrameBuffers f(w, h);
    Image a(w, h, 3), b(w, h, 3);
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        a.data()[i] = float(clean.data()[i] + draw());
        b.data()[i] = float(clean.data()[i] + draw());
    }
    Image& color = f.color();
    Image& variance = f.ensure(Layer::Variance);
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        color.data()[i] = float(0.5 * (double(a.data()[i]) + b.data()[i]));
        const double d = double(a.data()[i]) - b.data()[i];
        variance.data()[i] = float(0.25 * d * d);  // sample variance / n with n = 2
    }
    f.set(Layer::HalfColor, b);
    f.ensure(Layer::HalfVariance);  // one sample: 0
    for (float& v : f.ensure(Layer::SampleCount).data()) v = 2.0f;
    for (float& v : f.ensure(Layer::HalfSampleCount).data()) v = 1.0f;
    if (halfA) *halfA = a;
    if (halfB) *halfB = b;
    return f;
}

inline FilterBank gaussianBank(const FrameBuffers& f, const std::vector<double>& sigmas) {
    std::vector<BankMember> members;
    std::vector<Image> results;
    for (double s : sigmas) {
        members.push_back(
            {"gaussian", resolveParams(findFilter("gaussian"), {{"sigma", s}}), false});
        results.push_back(applyFilter(findFilter("gaussian"), f, members.back().params));
    }
    return FilterBank(std::move(members), std::move(results), Rect{0, f.width(), 0, f.height()},
                      f.width(), f.height(), hashFrame(f));
}

// The weight plane of `member` in an auto result (zero where the member has no layer).
inline Image planeOf(const AutoResult& r, int member) {
    for (const AutoLayer& l : r.layers)
        if (l.member == member) return l.weights;
    return Image(r.choice.width(), r.choice.height(), 1);
}

// The exact display curve (clamp to [0, 1], sRGB) at x.
inline double srgbOf(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

}  // namespace glint::denoise::halves_test
