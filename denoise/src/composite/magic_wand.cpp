// The multi-channel magic wand: a 4-connected flood fill from seed pixels that stops where the
// gradient of colour, albedo, normal or depth exceeds its threshold.
#include <algorithm>
#include <cmath>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// Luminance of an RGB pixel.
float luminance(const float* c) {
    return 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
}

// True when every channel differs by at most `limit` (and both are finite).
bool within(const float* a, const float* b, int channels, double limit) {
    for (int c = 0; c < channels; ++c) {
        if (!std::isfinite(a[c]) || !std::isfinite(b[c])) return false;
        if (std::fabs(double(a[c]) - double(b[c])) > limit) return false;
    }
    return true;
}

}  // namespace

Image magicWand(const FrameBuffers& frame, const Image& seeds, const WandOptions& options) {
    const int w = frame.width(), h = frame.height();
    if (seeds.width() != w || seeds.height() != h || seeds.channels() != 1)
        throw Error(ErrorKind::InvalidArgument,
                    "the seed mask must be " + std::to_string(w) + "x" + std::to_string(h) +
                        "x1, got " + std::to_string(seeds.width()) + "x" +
                        std::to_string(seeds.height()) + "x" + std::to_string(seeds.channels()),
                    {}, "magic wand");
    const Image& color = frame.color();
    const Image* albedo = options.albedo >= 0.0 ? frame.find(Layer::Albedo) : nullptr;
    const Image* normal = options.normal >= 0.0 ? frame.find(Layer::Normal) : nullptr;
    const Image* depth = options.depth >= 0.0 ? frame.find(Layer::Depth) : nullptr;

    // May the fill step from pixel a to its neighbour b?
    auto joins = [&](int ax, int ay, int bx, int by) {
        if (options.color >= 0.0) {
            const float* ca = color.row(ay) + std::size_t(ax) * 3;
            const float* cb = color.row(by) + std::size_t(bx) * 3;
            const double scale = std::max(luminance(ca), luminance(cb)) + 1e-3;
            if (!within(ca, cb, 3, options.color * scale)) return false;
        }
        if (albedo && !within(albedo->row(ay) + std::size_t(ax) * 3,
                              albedo->row(by) + std::size_t(bx) * 3, 3, options.albedo))
            return false;
        if (normal && !within(normal->row(ay) + std::size_t(ax) * 3,
                              normal->row(by) + std::size_t(bx) * 3, 3, options.normal))
            return false;
        if (depth) {
            const float da = (*depth)(ax, ay, 0), db = (*depth)(bx, by, 0);
            const double scale = std::max(std::fabs(double(da)), std::fabs(double(db)));
            if (!within(&da, &db, 1, options.depth * scale)) return false;
        }
        return true;
    };

    Image mask(w, h, 1, 0.0f);
    std::vector<int> queue;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (seeds(x, y, 0) > 0.0f) {
                mask(x, y, 0) = 1.0f;
                queue.push_back(y * w + x);
            }
    // Breadth-first from every seed; each pixel is visited once.
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const int x = queue[head] % w, y = queue[head] / w;
        const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
        for (int k = 0; k < 4; ++k) {
            if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
            if (mask(nx[k], ny[k], 0) > 0.0f || !joins(x, y, nx[k], ny[k])) continue;
            mask(nx[k], ny[k], 0) = 1.0f;
            queue.push_back(ny[k] * w + nx[k]);
        }
    }
    return mask;
}

}  // namespace glint::denoise
