// Synthetic FrameBuffers for the denoise tests (owner: denoise A; any denoise test may use it):
// a piecewise-smooth noisy colour with every feature layer and its variance.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "auto/choice.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/frame_buffers.h"

namespace glint::denoise::testing {

/// The registered filters that run with their default parameters (Filter::unavailable empty:
/// every one but external, which needs a program the user allowed): the filters the tests of
/// every filter apply as they are.
inline std::vector<const Filter*> runnableFilters() {
    std::vector<const Filter*> out;
    for (const Filter* f : allFilters())
        if (f->unavailable(resolveParams(*f, {})).empty()) out.push_back(f);
    return out;
}

/// applyFilter options that filter only `region`.
inline FilterOptions inRegion(const Rect& region) {
    FilterOptions options;
    options.region = region;
    return options;
}

/// A frame of w x h: colour = two regions split by a diagonal edge with a gradient and Gaussian
/// noise of standard deviation `noise` (fixed seed), plus albedo, normal, depth and their
/// variance layers, and a sample count.
inline FrameBuffers syntheticFrame(int w, int h, float noise = 0.05f, std::uint32_t seed = 7) {
    FrameBuffers f(w, h);
    std::mt19937 rng(seed);
    std::normal_distribution<float> n01(0.0f, 1.0f);
    Image& c = f.color();
    Image& albedo = f.ensure(Layer::Albedo);
    Image& normal = f.ensure(Layer::Normal);
    Image& depth = f.ensure(Layer::Depth);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool right = x + y > (w + h) / 2;
            const float base = right ? 0.8f : 0.2f;
            const float grad = 0.1f * float(x) / float(std::max(w, 1));
            c(x, y, 0) = base + grad + noise * n01(rng);
            c(x, y, 1) = 0.5f * base + grad + noise * n01(rng);
            c(x, y, 2) = 0.3f + 0.5f * base + noise * n01(rng);
            albedo(x, y, 0) = right ? 0.7f : 0.3f;
            albedo(x, y, 1) = 0.5f;
            albedo(x, y, 2) = right ? 0.2f : 0.6f;
            normal(x, y, 0) = right ? 1.0f : 0.0f;
            normal(x, y, 1) = 0.0f;
            normal(x, y, 2) = right ? 0.0f : 1.0f;
            depth(x, y, 0) = right ? 3.0f : 5.0f + 0.01f * float(y);
        }
    f.ensure(Layer::Variance).fill(noise * noise);
    f.ensure(Layer::AlbedoVariance).fill(1e-4f);
    f.ensure(Layer::NormalVariance).fill(1e-4f);
    f.ensure(Layer::DepthVariance).fill(1e-4f);
    f.ensure(Layer::SampleCount).fill(16.0f);
    return f;
}

/// A frame whose every layer is constant (colour = (r, g, b)).
inline FrameBuffers constantFrame(int w, int h, float r, float g, float b) {
    FrameBuffers f = syntheticFrame(w, h, 0.0f);
    Image& c = f.color();
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            c(x, y, 0) = r;
            c(x, y, 1) = g;
            c(x, y, 2) = b;
        }
    f.layer(Layer::Albedo).fill(0.5f);
    f.layer(Layer::Normal).fill(0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) f.layer(Layer::Normal)(x, y, 2) = 1.0f;
    f.layer(Layer::Depth).fill(2.0f);
    return f;
}

/// Whether two images have the same shape and the same bits.
inline bool sameBits(const Image& a, const Image& b) {
    return a.sameShape(b) &&
           std::memcmp(a.data().data(), b.data().data(), a.data().size_bytes()) == 0;
}

/// Largest absolute difference between two same-shaped images (NaN if any value is NaN).
inline double maxAbsDiff(const Image& a, const Image& b) {
    double m = 0.0;
    auto da = a.data();
    auto db = b.data();
    for (std::size_t i = 0; i < da.size(); ++i) {
        const double d = std::fabs(double(da[i]) - double(db[i]));
        if (std::isnan(d)) return d;
        m = std::max(m, d);
    }
    return m;
}

/// Root mean squared difference.
inline double rmsDiff(const Image& a, const Image& b) {
    double s = 0.0;
    auto da = a.data();
    auto db = b.data();
    for (std::size_t i = 0; i < da.size(); ++i) {
        const double d = double(da[i]) - double(db[i]);
        s += d * d;
    }
    return std::sqrt(s / double(std::max<std::size_t>(da.size(), 1)));
}

/// Where one member of `bank` has a true error (against `clean`, box-smoothed over `window`)
/// below half the runner-up's, how often the per-pixel `choice` (an AutoResult::choice) picks
/// it: {pixels where the best is unambiguous, pixels where the choice agrees}.
inline std::pair<int, int> agreementWhereUnambiguous(const FilterBank& bank, const Image& clean,
                                                     const Image& choice, int window) {
    const int w = clean.width(), h = clean.height();
    std::vector<Image> truth;
    for (std::size_t m = 0; m < bank.size(); ++m) {
        Image e(w, h, 1);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double s = 0.0;
                for (int c = 0; c < 3; ++c) {
                    const double d = bank.result(m)(x, y, c) - clean(x, y, c);
                    s += d * d;
                }
                e(x, y, 0) = float(s);
            }
        truth.push_back(detail::boxSmooth(e, window));
    }
    int unambiguous = 0, agree = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::vector<float> e;
            for (const Image& t : truth) e.push_back(t(x, y, 0));
            const int best = int(std::min_element(e.begin(), e.end()) - e.begin());
            std::vector<float> sorted = e;
            std::sort(sorted.begin(), sorted.end());
            if (sorted.size() > 1 && sorted[0] * 2.0f > sorted[1]) continue;
            ++unambiguous;
            agree += int(choice(x, y, 0)) == best;
        }
    return {unambiguous, agree};
}

}  // namespace glint::denoise::testing
