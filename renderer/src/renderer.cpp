// Renderer: owns the Embree scene, lights and camera; renders progressive passes over tiles
// through the shared RenderLoop. Each pixel's samples are taken in sample-index order by one
// task, and every random number comes from the (seed, pixel, sample) stream, so output does not
// depend on threads.
#include "glint/render/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <tuple>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "embree/embree_scene.h"
#include "film/film.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "glint/image/shard.h"
#include "integrators/mlt_integrator.h"
#include "integrators/path_integrator.h"
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

struct Renderer::Impl {
    explicit Impl(const detail::SceneData& scene)
        : embree(scene),
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
    GLINT_CHECK(m_scene.width() > 0 && m_scene.height() > 0, "scene has no film");
    m_impl = std::make_unique<Impl>(detail::sceneData(m_scene));
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

int lightBuilds(const Renderer& renderer) {
    return RendererAccess::impl(renderer).lightBuilds;
}

}  // namespace detail

namespace {

/// ZSobol's index layout (log2Res, log2Spp): the film's larger side and a pixel's samples (a
/// half's, with half buffers) in bits.
std::pair<int, int> zsobolLayout(const detail::SceneData& data, const Settings& settings) {
    const int perPixel = settings.halfBuffers ? (settings.spp + 1) / 2 : settings.spp;
    return {ceilLog2(std::uint32_t(std::max(data.width, data.height))),
            ceilLog2(std::uint32_t(std::max(perPixel, 1)))};
}

/// Pixel-sample placement of one pass: `count` samples starting at `first`, stratified over a
/// jittered grid (one random cell of a ceil(√n) × ⌈n/⌈√n⌉⌉ grid per sample, cells drawn without
/// repetition by a per-pixel permutation) or independent.
struct PassSampler {
    SamplerKind kind;
    std::uint64_t seed;
    int first, count, nx, ny;

    PassSampler(SamplerKind k, std::uint64_t s, int firstSample, int n)
        : kind(k), seed(s), first(firstSample), count(n) {
        nx = int(std::ceil(std::sqrt(double(n))));
        ny = (n + nx - 1) / nx;
    }

    /// Stratified 2D point for sample `sample` of pixel `pixel` in dimension pair `dim`.
    Vec2 point(std::uint64_t pixel, int sample, int dim, Rng& rng) const {
        const Vec2 jitter{rng.uniform(), rng.uniform()};
        if (kind == SamplerKind::Independent || count == 1) return jitter;
        const auto key = std::uint32_t(mix64(streamKey(seed, pixel, std::uint64_t(first)) +
                                             std::uint64_t(dim) * 0x2545f491ULL));
        const std::uint32_t cell =
            permuteIndex(std::uint32_t(sample - first), std::uint32_t(nx * ny), key);
        const int cx = int(cell % std::uint32_t(nx)), cy = int(cell / std::uint32_t(nx));
        return {std::min((float(cx) + jitter.x) / float(nx), 0x1.fffffep-1f),
                std::min((float(cy) + jitter.y) / float(ny), 0x1.fffffep-1f)};
    }

    /// Stratified 1D value for sample `sample` of pixel `pixel` in dimension `dim`: one random
    /// stratum of `count` per sample, drawn without repetition by its own permutation.
    float value(std::uint64_t pixel, int sample, int dim, Rng& rng) const {
        const float jitter = rng.uniform();
        if (kind == SamplerKind::Independent || count == 1) return jitter;
        const auto key = std::uint32_t(mix64(streamKey(seed, pixel, std::uint64_t(first)) +
                                             std::uint64_t(dim) * 0x2545f491ULL));
        const std::uint32_t stratum =
            permuteIndex(std::uint32_t(sample - first), std::uint32_t(count), key);
        return std::min((float(stratum) + jitter) / float(count), 0x1.fffffep-1f);
    }
};

/// The path tracer's work for the render loop: item i traces tile i's pixels for one pass,
/// each pixel's samples in sample-index order, every random number from (seed, pixel, sample).
class TilePasses final : public PassWork {
  public:
    TilePasses(const detail::SceneData& data, const PathIntegrator& integrator,
               const Camera& camera, const Settings& settings, Film& film)
        : m_data(data),
          m_integrator(integrator),
          m_camera(camera),
          m_settings(settings),
          m_film(film) {
        // Tiles in scanline order, on a grid fixed in film coordinates, clipped to the region.
        const int ts = settings.tileSize;
        const Rect region = settings.region.value_or(Rect{0, data.width, 0, data.height});
        for (int y = 0; y < data.height; y += ts)
            for (int x = 0; x < data.width; x += ts) {
                const Rect tile = intersect(
                    {x, std::min(x + ts, data.width), y, std::min(y + ts, data.height)}, region);
                if (!tile.empty()) m_tiles.push_back(tile);
            }
        m_thinLens = data.camera.lensRadius > 0.0f;
        // Time is sampled only when something moves during a shutter of non-zero length, so a
        // static scene draws exactly the random numbers it drew before motion blur existed.
        m_sampleTime = data.hasMotion() && data.camera.shutterClose > data.camera.shutterOpen;
        // The two halves' scramble seeds: independent of each other and of the whole render's.
        for (int h = 0; h < 2; ++h)
            m_halfSeed[h] = hash64(hash64(settings.seed, 0x4a1fb0ffULL), std::uint64_t(h));
        std::tie(m_log2Res, m_log2Spp) = zsobolLayout(data, settings);
    }

