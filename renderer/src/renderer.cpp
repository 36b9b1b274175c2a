// Renderer: owns the Embree scene, lights and camera; renders progressive passes over tiles
// with TBB. Each pixel's samples are taken in sample-index order by one task, and every random
// number comes from the (seed, pixel, sample) stream, so output does not depend on threads.
#include "glint/render/renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "embree/embree_scene.h"
#include "film/film.h"
#include "glint/image/error.h"
#include "integrators/mlt_integrator.h"
#include "integrators/path_integrator.h"
#include "lights/light_sampler.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

using Clock = std::chrono::steady_clock;

struct Renderer::Impl {
    explicit Impl(const detail::SceneData& scene)
        : embree(scene), lights(scene), camera(scene.camera, scene.width, scene.height) {}
    EmbreeScene embree;
    LightSampler lights;
    Camera camera;
};

Renderer::Renderer(Scene scene) : m_scene(std::move(scene)) {
    GLINT_CHECK(m_scene.width() > 0 && m_scene.height() > 0, "scene has no film");
    m_impl = std::make_unique<Impl>(m_scene.data());
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

namespace {

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

}  // namespace

FrameBuffers Renderer::render(const Settings& settings, const Callbacks& callbacks) {
    validate(settings);
    if (settings.integrator == Integrator::Mlt) {
        // Metropolis (docs/metropolis.md): features from a short path-traced pass, colour and
        // its variance from the Metropolis chains.
        validateMlt(settings.mlt);
        FrameBuffers features = render(mltFeatureSettings(settings));
        MltIntegrator mlt(m_scene.data(), m_impl->embree, m_impl->lights, m_impl->camera, settings);
        return mlt.render(std::move(features), callbacks, m_stats);
    }
    const detail::SceneData& data = m_scene.data();
    const int width = data.width, height = data.height;
    const Clock::time_point start = Clock::now();
    m_stats = RenderStats{};

    Film film(width, height);
    const PathIntegrator integrator(data, m_impl->embree, m_impl->lights, m_impl->camera, settings);
    const Camera& camera = m_impl->camera;
    const bool thinLens = data.camera.lensRadius > 0.0f;
    // Time is sampled only when something moves during a shutter of non-zero length, so a
    // static scene draws exactly the random numbers it drew before motion blur existed.
    const bool sampleTime = data.hasMotion() && data.camera.shutterClose > data.camera.shutterOpen;

    // Tiles in scanline order.
    const int ts = settings.tileSize;
    std::vector<Rect> tiles;
    for (int y = 0; y < height; y += ts)
        for (int x = 0; x < width; x += ts)
            tiles.push_back({x, std::min(x + ts, width), y, std::min(y + ts, height)});

    std::mutex callbackMutex;
    std::atomic<bool> cancelled{false};
    std::atomic<std::uint64_t> rays{0}, samples{0};
    const int threads = settings.threads > 0 ? settings.threads : tbb::task_arena::automatic;
    tbb::task_arena arena(threads);

    const bool timed = settings.timeLimit > 0.0;
    const double deadline = settings.timeLimit;
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

    int done = 0, pass = 0;
    double secondsPerSpp = 0.0;
    while (!cancelled.load()) {
        if (settings.spp > 0 && done >= settings.spp) break;
        if (timed && elapsed() >= deadline) break;
        // Pass sizes double (1, 1, 2, 4, ... up to 64 spp) for quick early feedback; under a time
        // limit they are also cut to what the remaining time allows by the measured rate.
        int count = std::clamp(done, 1, 64);
        if (settings.spp > 0) count = std::min(count, settings.spp - done);
        if (timed && secondsPerSpp > 0.0) {
            const double remaining = deadline - elapsed();
            // Clamped in double: a fast pass on a tiny film gives ratios beyond INT_MAX.
            count = int(std::clamp(remaining / secondsPerSpp, 1.0, double(count)));
        }
        const PassSampler sampler(settings.sampler, settings.seed, done, count);
        const double totalSpp = settings.spp > 0 ? double(settings.spp) : 0.0;
        std::atomic<int> tilesDone{0};
        const double passStart = elapsed();

        arena.execute([&] {
            tbb::parallel_for(
                tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                [&](const tbb::blocked_range<std::size_t>& range) {
                    for (std::size_t ti = range.begin(); ti != range.end(); ++ti) {
                        if (cancelled.load()) return;
                        if (callbacks.cancel) {
                            const std::lock_guard<std::mutex> lock(callbackMutex);
                            if (callbacks.cancel()) cancelled.store(true);
                        }
                        if (cancelled.load()) return;
                        const Rect& tile = tiles[ti];
                        std::uint64_t tileRays = 0;
                        FilmSample fs;
                        for (int y = tile.y0; y < tile.y1; ++y)
                            for (int x = tile.x0; x < tile.x1; ++x) {
                                const auto pixel = std::uint64_t(y) * std::uint64_t(width) + x;
                                for (int s = done; s < done + count; ++s) {
                                    Rng rng(settings.seed, pixel, std::uint64_t(s));
                                    const Vec2 jitter = sampler.point(pixel, s, 0, rng);
                                    const Vec2 lens = thinLens ? sampler.point(pixel, s, 1, rng)
                                                               : Vec2{0.5f, 0.5f};
                                    const float time =
                                        sampleTime ? sampler.value(pixel, s, 2, rng) : 0.0f;
                                    const Ray ray = camera.generateRay(
                                        float(x) + jitter.x, float(y) + jitter.y, lens, time);
                                    integrator.trace(ray, rng, fs, tileRays);
                                    film.add(x, y, fs);
                                }
                            }
                        rays += tileRays;
                        samples += std::uint64_t(tile.width()) * tile.height() * count;
                        const int finished = ++tilesDone;
                        if (callbacks.tileDone || callbacks.progress) {
                            const std::lock_guard<std::mutex> lock(callbackMutex);
                            if (callbacks.tileDone) callbacks.tileDone(tile);
                            if (callbacks.progress) {
                                double fraction;
                                const double passFraction = double(finished) / double(tiles.size());
                                if (totalSpp > 0.0)
                                    fraction = (double(done) + passFraction * count) / totalSpp;
                                else
                                    fraction = std::min(1.0, elapsed() / deadline);
                                callbacks.progress(pass, fraction);
                            }
                        }
                    }
                },
                tbb::simple_partitioner());
        });
        if (cancelled.load()) break;
        secondsPerSpp = (elapsed() - passStart) / double(count);
        done += count;
        ++pass;
        if (callbacks.passDone) {
            FrameBuffers snapshot = film.resolve(settings.position);
            snapshot.metadata().spp = done;
            callbacks.passDone(pass - 1, snapshot);
        }
    }

    FrameBuffers out = film.resolve(settings.position);
    FrameMetadata& meta = out.metadata();
    meta.spp = done;
    meta.seed = settings.seed;
    meta.integrator = integratorName(settings.integrator);
    meta.scene = data.path.string();
    meta.nonFiniteSamples = film.nonFiniteSamples();
    meta.extra["mis"] = misName(settings.mis);
    if (settings.mis == MisHeuristic::None)
        meta.extra["strategy"] = strategyName(settings.strategy);
    meta.extra["maxDepth"] = std::to_string(settings.maxDepth);
    meta.extra["rrDepth"] = std::to_string(settings.rrDepth);
    if (cancelled.load()) meta.extra["cancelled"] = "true";
    if (data.hasMotion()) {
        // Features are then time averages: their variance includes motion (docs/motion-blur.md).
        meta.extra["shutter"] = std::to_string(data.camera.shutterOpen) + " " +
                                std::to_string(data.camera.shutterClose);
        meta.extra["motionBlur"] = "true";
    }

    m_stats.seconds = elapsed();
    m_stats.samples = samples.load();
    m_stats.rays = rays.load();
    m_stats.nonFiniteSamples = meta.nonFiniteSamples;
    m_stats.passes = pass;
    m_stats.completedSpp = done;
    m_stats.cancelled = cancelled.load();
    return out;
}

RayThroughput Renderer::measureRayThroughput(std::uint64_t rayCount, int threads,
                                             std::uint64_t seed) const {
    const detail::SceneData& data = m_scene.data();
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const Vec3& p : data.positions)
        for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    if (data.positions.empty()) lo = hi = Vec3{};
    const std::uint64_t chunk = 4096;
    const std::uint64_t chunks = (rayCount + chunk - 1) / chunk;
    std::atomic<std::uint64_t> hits{0};
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    const Clock::time_point start = Clock::now();
    arena.execute([&] {
        tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
            std::uint64_t localHits = 0;
            const std::uint64_t end = std::min(rayCount, (c + 1) * chunk);
            for (std::uint64_t i = c * chunk; i < end; ++i) {
                Rng rng(seed, c, i);
                Ray ray;
                if (i % 2 == 0) {
                    // Camera ray through a random film point.
                    ray = m_impl->camera.generateRay(rng.uniform() * float(data.width),
                                                     rng.uniform() * float(data.height),
                                                     {0.5f, 0.5f});
                } else {
                    // Random ray: uniform origin in the bounding box, uniform direction.
                    ray.origin = {lo.x + (hi.x - lo.x) * rng.uniform(),
                                  lo.y + (hi.y - lo.y) * rng.uniform(),
                                  lo.z + (hi.z - lo.z) * rng.uniform()};
                    ray.dir = sampleUniformSphere({rng.uniform(), rng.uniform()});
                }
                Hit hit;
                if (m_impl->embree.intersect(ray, std::numeric_limits<float>::infinity(), hit))
                    ++localHits;
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
