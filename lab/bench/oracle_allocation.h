// What the oracle benches share (bench_adaptive_oracle, bench_adaptive_denoised;
// docs/lab/adaptive-dof.md, adaptive-dof-denoiser.md): each pixel's term of relMSE, a box blur
// of such terms, the samples per pixel an allocation gives, and the render that gives them.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <vector>

#include "glint/image/image.h"
#include "glint/render/renderer.h"

namespace glint::bench {

using Errors = std::vector<double>;

/// Per pixel, relMSE's term (glint::relMse: (x − r)² / (r² + 0.01), mean over channels).
inline Errors relativeErrors(const Image& image, const Image& reference) {
    Errors e(std::size_t(image.pixelCount()), 0.0);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x) {
            double sum = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double d = double(image(x, y, c)) - reference(x, y, c);
                sum += d * d / (double(reference(x, y, c)) * reference(x, y, c) + 0.01);
            }
            e[std::size_t(y) * image.width() + x] = sum / 3.0;
        }
    return e;
}

inline double mean(const Errors& v) {
    return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

/// The mean of `e` (w × h, row by row) over the (2r + 1)² window, cut at the border, in double.
inline Errors boxBlur(const Errors& e, int w, int h, int r) {
    Errors out(e.size(), 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum = 0.0;
            int n = 0;
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    const int sx = x + dx, sy = y + dy;
                    if (sx < 0 || sy < 0 || sx >= w || sy >= h) continue;
                    sum += e[std::size_t(sy) * w + sx];
                    ++n;
                }
            out[std::size_t(y) * w + x] = sum / n;
        }
    return out;
}

/// Samples per pixel ∝ `weight`: at least `least`, at most 16 × `spp`, mean `spp` (a few
/// fixed-point steps), in whole passes of 16 past `least`.
inline std::vector<int> targetsFrom(const Errors& weight, int spp, int least) {
    std::vector<int> target(weight.size(), spp);
    double scale = double(spp) / std::max(mean(weight), 1e-30);
    for (int step = 0; step < 20; ++step) {
        double sum = 0.0;
        for (std::size_t i = 0; i < weight.size(); ++i) {
            const double n = std::clamp(scale * weight[i], double(least), 16.0 * spp);
            target[i] = least + 16 * int(std::lround((n - least) / 16.0));
            sum += target[i];
        }
        scale *= double(spp) * double(weight.size()) / sum;
    }
    return target;
}

/// `settings` (its seed, threads, layers) rendered with adaptive passes that open exactly the
/// pixels below their `target` after a uniform start of `least`: before each pass weight 1 for
/// those, 0 for the others; the render ends when none is left.
inline render::RenderResult renderTargets(render::Renderer& renderer, render::Settings settings,
                                          const std::vector<int>& target, int least) {
    const int w = renderer.scene().width(), h = renderer.scene().height();
    settings.spp = *std::max_element(target.begin(), target.end());
    settings.adaptive = true;
    settings.minSpp = least;
    settings.noiseThreshold = 1e-9;
    bool done = false;
    render::Callbacks callbacks;
    callbacks.importance = [&](int, const FrameBuffers& frame) {
        const Image& n = frame.layer(Layer::SampleCount);
        auto map = std::make_shared<Image>(w, h, 1);
        bool any = false;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const bool open = n(x, y, 0) < float(target[std::size_t(y) * w + x]);
                (*map)(x, y, 0) = open ? 1.0f : 0.0f;
                any |= open;
            }
        done = !any;
        return any ? std::shared_ptr<const Image>(map) : nullptr;
    };
    callbacks.cancel = [&] { return done; };
    return renderer.render(settings, callbacks);
}

}  // namespace glint::bench
