// The primary-sample-space state of one Metropolis chain (Kelemen et al. 2002): a path is the
// point of the unit hypercube holding every random number the path integrator consumed. The
// vector grows lazily, and every coordinate remembers when it was last brought up to date, so a
// mutation costs only as much as the coordinates the new path actually reads.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "sampling/rng.h"
#include "sampling/sampler.h"

namespace glint::render {

/// The mutation strategies of the Metropolis integrator.
enum class MutationKind : int { Large = 0, Small = 1, Lens = 2, Light = 3 };
inline constexpr int kMutationKinds = 4;

/// Name of a mutation kind ("large", "small", "lens", "light").
const char* mutationName(MutationKind kind);

/// Reserved coordinates of the camera sample; the path and light streams follow, interleaved.
inline constexpr int kFilmX = 0, kFilmY = 1, kLensU = 2, kLensV = 3, kTime = 4;
inline constexpr int kCameraDims = 5;

/// Perturbation sizes of Kelemen's exponential kernel, log-uniform magnitudes in [s1, s2].
struct PerturbationSize {
    float s1 = 1.0f / 1024.0f;
    float s2 = 1.0f / 64.0f;
};

/// Sizes of every mutation kind, in the unit interval of each coordinate.
struct MutationSizes {
    PerturbationSize small;  ///< small step, every coordinate
    PerturbationSize lensX;  ///< lens perturbation of film x (pixels / width)
    PerturbationSize lensY;  ///< lens perturbation of film y (pixels / height)
    PerturbationSize light;  ///< light perturbation of light-stream coordinates
};

/// One chain's primary sample vector with lazy large/small-step bookkeeping (the scheme of
/// Kelemen et al. 2002, sec. 4, as pbrt-v3 sec. 16.4.3 describes it, except that only accepted
/// steps count as pending perturbations: see docs/metropolis.md). Coordinate layout: the
/// five camera coordinates (film x, y, lens u, v, time), then the path stream (BSDF and
/// Russian-roulette numbers) at even and the light stream (next-event estimation: light choice
/// and point on the light) at odd offsets, so a light perturbation can touch only the latter.
class MltSampler {
  public:
    /// A stream sampler (sampling/sampler.h): the path reads every number it might need.
    static constexpr bool kSlotted = false;

    /// A chain whose uniform numbers come from the stream `key`.
    MltSampler(std::uint64_t key, const MutationSizes& sizes);

    /// Continues with the random stream `key` (after the initial state was reproduced).
    void reseed(std::uint64_t key) { m_rng = Rng(key); }
    /// The chain's generator, also used for mutation choice and acceptance.
    Rng& rng() { return m_rng; }

    /// Begins a proposal of the given kind; the coordinates read next are the proposed state.
    void startIteration(MutationKind kind);
    /// Keeps the proposed state.
    void accept();
    /// Restores the state before startIteration.
    void reject();

    /// Sets camera coordinate `dim` of the current large-step proposal to `value` instead of a
    /// uniform number (stratified bootstrap film positions); call before the path reads it.
    void setCamera(int dim, float value);
    /// Camera coordinate `dim` (kFilmX ... kTime).
    float camera(int dim) { return get(std::size_t(dim), Stream::Camera); }
    /// Next path-stream number (BSDF sampling, Russian roulette).
    float uniform() { return get(kCameraDims + 2 * std::size_t(m_pathIndex++), Stream::Path); }
    /// Next light-stream number (next-event estimation).
    float uniformLight() {
        return get(kCameraDims + 2 * std::size_t(m_lightIndex++) + 1, Stream::Light);
    }

    /// PathSampler: next-event numbers from the light stream (so that light perturbations
    /// change only these), every other number from the path stream; a pair is two numbers.
    float bounce1D(int /*depth*/, BounceDim slot) {
        return isLightSlot(slot) ? uniformLight() : uniform();
    }
    Vec2 bounce2D(int depth, BounceDim slot) {
        const float u = bounce1D(depth, slot);
        return {u, bounce1D(depth, slot)};
    }

    /// Number of coordinates materialised so far (for tests).
    std::size_t dimensions() const { return m_x.size(); }

