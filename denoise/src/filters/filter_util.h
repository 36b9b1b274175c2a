// Shared private helpers for the filters in src/filters/ and src/prefilter/: reading resolved
// parameters, region maths and the planar copy with the non-finite policy. SIMD helpers are in
// simd.h; parallel loops go through the WorkContext each filter receives.
//
//   paramValue / paramInt      read a resolved parameter (throws Internal if absent).
//   expandRect                 roi grown by a margin, clipped to the image.
//   isFinitePixel              the non-finite policy test (see below).
//   PlanarPlanes               planar float copy of an interleaved image over a rectangle that may
//                              reach outside the image, with a 0/1 validity plane and padding
//                              columns so 8-wide SIMD loads never leave the buffer.
//
// Non-finite policy shared by all filters (tested by tests/denoise/filter_properties_test.cpp):
// an input pixel with a NaN or Inf in any colour channel is *missing*: it gets zero weight as a
// neighbour, so it cannot influence any output pixel, and its own output is the normalised
// average of the finite neighbours its kernel reaches (range terms that need the centre's value
// are dropped for it). When a kernel reaches no finite pixel at all, the output is 0. Hence the
// output is finite everywhere and equals the clean-input output beyond the filter's margin.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "filters/simd.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"
#include "glint/image/image.h"

namespace glint::denoise::detail {
/// The resolved value of parameter `name` (resolveParams guarantees presence).
inline double paramValue(const ParamValues& params, const std::string& name) {
    auto it = params.find(name);
    GLINT_CHECK(it != params.end(), "parameter not resolved");
    return it->second;
}

/// The resolved value of integer parameter `name`.
inline int paramInt(const ParamValues& params, const std::string& name) {
    return int(std::lround(paramValue(params, name)));
}

/// `roi` grown by `margin` on every side and clipped to `bounds`.
inline Rect expandRect(const Rect& roi, int margin, const Rect& bounds) {
    return intersect(Rect{roi.x0 - margin, roi.x1 + margin, roi.y0 - margin, roi.y1 + margin},
                     bounds);
}

/// True when the `channels` values at `p` are all finite (the non-finite policy above).
inline bool isFinitePixel(const float* p, int channels) {
    for (int c = 0; c < channels; ++c)
        if (!std::isfinite(p[c])) return false;
    return true;
}

/// Planar copy of the first `channels` channels of an image over `rect` (which may extend past
/// the image). Pixels outside the image or non-finite read as value 0 with valid 0.
struct PlanarPlanes {
    static constexpr int kPad = 8;  ///< extra missing columns on the right for SIMD tails
    Rect rect;                      ///< covered region, image coordinates
    int stride = 0;                 ///< floats per plane row (rect.width() + kPad)
    int channels = 0;
    std::vector<std::vector<float>> planes;  ///< channel planes
    std::vector<float> valid;                ///< 1 for a finite pixel inside the image, else 0

    /// Index of image pixel (x, y) in the planes; (x, y) must lie in rect.
    std::size_t index(int x, int y) const {
        return std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0);
    }
};

/// Builds the planar copy of `image` (first `channels` channels) over `rect`; parallel over rows.
inline PlanarPlanes makePlanar(const Image& image, const Rect& rect, int channels,
                               WorkContext& work) {
    PlanarPlanes p;
    p.rect = rect;
    p.stride = rect.width() + PlanarPlanes::kPad;
    p.channels = channels;
    const std::size_t size = std::size_t(p.stride) * std::size_t(std::max(0, rect.height()));
    p.planes.assign(std::size_t(channels), std::vector<float>(size, 0.0f));
    p.valid.assign(size, 0.0f);
    const int x0 = std::max(rect.x0, 0), x1 = std::min(rect.x1, image.width());
    const int y0 = std::max(rect.y0, 0), y1 = std::min(rect.y1, image.height());
    const int ic = image.channels();
    work.parallelFor(
        y0, y1,
        [&](int y) {
            const float* src = image.row(y);
            for (int x = x0; x < x1; ++x) {
                const float* px = src + std::size_t(x) * ic;
                if (!isFinitePixel(px, channels)) continue;
                const std::size_t i = p.index(x, y);
                for (int c = 0; c < channels; ++c) p.planes[std::size_t(c)][i] = px[c];
                p.valid[i] = 1.0f;
            }
        },
        0);  // copying counts as no work: the kernel's rows do
    return p;
}

}  // namespace glint::denoise::detail
