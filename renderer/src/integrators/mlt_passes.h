// Metropolis light transport's passes for the render loop (integrators/render_loop.h): the
// bootstrap as the loop's preparatory pass (items: blocks of bootstrap samples), then the
// passes of the chains (item g: the chains of group g), so both report progress and stop when
// cancelled (docs/metropolis.md).
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "integrators/render_loop.h"
#include "sampling/mlt_sampler.h"
#include "vecmath.h"

namespace glint::render {

class MltIntegrator;

/// What the chains' mutation choice and splatting need from the integrator's settings.
struct MltPassSettings {
    std::uint64_t seed = 0;
    std::int64_t bootstrap = 1;  ///< bootstrap samples N
    int chains = 2, groups = 2;
    MutationSizes sizes;
    std::array<float, kMutationKinds> cdf{};  ///< cumulative mutation probabilities
    float pLarge = 0.0f;                      ///< probability of a large step
};

/// The bootstrap and the chains of one Metropolis render.
class MltPasses final : public PassWork {
  public:
    /// `features` (the path-traced frame) and `integrator` must outlive the passes.
    MltPasses(const MltIntegrator& integrator, int width, int height, const MltPassSettings& s,
              const FrameBuffers& features);

    // The bootstrap (Kelemen et al. 2002, sec. 5; Veach 1997, sec. 11.3.1): N independent
    // uniform primary samples estimate b = ∫ f, the image's mean luminance.
    std::size_t setupItems() const override;
    double setupSpp() const override;
    void runSetup(std::size_t block, const RenderLoop& loop) override;
    /// Estimates b and picks the chains' start samples; false for a black image (b = 0).
    bool setupCompleted() override;

    // The chains: every chain advances by the same number of mutations a pass (pass.count
    // mutations per pixel over all chains); groups run in parallel, the chains of a group one
    // after another in index order, so every sum has a fixed order.
    std::size_t items() const override { return m_groups.size(); }
    void run(const PassInfo& pass, std::size_t group, const RenderLoop& loop) override;
    void passCompleted(const PassInfo& pass) override;
    FrameBuffers snapshot() override { return m_snapshot; }

    /// The frame of the completed passes; empty before the first.
    const FrameBuffers& last() const { return m_snapshot; }
    /// Mutations of each chain in the completed passes.
    std::uint64_t perChainDone() const { return m_perChainDone; }
    /// Chains started (0 before the bootstrap completed or for a black image).
    std::size_t chainsStarted() const { return m_chains.size(); }
    /// True once the bootstrap completed (not when it was cancelled).
    bool bootstrapDone() const { return m_bootDone; }
    /// Seconds from construction to the end of the bootstrap.
    double bootstrapSeconds() const { return m_bootSeconds; }
    /// Adds the bootstrap's and the chains' figures to `stats` (b, its error, bootstrap samples
    /// taken, mutation counts), `rays` and `nonFinite`.
    void addStatistics(MltStats& stats, std::uint64_t& rays, std::int64_t& nonFinite) const;
    /// Relative standard error of the image's mean luminance from the chains alone, for a
    /// given b: batch means over the groups of their images' mean luminance (0 before the first
    /// pass or with one group).
    double chainsRelStdErr() const;

  private:
    /// One Markov chain: its primary sample vector and the current state's contribution.
    struct Chain {
        MltSampler sampler;
        std::int64_t bootstrapIndex;  // the bootstrap sample it started from
        Vec3 radiance;
        Vec2 raster;
        float f = 0.0f;  // target: luminance of the contribution
    };
    /// The splats of one batch of chains (accumulated in double) and its counters.
    struct Group {
        std::vector<double> sum;  // width × height × 3
        std::array<std::uint64_t, kMutationKinds> proposed{}, accepted{};
        std::uint64_t rays = 0;
        std::int64_t nonFinite = 0;
        bool started = false;  // its chains reproduced their bootstrap samples
    };

    /// Starts bootstrap sample i: a large step with its film point stratified.
    void startBootstrapSample(MltSampler& sampler, std::int64_t i) const;
    /// Reproduces the start sample of each chain of group g, then continues it with its own
    /// stream.
    void startChains(std::size_t g);
    /// Mutations per chain in a pass.
    std::uint64_t perChain(const PassInfo& pass) const;
    /// The frame of the completed passes (batch means over the groups).
    FrameBuffers resolve() const;

    const MltIntegrator& m_integrator;
    int m_width, m_height;
    std::size_t m_pixels;
    MltPassSettings m_s;
    const FrameBuffers& m_features;
    std::chrono::steady_clock::time_point m_start;
    // Bootstrap: f of every sample, and per block of samples its counters.
    std::vector<float> m_bootF;
    std::vector<std::uint64_t> m_bootRays, m_bootTaken;
    std::vector<std::int64_t> m_bootNonFinite;
    double m_b = 0.0, m_bRelStdErr = 0.0, m_bootSeconds = 0.0;
    bool m_bootDone = false;
    float m_invB = 0.0f;
    // Chains.
    std::vector<Chain> m_chains;
    std::vector<Group> m_groups;
    std::uint64_t m_perChainDone = 0;
    FrameBuffers m_snapshot;
};

}  // namespace glint::render
