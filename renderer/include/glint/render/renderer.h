// glint::render::Renderer — renders a Scene progressively into glint::FrameBuffers.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/render/scene.h"
#include "glint/render/settings.h"

namespace glint::render {

/// Observers of a running render. Every callback may be empty. Calls are serialised (never two
/// at once) but may come from worker threads.
struct Callbacks {
    /// After each tile: pass index (0-based) and the fraction of the whole render done so far.
    std::function<void(int pass, double fraction)> progress;
    /// A tile finished its share of the current pass.
    std::function<void(const Rect& tile)> tileDone;
    /// Polled between tiles; returning true stops the render, which then returns what it has.
    std::function<bool()> cancel;
    /// After each completed pass, with the frame accumulated so far (resolved only when set).
    std::function<void(int pass, const FrameBuffers& frame)> passDone;
};

/// What the last render did (for summaries and benchmarks).
struct RenderStats {
    double seconds = 0.0;               ///< wall-clock time of render()
    std::uint64_t samples = 0;          ///< camera samples traced (including discarded ones)
    std::uint64_t rays = 0;             ///< rays traced: camera, bounce and shadow rays
    std::int64_t nonFiniteSamples = 0;  ///< samples discarded because they were NaN/Inf
    int passes = 0;                     ///< passes completed
    int completedSpp = 0;               ///< samples per pixel of every completed pass
    bool cancelled = false;             ///< stopped by Callbacks::cancel
};

/// Throughput of the ray-tracing kernel alone (no shading), for benchmarks.
struct RayThroughput {
    std::uint64_t rays = 0;
    double seconds = 0.0;
    std::uint64_t hits = 0;
};

/// Owns the acceleration structure of one scene; render() may be called repeatedly.
class Renderer {
  public:
    /// Builds the ray-tracing structures of the scene.
    explicit Renderer(Scene scene);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    /// Renders with `settings` in progressive passes. Output: colour mean, variance of the mean,
    /// albedo/normal/depth (and position if asked) with their variances, sample count. A
    /// cancelled render returns the tiles it finished, each pixel's statistics covering exactly
    /// its sampleCount samples. Output is bit-identical for any thread count.
    FrameBuffers render(const Settings& settings, const Callbacks& callbacks = {});

    /// Statistics of the last render().
    const RenderStats& stats() const { return m_stats; }

    /// The scene being rendered.
    const Scene& scene() const { return m_scene; }

    /// Traces `rays` single rays (half camera rays, half uniformly random rays from the scene's
    /// bounding box centre) with the raw intersection kernel on `threads` threads (0 = all).
    RayThroughput measureRayThroughput(std::uint64_t rays, int threads,
                                       std::uint64_t seed = 1) const;

  private:
    struct Impl;
    Scene m_scene;
    std::unique_ptr<Impl> m_impl;
    RenderStats m_stats;
};

}  // namespace glint::render
