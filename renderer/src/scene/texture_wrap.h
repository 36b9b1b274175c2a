// Wrapping texture coordinates and texel indices by a glTF sampler's wrap mode, shared by the
// lookups of images in memory and of a file texture's resident MIP levels.
#pragma once

#include <algorithm>
#include <cmath>

#include "scene/texture_store.h"

namespace glint::render::detail {

/// std::floor(t) for a finite t, without SSE4.1's roundss: the build targets plain x86-64, where
/// std::floor is a long sequence, and texture filtering takes several per lookup. (Only -0 differs:
/// it gives +0.) Floats of magnitude 2^23 and more are whole already.
inline float floorFast(float t) {
    if (!(std::fabs(t) < 0x1p23f)) return t;
    const float i = float(int(t));  // truncated towards zero
    return i > t ? i - 1.0f : i;
}

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
            return t - 2.0f * floorFast(0.5f * t);
        case TextureWrap::Repeat:
            break;
    }
    return t - floorFast(t);
}

}  // namespace glint::render::detail