  private:
    enum class Stream { Camera, Path, Light };
    /// Counts of iterations per mutation kind (unsigned: differences stay right on wrap-around).
    using Counts = std::array<std::uint32_t, kMutationKinds>;
    struct Coordinate {
        float value = 0.0f;
        float backupValue = 0.0f;
        std::int64_t largeIteration = INT64_MIN;  // large step it was last drawn in
        std::int64_t backupLarge = INT64_MIN;
        std::int64_t touched = -1;  // iteration it was last backed up in
        Counts seen{};              // mutation counts it has caught up with
        Counts backupSeen{};
    };
    /// Kelemen's kernel with precomputed constants.
    struct Kernel {
        float s2 = 0.0f, log2Ratio = 0.0f;  // dv = s2 · 2^(−log2(s2/s1) u)
        double variance = 0.0;              // E[dv²], for the Gaussian catch-up
    };

    /// Coordinate `index` of the current proposal. Inline fast path for the common case of a
    /// path- or light-stream number read in the previous accepted state (at most one pending
    /// step); everything else (growth, stale numbers, large steps, catch-up) in getSlow.
    float get(std::size_t index, Stream stream) {
        if (index < m_x.size()) {
            Coordinate& c = m_x[index];
            if (c.touched == m_iteration) return c.value;
            if (stream != Stream::Camera && m_kind != MutationKind::Large &&
                c.largeIteration >= m_lastLarge) {
                constexpr int kSmall = int(MutationKind::Small), kLight = int(MutationKind::Light);
                const std::uint32_t nSmall = m_count[kSmall] - c.seen[kSmall];
                const std::uint32_t nLight =
                    stream == Stream::Light ? m_count[kLight] - c.seen[kLight] : 0u;
                if (nSmall + nLight <= 1) {
                    backup(c, index);
                    if (nSmall) c.value = step(c.value, m_small);
                    if (nLight) c.value = step(c.value, m_light);
                    c.seen = m_count;
                    return c.value;
                }
            }
        }
        return getSlow(index, stream);
    }
    /// Records the coordinate's state before this proposal, for reject().
    void backup(Coordinate& c, std::size_t index) {
        c.touched = m_iteration;
        c.backupValue = c.value;
        c.backupLarge = c.largeIteration;
        c.backupSeen = c.seen;
        m_touchedList.push_back(std::uint32_t(index));
    }
    float getSlow(std::size_t index, Stream stream);
    /// 2^t for t in (−126, 0]: exponent bits plus a cubic for the fraction (relative error
    /// ~1e-4). Only perturbation magnitudes use it: any symmetric kernel keeps the chain exact.
    static float fastExp2Negative(float t) {
        const float fl = std::floor(t);
        const float f = t - fl;
        const float p = 1.0f + f * (0.6960656f + f * (0.2244012f + f * 0.0794220f));
        const std::uint32_t bits = std::uint32_t(int(fl) + 127) << 23;
        float scale;
        std::memcpy(&scale, &bits, sizeof scale);
        return p * scale;
    }
    /// One kernel step applied to x in [0, 1), wrapped around.
    float step(float x, const Kernel& k) {
        const std::uint64_t bits = m_rng.nextU64();
        const float u = float(bits >> 40) * 0x1p-24f;
        const float dv = k.s2 * fastExp2Negative(-k.log2Ratio * u);
        x += (bits & 1u) ? dv : -dv;
        if (x < 0.0f) x += 1.0f;
        if (x >= 1.0f) x -= 1.0f;
        return x < 1.0f && x >= 0.0f ? x : 0.0f;
    }
    /// Catches up with nSmall small steps and nOther steps of kernel `other` (exactly for few
    /// steps, else by the central-limit Gaussian of the same variance).
    float catchUp(float x, std::uint32_t nSmall, std::uint32_t nOther, const Kernel* other);
    static Kernel makeKernel(const PerturbationSize& size);

    Rng m_rng;
    Kernel m_small, m_lensX, m_lensY, m_light;
    std::vector<Coordinate> m_x;
    std::vector<std::uint32_t> m_touchedList;
    std::int64_t m_iteration = -1;
    MutationKind m_kind = MutationKind::Large;
    Counts m_count{};               // accepted iterations of each kind (+ the current one)
    std::int64_t m_lastLarge = -1;  // iteration of the last accepted large step
    Counts m_countAtLarge{};        // m_count when that large step was accepted
    int m_pathIndex = 0, m_lightIndex = 0;
};

static_assert(PathSampler<MltSampler>);

}  // namespace glint::render
