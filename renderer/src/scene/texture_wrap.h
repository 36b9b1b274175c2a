// Wrapping texture coordinates and texel indices by a glTF sampler's wrap mode, shared by the
// lookups of images in memory and of a file texture's resident MIP levels.
#pragma once

#include <algorithm>
#include <cmath>

#include "scene/texture_store.h"

namespace glint::render::detail {

/// A texel index along an axis of n texels under `wrap` (i may be any integer).
inline int wrapIndex(long i, int n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return int(std::clamp<long>(i, 0, n - 1));
        case TextureWrap::Mirror: {
            const long period = 2L * n;
            const long k = ((i % period) + period) % period;
            return int(k < n ? k : period - 1 - k);
        }
        case TextureWrap::Repeat:
            break;
    }
    return int(((i % n) + n) % n);
}

/// The coordinate in [0, 1) (repeat, mirror: one period of two) or [-1, 2] (clamp) that wrapping
/// maps t to; non-finite coordinates become 0. Wrapping the coordinate before it becomes a
/// texel index keeps huge or non-finite uvs from a mesh out of the float → integer conversion
/// (which would be undefined behaviour).
inline float wrapCoordinate(float t, TextureWrap wrap) {
    if (!std::isfinite(t)) return 0.0f;
    switch (wrap) {
        case TextureWrap::Clamp:
            return std::clamp(t, -1.0f, 2.0f);
        case TextureWrap::Mirror:
            return t - 2.0f * std::floor(0.5f * t);
        case TextureWrap::Repeat:
            break;
    }
    return t - std::floor(t);
}

}  // namespace glint::render::detail
