// Images for the navigation tests (tests/denoise/navigation_test.cpp, the simulated user's in
// tests/lab/oracle_test.cpp): results of distinct levels, and pointers to them as the tree takes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "glint/image/image.h"
#include "glint/image/random.h"

namespace glint::testing {

// n images of 24×20 whose colour is a distinct level plus a pattern, so that their distances
// are spread out and unambiguous.
inline std::vector<Image> syntheticResults(int n, std::uint64_t seed = 3) {
    std::vector<Image> images;
    SplitMix64 rng(seed);
    for (int i = 0; i < n; ++i) {
        Image im(24, 20, 3);
        const float level = 0.05f + 0.9f * float(i) / float(std::max(n - 1, 1));
        const float tilt = float(rng.uniformDouble()) * 0.1f;
        for (int y = 0; y < 20; ++y)
            for (int x = 0; x < 24; ++x)
                for (int c = 0; c < 3; ++c)
                    im(x, y, c) =
                        level * (1.0f + tilt * float(x - 12) / 12.0f) * (c == 0 ? 1.0f : 0.8f);
        images.push_back(std::move(im));
    }
    return images;
}

inline std::vector<const Image*> pointers(const std::vector<Image>& images) {
    std::vector<const Image*> out;
    for (const Image& im : images) out.push_back(&im);
    return out;
}

}  // namespace glint::testing