    std::size_t items() const override { return m_tiles.size(); }
    std::optional<Rect> itemRect(std::size_t item) const override { return m_tiles[item]; }

    void run(const PassInfo& pass, std::size_t item, const RenderLoop&) override {
        if (m_settings.sampler == SamplerKind::Sobol)
            runBatches<SobolSampler>(pass, m_tiles[item]);
        else if (m_settings.sampler == SamplerKind::ZSobol)
            runBatches<ZSobolSampler>(pass, m_tiles[item]);
        else
            runBatches<Rng>(pass, m_tiles[item]);
    }

    FrameBuffers snapshot() override { return m_film.resolve(m_settings.positionLayer); }

    std::uint64_t rays() const { return m_rays.load(); }

  private:
    /// Paths traced together (PathIntegrator::traceMany): enough for full packets at the
    /// deeper bounces, few enough that their states stay in the core's cache.
    static constexpr std::size_t kBatch = 512;

    /// The sampler of sample `s` of pixel (x, y) and its camera ray.
    Ray cameraSample(const PassSampler&, int x, int y, int s,
                     std::vector<SobolSampler>& samplers) const {
        const auto pixel = std::uint64_t(y) * std::uint64_t(m_data.width) + x;
        // Every dimension from its own scrambled Sobol sequence (sampling/sobol.h); with half
        // buffers, sample s is sample s/2 of half s mod 2's own scramble.
        const SobolSampler& sobol = samplers.emplace_back(
            m_settings.halfBuffers ? SobolSampler(m_halfSeed[s & 1], pixel, std::uint32_t(s >> 1))
                                   : SobolSampler(m_settings.seed, pixel, std::uint32_t(s)));
        return slottedCameraRay(sobol, x, y);
    }
    Ray cameraSample(const PassSampler&, int x, int y, int s,
                     std::vector<ZSobolSampler>& samplers) const {
        // With half buffers, sample s is sample s/2 of half s mod 2's own scramble.
        return slottedCameraRay(
            samplers.emplace_back(m_settings.halfBuffers ? m_halfSeed[s & 1] : m_settings.seed, x,
                                  y, std::uint32_t(m_settings.halfBuffers ? s >> 1 : s), m_log2Res,
                                  m_log2Spp),
            x, y);
    }
    /// The camera ray of pixel (x, y) from a sampler's camera slots (film, lens, time).
    template <class Slotted>
    Ray slottedCameraRay(const Slotted& sampler, int x, int y) const {
        const Vec2 jitter = sampler.camera2D(0);
        const Vec2 lens = m_thinLens ? sampler.camera2D(1) : Vec2{0.5f, 0.5f};
        const float time = m_sampleTime ? sampler.camera1D(2) : 0.0f;
        return m_camera.generateRay(float(x) + jitter.x, float(y) + jitter.y, lens, time);
    }
    Ray cameraSample(const PassSampler& sampler, int x, int y, int s,
                     std::vector<Rng>& samplers) const {
        const auto pixel = std::uint64_t(y) * std::uint64_t(m_data.width) + x;
        Rng& rng = samplers.emplace_back(m_settings.seed, pixel, std::uint64_t(s));
        const Vec2 jitter = sampler.point(pixel, s, 0, rng);
        const Vec2 lens = m_thinLens ? sampler.point(pixel, s, 1, rng) : Vec2{0.5f, 0.5f};
        const float time = m_sampleTime ? sampler.value(pixel, s, 2, rng) : 0.0f;
        return m_camera.generateRay(float(x) + jitter.x, float(y) + jitter.y, lens, time);
    }

