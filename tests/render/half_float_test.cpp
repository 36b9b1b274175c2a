// halfToFloat and halfToFloat4 against Imath's half, on every one of the 65 536 halves.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>

#include <Imath/half.h>

#include "scene/half_float.h"

namespace glint::render {
namespace {

/// True when a and b are the same float bit for bit, or both NaN.
bool same(float a, float b) {
    if (std::isnan(a)) return std::isnan(b);
    return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(HalfFloat, EveryHalfConvertsAsImathConvertsIt) {
    int wrong = 0;
    for (std::uint32_t bits = 0; bits < 65536; ++bits) {
        Imath::half h;
        h.setBits(std::uint16_t(bits));
        const float expected = float(h);
        if (!same(detail::halfToFloat(std::uint16_t(bits)), expected) && ++wrong <= 5)
            ADD_FAILURE() << std::hex << bits << ": " << detail::halfToFloat(std::uint16_t(bits))
                          << " for " << expected;
    }
    EXPECT_EQ(wrong, 0);
}

#if defined(__SSE2__)
TEST(HalfFloat, FourAtOnceAsOneAtATime) {
    int wrong = 0;
    for (std::uint32_t bits = 0; bits < 65536; bits += 4) {
        // Each lane a different kind of value: the four halves bits, bits ^ 0x8000 (the other
        // sign), bits + 1, bits + 2.
        const std::uint16_t in[4] = {std::uint16_t(bits), std::uint16_t(bits ^ 0x8000u),
                                     std::uint16_t(bits + 1), std::uint16_t(bits + 2)};
        alignas(16) float out[4];
        _mm_store_ps(out, detail::halfToFloat4(in));
        for (int k = 0; k < 4; ++k)
            if (!same(out[k], detail::halfToFloat(in[k])) && ++wrong <= 5)
                ADD_FAILURE() << std::hex << in[k] << ": lane " << k << " gives " << out[k];
    }
    EXPECT_EQ(wrong, 0);
}
#endif

}  // namespace
}  // namespace glint::render
