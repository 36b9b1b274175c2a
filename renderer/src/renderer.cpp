// Renderer: owns the Embree scene, lights and camera, and orchestrates a render: checks the
// settings, then runs the integrators' passes (integrators/path_passes.h, mlt_passes.h) through
// the shared RenderLoop and records the frame's metadata and statistics.
#include "glint/render/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "embree/embree_scene.h"
#include "film/continued_frame.h"
#include "film/film.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "glint/image/shard.h"
#include "glint/render/importance_map.h"
#include "glint/render/settings_codec.h"
#include "integrators/mlt_integrator.h"
#include "integrators/path_integrator.h"
#include "integrators/path_passes.h"
#include "integrators/render_loop.h"
#include "lights/light_sampler.h"
#include "renderer_detail.h"
#include "sampling/rng.h"
#include "sampling/sobol.h"
#include "sampling/warp.h"
#include "scene/camera.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/scene_hash.h"

namespace glint::render {

using Clock = std::chrono::steady_clock;

namespace {

/// "a 640x480 path render": the film a memory message names.
std::string filmDescription(const detail::SceneData& data, const Settings& settings) {
    return "a " + std::to_string(data.width) + "x" + std::to_string(data.height) + " " +
           integratorName(settings.integrator) + " render";
}

/// What a render may allocate: an explicit limit, which what the scene holds counts against, or
/// the machine's available memory, from which it is already spent.
struct MemoryBudget {
    explicit MemoryBudget(const Settings& settings)
        : machine(settings.memoryLimit == 0),
          allowed(machine ? availableMemory() : settings.memoryLimit) {}
    std::uint64_t needs(std::uint64_t film, const SceneMemory& scene) const {
        return saturatingAdd(film, machine ? scene.added() : scene.total());
    }
    bool fits(std::uint64_t film, const SceneMemory& scene) const {
        return needs(film, scene) <= allowed;
    }
    bool machine;
    std::uint64_t allowed;
};

}  // namespace

struct Renderer::Impl {
    Impl(const detail::SceneData& scene, Accel accel)
        : embree(scene, accel),
          lights(scene),
          camera(scene.camera, scene.width, scene.height),
          lookRevision(scene.lookRevision) {}
    EmbreeScene embree;
    LightSampler lights;
    Camera camera;
    std::uint64_t lookRevision;  // of the scene when `lights` was built
    int accelerationBuilds = 1;
    int lightBuilds = 1;
};

Renderer::Renderer(Scene scene) : m_scene(std::move(scene)) {
    build(m_scene.settings().accel);
}

Renderer::Renderer(Scene scene, Accel accel) : m_scene(std::move(scene)) {
    build(accel);
}

Renderer::Renderer(Scene scene, const Settings& settings) : m_scene(std::move(scene)) {
    build(accelWithin(settings));
}

Accel Renderer::accelWithin(const Settings& settings) const {
    GLINT_CHECK(m_scene.width() > 0 && m_scene.height() > 0, "scene has no film");
    validate(settings);
    const detail::SceneData& data = detail::sceneData(m_scene);
    const std::uint64_t film = estimateMemory(settings);
    checkMemory(film, settings.memoryLimit, filmDescription(data, settings), data.path.string(),
                "/film");
    const MemoryBudget budget(settings);
    const SceneMemory asked = estimateSceneMemory(m_scene, settings.accel, settings.textureCacheMb);
    if (budget.fits(film, asked)) return asked.accel;
    // Clusters hold the same triangles in about a third of the memory (docs/renderer.md).
    if (settings.accel == Accel::Auto && asked.accel == Accel::Triangles &&
        budget.fits(film, estimateSceneMemory(m_scene, Accel::Clusters, settings.textureCacheMb)))
        return Accel::Clusters;
    checkSceneMemory(film, asked, settings);
    return asked.accel;
}

void Renderer::checkSceneMemory(std::uint64_t film, const SceneMemory& scene,
                                const Settings& settings) const {
    const MemoryBudget budget(settings);
    if (budget.fits(film, scene)) return;
    const detail::SceneData& data = detail::sceneData(m_scene);
    const char* over = scene.accel == Accel::Clusters ? "clusters" : "Embree's triangles";
    const std::uint64_t textures =
        budget.machine ? scene.textureCache : saturatingAdd(scene.images, scene.textureCache);
    std::string msg =
        "the scene (" + std::to_string(data.triangleCount()) + " triangles) and " +
        filmDescription(data, settings) + " need " + formatBytes(budget.needs(film, scene)) + " (" +
        (budget.machine ? "" : "meshes " + formatBytes(scene.meshes) + ", ") + "BVH over " + over +
        " " + formatBytes(scene.structures) + ", textures " + formatBytes(textures) + ", film " +
        formatBytes(film) + ") but only " + formatBytes(budget.allowed) +
        (budget.machine ? " is available on this machine" : " is allowed (memory limit)");
    // What would help.
    if (scene.accel == Accel::Triangles) {
        const std::uint64_t clusters = budget.needs(
            film, estimateSceneMemory(m_scene, Accel::Clusters, settings.textureCacheMb));
        msg += "; over clusters (--set accel=clusters) it would " +
               std::string(clusters <= budget.allowed ? "need " : "still need ") +
               formatBytes(clusters) + (clusters <= budget.allowed ? ", which fits" : "");
    }
    if (scene.textureCache > budget.allowed / 4)
        msg += "; a smaller texture cache (--texture-cache-mb) needs less";
    throw Error(ErrorKind::OutOfMemory, msg + "; nothing was built", data.path.string(), "/shapes");
}

Accel Renderer::accel() const {
    return m_impl->embree.clusteredMeshCount() > 0 ? Accel::Clusters : Accel::Triangles;
}

void Renderer::build(Accel accel) {
    GLINT_CHECK(m_scene.width() > 0 && m_scene.height() > 0, "scene has no film");
    const detail::SceneData& data = detail::sceneData(m_scene);
    // A camera without a view basis would send NaN rays into Embree: refuse it before building.
    checkCamera(data);
    m_impl = std::make_unique<Impl>(data, accel);
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

namespace detail {

/// The renderer's private state, for the hooks of renderer_detail.h.
struct RendererAccess {
    static const Renderer::Impl& impl(const Renderer& renderer) { return *renderer.m_impl; }
};

int accelerationBuilds(const Renderer& renderer) {
    return RendererAccess::impl(renderer).accelerationBuilds;
}

AccelerationMemory accelerationMemory(const Renderer& renderer) {
    const EmbreeScene& embree = RendererAccess::impl(renderer).embree;
    const EmbreeMemory m = embree.memory();
    return {m.current, m.peak, std::int64_t(embree.clusterOrderBytes()),
            embree.clusteredMeshCount(), embree.clusterSize()};
}

int lightBuilds(const Renderer& renderer) {
    return RendererAccess::impl(renderer).lightBuilds;
}

}  // namespace detail

namespace {

/// Whether the film keeps half B's statistics without writing them: adaptive sampling estimates
/// the error from them.
bool keepsHalf(const Settings& settings) {
    return settings.adaptive && settings.adaptiveError == AdaptiveError::Half;
}

/// Path-traces `settings` through the render loop, reporting progress in [begin, end].
RenderResult renderPath(const detail::SceneData& data, const EmbreeScene& embree,
                        const LightSampler& lights, const Camera& camera, const Settings& settings,
                        const Callbacks& callbacks, tbb::task_arena& arena, double begin,
                        double end, bool reportPasses) {
    const Clock::time_point start = Clock::now();
    Film film(data.width, data.height, settings.halfBuffers, keepsHalf(settings));
    const PathIntegrator integrator(data, embree, lights, camera, settings);
    PathPasses work(data, integrator, camera, settings, film);
    RenderLoop loop(settings.spp, settings.timeLimit, callbacks, arena, begin, end);
    if (settings.adaptive) loop.setAdaptive(adaptiveStartSpp(settings));
    if (settings.continueFrom) {
        // The loop goes on where the frame's fullest pixel is.
        const int spp =
            checkContinuedFrame(*settings.continueFrom, settings, data.width, data.height,
                                adaptiveStartSpp(settings), keepsHalf(settings));
        film.continueFrom(*settings.continueFrom);
        loop.continueAt(spp);
    }
    // A shard takes its range of every pixel's samples; the passes stay those of the whole
    // render, so a stratified pass stratifies over the same block (docs/distributed.md).
    std::optional<ShardInfo> shard;
    if (settings.shard) {
        shard = ShardInfo{settings.shard->index, settings.shard->count, settings.spp, 0, 0, 0};
        std::tie(shard->sampleBegin, shard->sampleEnd) =
            shardSampleRange(settings.spp, shard->index, shard->count);
        loop.restrictSamples(shard->sampleBegin, shard->sampleEnd);
    }
    const LoopResult done = loop.run(work, reportPasses);

    RenderResult result;
    result.frame = film.resolve(settings.positionLayer);
    FrameMetadata& meta = result.frame.metadata();
    recordSettings(settings, meta);
    meta.spp = done.completedSpp;
    meta.scene = data.path.string();
    meta.nonFiniteSamples = film.nonFiniteSamples();
    if (done.cancelled) meta.extra["cancelled"] = "true";
    if (shard) {
        shard->sceneHash = sceneContentHash(data);
        setShardInfo(meta, *shard);
    }
    if (data.hasMotion()) {
        // Features are then time averages: their variance includes motion (docs/motion-blur.md).
        meta.extra["shutter"] = std::to_string(data.camera.shutterOpen) + " " +
                                std::to_string(data.camera.shutterClose);
        meta.extra["motionBlur"] = "true";
    }

    RenderStats& stats = result.stats;
    stats.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    stats.samples = done.samples;
    stats.rays = work.rays();
    stats.nonFiniteSamples = meta.nonFiniteSamples;
    stats.passes = done.passes;
    stats.completedSpp = done.completedSpp;
    stats.cancelled = done.cancelled;
    return result;
}

}  // namespace

std::uint64_t Renderer::estimateMemory(const Settings& settings) const {
    const detail::SceneData& data = detail::sceneData(m_scene);
    const std::uint64_t pixels = std::uint64_t(data.width) * std::uint64_t(data.height);
    // A resolved frame: every layer but the optional position and half buffer (and the noisy
    // layer, a denoiser's), 4-byte floats.
    std::uint64_t frameChannels = 0;
    for (int l = 0; l < kLayerCount; ++l)
        if (Layer(l) != Layer::Noisy && (Layer(l) != Layer::Position || settings.positionLayer) &&
            (!isHalfLayer(Layer(l)) || settings.halfBuffers))
            frameChannels += std::uint64_t(layerInfo(Layer(l)).channels);
    const std::uint64_t frame = frameChannels * sizeof(float);
    // The film, the frame it resolves to, and the copy a pass observer may be handed.
    std::uint64_t perPixel =
        Film::bytesPerPixel(settings.halfBuffers || keepsHalf(settings)) + 2 * frame;
    // Adaptive sampling's two masks (converged, chosen).
    if (settings.adaptive) perPixel += 2;
    if (settings.integrator == Integrator::Mlt) {
        // The feature frame kept beside the colour, and each group's splats (3 doubles).
        perPixel += frame + std::uint64_t(std::max(settings.mlt.groups, 1)) * 3 * sizeof(double);
    }
    return saturatingMul(pixels, perPixel);
}

RenderResult Renderer::render(const Settings& settings, const Callbacks& callbacks) {
    validate(settings);
    const detail::SceneData& data = detail::sceneData(m_scene);
    if (settings.region &&
        intersect(*settings.region, Rect{0, data.width, 0, data.height}) != *settings.region)
        throw Error(ErrorKind::InvalidArgument,
                    "the render region lies outside the " + std::to_string(data.width) + "x" +
                        std::to_string(data.height) + " film",
                    {}, "region");
    if (settings.importance) checkImportanceMap(*settings.importance, data.width, data.height);
    if (settings.sampler == SamplerKind::ZSobol) {
        const auto [log2Res, log2Spp] = zsobolLayout(data, settings);
        const int bits = 2 * log2Res + log2Spp;
        if (bits > 32)
            throw Error(ErrorKind::InvalidArgument,
                        "the zsobol sampler indexes a " + std::to_string(data.width) + "x" +
                            std::to_string(data.height) + " film at " +
                            std::to_string(settings.spp) + " spp with " + std::to_string(bits) +
                            " bits, more than its 32 (use the sobol sampler)",
                        {}, "sampler");
    }
    // Refuse a frame the machine cannot hold before allocating any of it; a limit given counts
    // the scene too.
    const std::uint64_t film = estimateMemory(settings);
    checkMemory(film, settings.memoryLimit, filmDescription(data, settings), data.path.string(),
                "/film");
    if (settings.memoryLimit > 0)
        checkSceneMemory(film, estimateSceneMemory(m_scene, accel(), settings.textureCacheMb),
                         settings);
    // Look edits since the last render: rebuild the lights, keep the BVH.
    if (data.lookRevision != m_impl->lookRevision) {
        m_impl->lights = LightSampler(data);
        m_impl->lookRevision = data.lookRevision;
        ++m_impl->lightBuilds;
    }
    // Texture tiles: the cache this render may fill; a tile that fails to read mid-render
    // (lookups cannot throw inside Embree's callbacks) is reported once the render ends.
    const std::shared_ptr<detail::TextureStore>& textures = data.textureStore;
    if (textures) {
        textures->setCacheMb(settings.textureCacheMb);
        textures->clearFailure();
    }
    auto checked = [&textures](RenderResult result) {
        if (textures) textures->throwIfFailed();
        return result;
    };
    const int threads = settings.threads > 0 ? settings.threads : tbb::task_arena::automatic;
    tbb::task_arena arena(threads);
    if (settings.integrator == Integrator::Path)
        return checked(renderPath(data, m_impl->embree, m_impl->lights, m_impl->camera, settings,
                                  callbacks, arena, 0.0, 1.0, true));

    // Metropolis (docs/metropolis.md): features from a short path-traced pass (the first part
    // of the progress, cancellable like the rest), colour and its variance from the chains.
    validateMlt(settings.mlt);
    const Settings featureSettings = mltFeatureSettings(settings);
    const double featureShare =
        settings.spp > 0 ? double(featureSettings.spp) / double(featureSettings.spp + settings.spp)
                         : 0.05;
    RenderResult features = renderPath(data, m_impl->embree, m_impl->lights, m_impl->camera,
                                       featureSettings, callbacks, arena, 0.0, featureShare, false);
    MltIntegrator mlt(data, m_impl->embree, m_impl->lights, m_impl->camera, settings);
    if (features.stats.cancelled) {
        // Stopped during the feature pass: the features it has, no colour.
        features.frame.color().fill(0.0f);
        features.frame.ensure(Layer::Variance).fill(0.0f);
        features.frame.metadata().spp = 0;
        features.frame.metadata().integrator = integratorName(Integrator::Mlt);
        features.stats.completedSpp = 0;
        features.stats.passes = 0;
        return checked(std::move(features));
    }
    const double budget = settings.timeLimit > 0.0
                              ? std::max(settings.timeLimit - features.stats.seconds, 1e-9)
                              : 0.0;
    RenderResult result;
    result.stats = features.stats;
    result.frame =
        mlt.render(std::move(features.frame), callbacks, arena, budget, featureShare, result.stats);
    return checked(std::move(result));
}

detail::RayThroughput detail::measureRayThroughput(const Renderer& renderer, std::uint64_t rayCount,
                                                   int threads, std::uint64_t seed, bool packets) {
    const auto& impl = RendererAccess::impl(renderer);
    const SceneData& data = sceneData(renderer.scene());
    const Vec3 lo = data.bounds.empty() ? Vec3{} : data.bounds.lo;
    const Vec3 hi = data.bounds.empty() ? Vec3{} : data.bounds.hi;
    const std::uint64_t chunk = 4096;
    const std::uint64_t chunks = (rayCount + chunk - 1) / chunk;
    std::atomic<std::uint64_t> hits{0};
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    const Clock::time_point start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
            std::uint64_t localHits = 0;
            const std::uint64_t end = std::min(rayCount, (c + 1) * chunk);
            std::vector<Ray> batch;
            for (std::uint64_t i = c * chunk; i < end; ++i) {
                Rng rng(seed, c, i);
                Ray& ray = batch.emplace_back();
                if (i % 2 == 0) {
                    // Camera ray through a random film point.
                    ray = impl.camera.generateRay(rng.uniform() * float(data.width),
                                                  rng.uniform() * float(data.height), {0.5f, 0.5f});
                } else {
                    // Random ray: uniform origin in the bounding box, uniform direction.
                    ray.origin = {lo.x + (hi.x - lo.x) * rng.uniform(),
                                  lo.y + (hi.y - lo.y) * rng.uniform(),
                                  lo.z + (hi.z - lo.z) * rng.uniform()};
                    ray.dir = sampleUniformSphere({rng.uniform(), rng.uniform()});
                }
                if (packets) continue;
                Hit hit;
                if (impl.embree.intersect(ray, std::numeric_limits<float>::infinity(), hit))
                    ++localHits;
            }
            if (packets) {
                std::vector<const Ray*> pointers;
                for (const Ray& r : batch) pointers.push_back(&r);
                std::vector<Hit> found(batch.size());
                std::unique_ptr<bool[]> hit(new bool[batch.size()]);
                impl.embree.intersectMany(batch.size(), pointers.data(), found.data(), hit.get(),
                                          false);
                for (std::size_t k = 0; k < batch.size(); ++k) localHits += hit[k];
            }
            hits += localHits;
        });
    });
    RayThroughput result;
    result.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    result.rays = rayCount;
    result.hits = hits.load();
    return result;
}

}  // namespace glint::render
