// The image pairs on which Glint's FLIP is compared with the authors' implementation
// (tests/image/flip_test.cpp; the reference values come from lab/bench/flip_reference.sh, which
// builds the same pairs with this header). Plain C++ (no Glint types): interleaved RGB floats.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace flip_pairs {

constexpr int kWidth = 48;
constexpr int kHeight = 40;

/// A deterministic value in [0, 1) from integers (a 32-bit integer hash, Wellons' lowbias32).
inline float hashUnit(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    std::uint32_t h = a * 0x9E3779B9u ^ (b + 0x7F4A7C15u) * 0x85EBCA6Bu ^ (c + 0x165667B1u);
    h ^= h >> 16;
    h *= 0x7FEB352Du;
    h ^= h >> 15;
    h *= 0x846CA68Bu;
    h ^= h >> 16;
    return float(h >> 8) * (1.0f / 16777216.0f);
}

struct Pair {
    std::string name;
    bool hdr = false;
    std::vector<float> reference, test;  ///< kWidth * kHeight * 3, linear RGB
};

/// The reference scene: smooth colour gradients, a checkerboard of hard edges and a bright disc
/// (HDR: radiance up to 24, LDR: scaled into [0.02, 0.98]).
inline std::vector<float> scene(bool hdr) {
    std::vector<float> out(std::size_t(kWidth) * kHeight * 3);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const float u = float(x) / (kWidth - 1), v = float(y) / (kHeight - 1);
            const bool check = ((x / 6) + (y / 6)) % 2 == 0;
            const float dx = float(x) - 30.0f, dy = float(y) - 14.0f;
            const bool disc = dx * dx + dy * dy < 49.0f;
            float rgb[3] = {0.2f + 0.6f * u, 0.3f + 0.4f * v * (1 - u), 0.6f - 0.4f * u * v};
            for (float& c : rgb) c *= check ? 1.0f : 0.45f;
            if (disc)
                for (int c = 0; c < 3; ++c) rgb[c] = hdr ? 24.0f * (c == 2 ? 0.5f : 1.0f) : 0.98f;
            for (int c = 0; c < 3; ++c)
                out[(std::size_t(y) * kWidth + x) * 3 + c] =
                    hdr ? rgb[c] * (0.2f + 3.0f * u) : std::clamp(rgb[c], 0.02f, 0.98f);
        }
    return out;
}

/// The eight pairs: LDR and HDR, each with noise, blur, a colour shift and fireflies.
inline std::vector<Pair> pairs() {
    std::vector<Pair> out;
    for (const bool hdr : {false, true}) {
        const std::vector<float> ref = scene(hdr);
        const float top = hdr ? 1e30f : 1.0f;
        auto at = [&](const std::vector<float>& im, int x, int y, int c) {
            x = std::clamp(x, 0, kWidth - 1);
            y = std::clamp(y, 0, kHeight - 1);
            return im[(std::size_t(y) * kWidth + x) * 3 + c];
        };
        const std::string range = hdr ? "hdr-" : "ldr-";
        Pair noise{range + "noise", hdr, ref, ref}, blur{range + "blur", hdr, ref, ref},
            shift{range + "shift", hdr, ref, ref}, fireflies{range + "fireflies", hdr, ref, ref};
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x) {
                const bool firefly = hashUnit(std::uint32_t(x), std::uint32_t(y), 99) < 0.015f;
                for (int c = 0; c < 3; ++c) {
                    const std::size_t i = (std::size_t(y) * kWidth + x) * 3 + std::size_t(c);
                    const float r = ref[i];
                    // Noise: relative (HDR) or absolute (LDR), uniform, zero mean.
                    const float n =
                        hashUnit(std::uint32_t(x), std::uint32_t(y), std::uint32_t(c)) - 0.5f;
                    noise.test[i] =
                        std::clamp(hdr ? r * (1.0f + 0.8f * n) : r + 0.25f * n, 0.0f, top);
                    // Blur: 3x3 box.
                    float sum = 0.0f;
                    for (int j = -1; j <= 1; ++j)
                        for (int k = -1; k <= 1; ++k) sum += at(ref, x + k, y + j, c);
                    blur.test[i] = sum / 9.0f;
                    // Colour shift: warmer.
                    const float gain[3] = {1.12f, 0.97f, 0.85f};
                    shift.test[i] = std::clamp(r * gain[c], 0.0f, top);
                    // Fireflies: 1.5 % of the pixels saturated (LDR) or at 200 (HDR).
                    fireflies.test[i] = firefly ? (hdr ? 200.0f : 1.0f) : r;
                }
            }
        for (Pair* p : {&noise, &blur, &shift, &fireflies}) out.push_back(std::move(*p));
    }
    return out;
}

}  // namespace flip_pairs
