// glint::render::Settings — how one render runs (spp, seed, threads, integrator, MIS...).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "glint/image/image.h"

#include "glint/render/mlt_settings.h"

namespace glint {
class FrameBuffers;
}

namespace glint::render {

/// Light-transport algorithm.
enum class Integrator { Path, Mlt };
/// How next-event estimation and BSDF sampling are combined (Veach 1997, ch. 9).
enum class MisHeuristic { Power, Balance, None };
/// The single strategy used when MisHeuristic::None is selected.
enum class Strategy { Bsdf, Light };
/// Where a camera sample's random numbers come from (docs/renderer.md, "Sampling").
enum class SamplerKind {
    Stratified,   ///< pixel, lens and time stratified per pass; the rest independent
    Independent,  ///< every number independent
    Sobol,        ///< Owen-scrambled Sobol over every path dimension (Burley 2020)
    ZSobol        ///< one Sobol sequence across the film in Morton order (Ahmed and Wonka 2020)
};

/// Which statistics adaptive sampling estimates a pixel's error from (docs/renderer.md,
/// "Adaptive sampling").
enum class AdaptiveError {
    /// The odd samples alone (half B): the even half never steers where samples go, so it stays
    /// an unbiased estimate of the pixel (and half buffers stay honest for cross-validation).
    Half,
    /// Every sample (the film's own Welford statistics): a decision from the very samples it
    /// stops, so the mean has a small bias.
    Whole
};

/// What Embree builds its BVH over (docs/renderer.md, "Acceleration structure").
enum class Accel {
    /// Clusters when the BVHs would hold more than kClusterTriangles triangles (a mesh shared
    /// by instances counted once), else triangles.
    Auto,
    Triangles,  ///< Embree's own triangles
    Clusters    ///< clusters of a few triangles a static mesh (less memory, slower rays)
};
/// Above this many triangles, Accel::Auto builds clusters.
inline constexpr std::size_t kClusterTriangles = std::size_t(1) << 21;

/// The limits of Settings, the same for scene.json's "render" block, the command line and the
/// API (validate()).
inline constexpr int kMaxSpp = 1 << 24;       ///< samples per pixel
inline constexpr int kMaxDepth = 1024;        ///< bounces (maxDepth, rrDepth)
inline constexpr int kMaxThreads = 1024;      ///< worker threads
inline constexpr double kMaxTimeLimit = 1e7;  ///< seconds (about 4 months)
inline constexpr std::uint64_t kMaxSeed = (std::uint64_t(1) << 63) - 1;
inline constexpr int kMaxTextureCacheMb = 1 << 20;  ///< texture tile cache, MB (1 TiB)
inline constexpr double kMaxNoiseThreshold = 1e6;   ///< adaptive sampling's noiseThreshold

/// One shard of a render split over machines (docs/distributed.md): shard `index` of `count`
/// takes per-pixel samples [⌊index·spp/count⌋, ⌊(index+1)·spp/count⌋) of the spp of the whole
/// render, the very samples the whole render takes there, so that glint::mergeShards of all
/// `count` shards gives the whole render.
struct Shard {
    int index = 0;
    int count = 1;
};

/// Render settings. A scene's "render" block gives defaults (Scene::settings()); a caller
/// copies them and overrides what it wants.
struct Settings {
    int spp = 16;            ///< samples per pixel (0 with timeLimit > 0: until time runs out)
    std::uint64_t seed = 1;  ///< seed of every per-pixel random stream
    int threads = 0;         ///< worker threads; 0 = all hardware threads
    Integrator integrator = Integrator::Path;
    MisHeuristic mis = MisHeuristic::Power;
    Strategy strategy = Strategy::Bsdf;  ///< only with mis == None
    SamplerKind sampler = SamplerKind::Sobol;
    int maxDepth = 32;  ///< maximum number of bounces (1 = direct lighting only)
    int rrDepth = 3;    ///< Russian roulette starts after this many bounces
    /// Seconds; > 0 renders passes until time runs out (the first pass of 1 spp always
    /// completes, so a tiny limit still gives an image).
    double timeLimit = 0.0;
    int tileSize = 16;  ///< tile edge in pixels
    /// Render only these pixels (path integrator): the rest of the frame has no samples. For a
    /// studio's render region; the whole film when empty.
    std::optional<Rect> region;
    bool positionLayer = false;  ///< also produce the optional world-space position layer
    /// Split every pixel's samples into two independent halves (even and odd sample indices;
    /// the Sobol sampler scrambles each half on its own) and also produce the half-buffer
    /// layers, the statistics of the odd half alone (glint::splitHalves gives both halves).
    /// Two halves estimate a filter's error without a reference by cross-validation
    /// (docs/renderer.md, "Half buffers"). Path integrator with the sobol or independent
    /// sampler. The cost: two sequences of n/2 samples are worth less than one of n.
    bool halfBuffers = false;
    /// Bytes a render's data may take: its film and frames (Renderer::estimateMemory) and, when
    /// set, the scene (estimateSceneMemory: meshes, images, BVH, texture cache); a render or a
    /// Renderer(scene, settings) needing more is refused with Error(OutOfMemory) before anything
    /// is allocated. 0: what the machine has available (glint::availableMemory()).
    std::uint64_t memoryLimit = 0;
    /// Megabytes of texture tiles the scene's texture cache holds (docs/assets.md, "Textures");
    /// textures larger than it render the same, reading tiles again as they are needed.
    int textureCacheMb = 1024;
    MltSettings mlt;  ///< Metropolis parameters (integrator == Mlt)
    /// The BVH's primitives; read when a Renderer is made (the BVH is built once), not by
    /// render().
    Accel accel = Accel::Auto;
    /// Render only this shard of the spp samples per pixel (path integrator, no time limit);
    /// the frame then records glint::ShardInfo. The whole render when empty.
    std::optional<Shard> shard;
    /// Adaptive sampling (docs/renderer.md, "Adaptive sampling"; Cycles' "noise threshold"):
    /// after minSpp samples everywhere, passes add samples only to the pixels whose estimated
    /// error (times the importance map's weight) is above noiseThreshold, until none is, spp
    /// (the most a pixel takes) is reached or the time limit runs out. Path integrator, sobol,
    /// zsobol or independent sampler, no shard.
    bool adaptive = false;
    /// A pixel has converged when its estimated error is below this, in (0, 1e6].
    double noiseThreshold = 0.01;
    /// Samples every pixel takes before adaptive passes; 0: Cycles' automatic choice,
    /// max(4, ceil(16 / noiseThreshold^0.3)) (64 at 0.01), at most spp.
    int minSpp = 0;
    /// Whose statistics estimate the error (AdaptiveError).
    AdaptiveError adaptiveError = AdaptiveError::Half;
    /// Per-pixel weights (one channel, the film's size, finite, ≥ 0, not all 0) that multiply
    /// the estimated error: 0 gives a pixel only the minSpp start. Needs adaptive. None: 1.
    std::shared_ptr<const Image> importance;
    /// Adaptive sampling: a finished render to go on from instead of starting from nothing (the
    /// studio's Keep Refining continues the render on screen). Its pixels' statistics (colour,
    /// features, their variances and sample counts, and half B's) become the film's, and the
    /// adaptive passes follow, each pixel continuing its own sample sequence. It must be a
    /// path-traced render of this scene with the same seed, sampler (sobol or independent), MIS,
    /// depths and half buffers, of the film's size, every pixel at least at the adaptive start
    /// (minSpp) and at most at spp, no sample discarded, with half buffers when this render
    /// steers by half B and the position layer when it writes one; render() refuses any other
    /// with an error naming continueFrom. Not with a render region. None: from nothing.
    std::shared_ptr<const FrameBuffers> continueFrom;
};

/// The samples every pixel takes before adaptive passes (Settings::minSpp, or its automatic
/// value), at most spp when spp is set.
int adaptiveStartSpp(const Settings& settings);

/// Parses "path" / "mlt"; throws glint::Error(InvalidArgument).
Integrator parseIntegrator(const std::string& name);
/// Parses "power" / "balance" / "none"; throws glint::Error(InvalidArgument).
MisHeuristic parseMis(const std::string& name);
/// Parses "bsdf" / "light"; throws glint::Error(InvalidArgument).
Strategy parseStrategy(const std::string& name);
/// Parses "stratified" / "independent" / "sobol" / "zsobol"; throws
/// glint::Error(InvalidArgument).
SamplerKind parseSampler(const std::string& name);
/// Parses "auto" / "triangles" / "clusters"; throws glint::Error(InvalidArgument).
Accel parseAccel(const std::string& name);
/// Name of an acceleration choice ("auto", "triangles", "clusters").
const char* accelName(Accel accel);
/// Name of a sampler ("stratified", "independent", "sobol", "zsobol").
const char* samplerName(SamplerKind sampler);

/// Parses "half" / "whole"; throws glint::Error(InvalidArgument).
AdaptiveError parseAdaptiveError(const std::string& name);
/// Name of an adaptive error source ("half", "whole").
const char* adaptiveErrorName(AdaptiveError from);

/// Name of an integrator ("path", "mlt").
const char* integratorName(Integrator integrator);
/// Name of a MIS heuristic ("power", "balance", "none").
const char* misName(MisHeuristic mis);
/// Name of a strategy ("bsdf", "light").
const char* strategyName(Strategy strategy);

/// Throws glint::Error(InvalidArgument) naming the first out-of-range field (`where` is the
/// field's name) and its allowed range.
void validate(const Settings& settings);

}  // namespace glint::render
