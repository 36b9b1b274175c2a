// glint::render::Renderer — renders a Scene progressively into glint::FrameBuffers.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/render/scene.h"
#include "glint/render/settings.h"

namespace glint::render {

namespace detail {
struct RendererAccess;
}

/// Observers of a running render. Every callback may be empty. Calls are serialised (never two
/// at once) but may come from worker threads.
struct Callbacks {
    /// After each work item (a tile; a group of Metropolis chains; a block of Metropolis's
    /// bootstrap, which precedes pass 0 and reports as it): pass index (0-based) and the
    /// fraction of the whole render done so far.
    std::function<void(int pass, double fraction)> progress;
    /// A tile finished its share of the current pass.
    std::function<void(const Rect& tile)> tileDone;
    /// Polled between tiles; returning true stops the render, which then returns what it has.
    std::function<bool()> cancel;
    /// After each completed pass, with the frame accumulated so far (resolved only when set).
    std::function<void(int pass, const FrameBuffers& frame)> passDone;
    /// Adaptive sampling (Settings::adaptive): before each adaptive pass, its index and the frame
    /// so far (resolved only when set). A map returned replaces the importance map from that pass
    /// on (checked as Settings::importance is: one channel, the film's size, finite weights ≥ 0,
    /// not all 0); an empty pointer keeps the current one. The render stays deterministic when
    /// the callback's answer is a function of the frame.
    std::function<std::shared_ptr<const Image>(int pass, const FrameBuffers& frame)> importance;
    /// Adaptive sampling: when no pixel would take the next pass (each converged or at spp), the
    /// frame so far. A map returned replaces the importance map and the pass is planned again
    /// (larger weights lower the threshold: a time limit's caller keeps sampling); an empty
    /// pointer ends the render, as does a run of kMaxConvergedRetries maps that open no pixel.
    std::function<std::shared_ptr<const Image>(int pass, const FrameBuffers& frame)> converged;
};

/// The most maps in a row Callbacks::converged may return that open no pixel before the render
/// ends (a caller that keeps scaling its map up cannot loop forever on pixels at spp).
inline constexpr int kMaxConvergedRetries = 64;

/// What a Metropolis render did (Settings::integrator == Mlt), per mutation kind in the order
/// large step, small step, lens perturbation, light perturbation (mltMutationName()).
struct MltStats {
    std::array<std::uint64_t, 4> proposed{};
    std::array<std::uint64_t, 4> accepted{};
    std::array<double, 4> probabilities{};  ///< normalised mutation weights used
    std::uint64_t mutations = 0;            ///< mutations over all chains
    std::uint64_t bootstrap = 0;            ///< uniform paths that estimated b
    double b = 0.0;                         ///< mean luminance of the image (bootstrap estimate)
    double bRelStdErr = 0.0;                ///< relative standard error of b
    /// Relative standard error of the chains' estimate given b (batch means over the groups).
    double chainsRelStdErr = 0.0;
    /// Relative standard error of the image's mean: b's and the chains' in quadrature.
    double meanRelStdErr = 0.0;
    double mutationSeconds = 0.0;  ///< time spent in the chains
    int chains = 0;
    int groups = 0;      ///< batches of chains of the batch-means variance
    int featureSpp = 0;  ///< spp of the path-traced feature pass

