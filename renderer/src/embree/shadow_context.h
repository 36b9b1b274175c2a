// The context of an occlusion query: Embree hands it to the occluded filter, which accumulates
// each ray's transmittance through BLEND surfaces there (embree/alpha_filter.cpp). Private to
// embree/: it includes <embree3/rtcore.h>.
#pragma once

#include <cstdint>

#include <embree3/rtcore.h>

namespace glint::render {

/// RTCIntersectContext extended (it comes first, so Embree's pointer is this struct's) with
/// per-lane shadow state; lane k is the ray whose id is k.
struct ShadowContext {
    static constexpr int kLanes = 16;  ///< the widest packet
    static constexpr int kSeen = 16;   ///< BLEND hits a lane remembers; past them, stochastic

    RTCIntersectContext base;
    float transmittance[kLanes];  ///< product of (1 − alpha) of the BLEND hits counted so far
    std::uint8_t seenCount[kLanes];
    /// The (instance, triangle) of each counted hit: Embree may report one hit more than once
    /// (spatial splits put a triangle in several leaves), and it must count once.
    std::uint32_t seenInstance[kLanes][kSeen];
    std::uint32_t seenPrim[kLanes][kSeen];

    /// A fresh query of `lanes` rays: all clear, nothing seen.
    void reset(int lanes) {
        rtcInitIntersectContext(&base);
        for (int k = 0; k < lanes; ++k) {
            transmittance[k] = 1.0f;
            seenCount[k] = 0;
        }
    }
};

}  // namespace glint::render