    /// The tile's pixels for one pass, each pixel's samples in sample-index order, traced in
    /// batches of kBatch paths and added to the film in that same order.
    template <class Sampler>
    void runBatches(const PassInfo& pass, const Rect& tile) {
        const PassSampler sampler(m_settings.sampler, m_settings.seed, pass.first, pass.count);
        std::uint64_t tileRays = 0;
        struct Target {
            int x, y;
            bool odd;
        };
        std::vector<Sampler> samplers;
        std::vector<Ray> cameraRays;
        std::vector<Target> targets;
        std::vector<FilmSample> results(kBatch);
        samplers.reserve(kBatch);
        cameraRays.reserve(kBatch);
        targets.reserve(kBatch);
        auto flush = [&] {
            m_integrator.traceMany(cameraRays.size(), cameraRays.data(), samplers.data(),
                                   results.data(), tileRays);
            for (std::size_t i = 0; i < targets.size(); ++i)
                m_film.add(targets[i].x, targets[i].y, results[i], targets[i].odd);
            samplers.clear();
            cameraRays.clear();
            targets.clear();
        };
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
                for (int s = pass.begin; s < pass.end; ++s) {
                    cameraRays.push_back(cameraSample(sampler, x, y, s, samplers));
                    targets.push_back({x, y, (s & 1) != 0});
                    if (targets.size() == kBatch) flush();
                }
        if (!targets.empty()) flush();
        m_rays += tileRays;
    }

    const detail::SceneData& m_data;
    const PathIntegrator& m_integrator;
    const Camera& m_camera;
    const Settings& m_settings;
    Film& m_film;
    std::vector<Rect> m_tiles;
    bool m_thinLens, m_sampleTime;
    std::uint64_t m_halfSeed[2];
    int m_log2Res = 0, m_log2Spp = 0;
    std::atomic<std::uint64_t> m_rays{0};
};

/// Path-traces `settings` through the render loop, reporting progress in [begin, end].
RenderResult renderPath(const detail::SceneData& data, const EmbreeScene& embree,
                        const LightSampler& lights, const Camera& camera, const Settings& settings,
                        const Callbacks& callbacks, tbb::task_arena& arena, double begin,
                        double end, bool reportPasses) {
    const Clock::time_point start = Clock::now();
    Film film(data.width, data.height, settings.halfBuffers);
    const PathIntegrator integrator(data, embree, lights, camera, settings);
    TilePasses work(data, integrator, camera, settings, film);
    RenderLoop loop(settings.spp, settings.timeLimit, callbacks, arena, begin, end);
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
    meta.spp = done.completedSpp;
    meta.seed = settings.seed;
    meta.integrator = integratorName(settings.integrator);
    meta.scene = data.path.string();
    meta.nonFiniteSamples = film.nonFiniteSamples();
    meta.extra["mis"] = misName(settings.mis);
    meta.extra["sampler"] = samplerName(settings.sampler);
    if (settings.mis == MisHeuristic::None)
        meta.extra["strategy"] = strategyName(settings.strategy);
    meta.extra["maxDepth"] = std::to_string(settings.maxDepth);
    meta.extra["rrDepth"] = std::to_string(settings.rrDepth);
    if (settings.halfBuffers) meta.extra["halfBuffers"] = "true";
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
    // A resolved frame: every layer but the optional position and half buffer, 4-byte floats.
    std::uint64_t frameChannels = 0;
    for (int l = 0; l < kLayerCount; ++l)
        if ((Layer(l) != Layer::Position || settings.positionLayer) &&
            (!isHalfLayer(Layer(l)) || settings.halfBuffers))
            frameChannels += std::uint64_t(layerInfo(Layer(l)).channels);
    const std::uint64_t frame = frameChannels * sizeof(float);
    // The film, the frame it resolves to, and the copy a pass observer may be handed.
    std::uint64_t perPixel = Film::bytesPerPixel(settings.halfBuffers) + 2 * frame;
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
    // Refuse a frame the machine cannot hold before allocating any of it.
    checkMemory(estimateMemory(settings), settings.memoryLimit,
                "a " + std::to_string(data.width) + "x" + std::to_string(data.height) + " " +
                    integratorName(settings.integrator) + " render",
                data.path.string(), "/film");
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
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    bool any = false;
    for (const Instance& inst : data.instances)
        for (const Vec3& q : data.meshes[inst.mesh].positions) {
            const Vec3 p = inst.identity ? q : inst.transform.point(q);
            for (int c = 0; c < 3; ++c)
                lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
            any = true;
        }
    if (!any) lo = hi = Vec3{};
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
