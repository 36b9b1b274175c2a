// The per-pixel NL-means distance that nlmeans and nfor share (Rousselle, Knaus & Zwicker 2012,
// eq. 5), on 8-wide vectors of planar rows.
#pragma once

#include <cstddef>

#include "filters/simd.h"

namespace glint::denoise::detail {

/// The planes one distance row reads: colour u and its variance of the mean v (3 channels each)
/// and the validity m (1 or 0), all with the same indexing.
struct NlDistancePlanes {
    const float* u[3];
    const float* v[3];
    const float* m;
};

/// out[i], for n pixels (a multiple of 8) from plane index ip with partners at ip + offset: the
/// channel mean of ((u_p - u_q)^2 - alpha (v_p + min(v_p, v_q))) / (1e-10 + k2 (v_p + v_q)),
/// clamped to [-cap, cap], times m_p m_q. Inlined into the callers' SIMD clones.
[[gnu::always_inline]] inline void nlDistanceRow(const NlDistancePlanes& pl, std::size_t ip,
                                                 std::ptrdiff_t offset, int n, float k2,
                                                 float alpha, float cap, float* out) {
    constexpr float kEps = 1e-10f;
    for (int i = 0; i < n; i += 8) {
        const std::size_t a = ip + std::size_t(i), b = std::size_t(std::ptrdiff_t(a) + offset);
        VecF d{};
        for (int c = 0; c < 3; ++c) {
            VecF up, uq, vp, vq;
            loadVec(up, pl.u[c] + a);
            loadVec(uq, pl.u[c] + b);
            loadVec(vp, pl.v[c] + a);
            loadVec(vq, pl.v[c] + b);
            const VecF diff = up - uq;
            const VecF vmin = vp < vq ? vp : vq;
            d += (diff * diff - alpha * (vp + vmin)) / (kEps + k2 * (vp + vq));
        }
        d *= 1.0f / 3.0f;
        d = d > cap ? (VecF{} + cap) : d;
        d = d < -cap ? (VecF{} - cap) : d;
        VecF mp, mq;
        loadVec(mp, pl.m + a);
        loadVec(mq, pl.m + b);
        storeVec(out + i, d * (mp * mq));
    }
}

}  // namespace glint::denoise::detail