    /// Accepted / proposed of mutation kind k (0 when none was proposed).
    double acceptance(int k) const {
        return proposed[std::size_t(k)] > 0
                   ? double(accepted[std::size_t(k)]) / double(proposed[std::size_t(k)])
                   : 0.0;
    }
    /// Mutations per second of chain time.
    double mutationsPerSecond() const {
        return mutationSeconds > 0.0 ? double(mutations) / mutationSeconds : 0.0;
    }
};

/// Name of Metropolis mutation kind k: "large", "small", "lens", "light".
const char* mltMutationName(int k);

/// What a render did (for summaries and benchmarks).
struct RenderStats {
    double seconds = 0.0;               ///< wall-clock time of render()
    std::uint64_t samples = 0;          ///< camera samples traced (including discarded ones)
    std::uint64_t rays = 0;             ///< rays traced: camera, bounce and shadow rays
    std::int64_t nonFiniteSamples = 0;  ///< samples discarded because they were NaN/Inf
    int passes = 0;                     ///< passes completed
    int completedSpp = 0;               ///< samples per pixel of every completed pass
    bool cancelled = false;             ///< stopped by Callbacks::cancel
    std::optional<MltStats> mlt;        ///< set by a Metropolis render
};

/// A rendered frame and what it took.
struct RenderResult {
    FrameBuffers frame;
    RenderStats stats;
};

/// What a scene needs in memory besides the film, estimated before its ray-tracing structures
/// are built (docs/renderer.md, "Memory").
struct SceneMemory {
    Accel accel = Accel::Triangles;  ///< what the BVH is built over (Auto resolved)
    std::uint64_t meshes = 0;        ///< the mesh arrays and instances (held since loading)
    std::uint64_t images = 0;      ///< in-memory textures, resident texture levels, the environment
    std::uint64_t structures = 0;  ///< the BVH at its build's peak (and the clusters' order)
    std::uint64_t textureCache = 0;  ///< the texture tile cache, full (at most the textures)
    /// Bytes held since loading.
    std::uint64_t held() const;
    /// Bytes building and rendering will add.
    std::uint64_t added() const;
    /// held() + added().
    std::uint64_t total() const;
};

/// Estimates the memory of `scene` built over `accel` (Auto resolved as a Renderer resolves it)
/// and rendered with a texture cache of `textureCacheMb` megabytes.
SceneMemory estimateSceneMemory(const Scene& scene, Accel accel, int textureCacheMb);

/// Owns the acceleration structure of one scene; render() may be called repeatedly.
class Renderer {
  public:
    /// Builds the ray-tracing structures of the scene, over the primitives its settings' accel
    /// names.
    explicit Renderer(Scene scene);
    /// Builds them over the primitives `accel` names (Settings::accel).
    Renderer(Scene scene, Accel accel);
    /// Builds them over settings.accel within settings.memoryLimit (0: the memory available),
    /// for renders with `settings`: before building anything, refuses with Error(OutOfMemory) a
    /// film (estimateMemory) or a scene and film (estimateSceneMemory: against an explicit
    /// limit what the scene holds counts too) that exceed it, saying whether clusters would
    /// fit; under Accel::Auto builds clusters where Embree's triangles would not fit and
    /// clusters do.
    Renderer(Scene scene, const Settings& settings);
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    /// Renders with `settings` in progressive passes. Output: colour mean, variance of the mean,
    /// albedo/normal/depth (and position if asked) with their variances, sample count, and the
    /// render's statistics. A cancelled render returns the tiles it finished, each pixel's
    /// statistics covering exactly its sampleCount samples. Output is bit-identical for any
    /// thread count. Look edits made through scene() since the last render are picked up here
    /// (lights are rebuilt; the ray-tracing structures are kept).
    RenderResult render(const Settings& settings, const Callbacks& callbacks = {});

    /// Bytes render(settings) allocates at most besides the scene and its BVH (already built):
    /// the film's running statistics, the resolved frame, a snapshot for Callbacks::passDone,
    /// and Metropolis' per-group splat buffers. render() refuses with Error(OutOfMemory) when
    /// this exceeds the memory available or, with Settings::memoryLimit, when this and the
    /// scene's estimateSceneMemory exceed the limit, before allocating.
    std::uint64_t estimateMemory(const Settings& settings) const;

    /// What the BVH was built over: Accel::Triangles or Accel::Clusters.
    Accel accel() const;

    /// The scene being rendered; its look (materials, lights, environment) may be edited
    /// between renders.
    const Scene& scene() const { return m_scene; }
    Scene& scene() { return m_scene; }

  private:
    // Test and benchmark hooks (renderer/src/renderer_detail.h) read the private state.
    friend struct detail::RendererAccess;
    struct Impl;
    /// Checks the scene's camera and builds the ray-tracing structures over `accel`.
    void build(Accel accel);
    /// What to build over for renders with `settings` within their memory limit (see the
    /// constructor); throws Error(OutOfMemory) when nothing fits.
    Accel accelWithin(const Settings& settings) const;
    /// Throws Error(OutOfMemory) when a film of `film` bytes and the scene built as `scene` says
    /// exceed `settings`' limit, saying what would fit.
    void checkSceneMemory(std::uint64_t film, const SceneMemory& scene,
                          const Settings& settings) const;
    Scene m_scene;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace glint::render
