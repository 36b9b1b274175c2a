#include "integrators/path_passes.h"

#include <algorithm>
#include <tuple>

#include "glint/render/importance_map.h"
#include "sampling/rng.h"
#include "sampling/sobol.h"
#include "sampling/stratified_sampler.h"

namespace glint::render {

namespace {
/// Paths traced together (PathIntegrator::traceMany): enough for full packets at the deeper
/// bounces, few enough that their states stay in the core's cache.
constexpr std::size_t kBatch = 512;
}  // namespace

std::pair<int, int> zsobolLayout(const detail::SceneData& data, const Settings& settings) {
    const int perPixel = settings.halfBuffers ? (settings.spp + 1) / 2 : settings.spp;
    return {ceilLog2(std::uint32_t(std::max(data.width, data.height))),
            ceilLog2(std::uint32_t(std::max(perPixel, 1)))};
}

PathPasses::PathPasses(const detail::SceneData& data, const PathIntegrator& integrator,
                       const Camera& camera, const Settings& settings, Film& film)
    : m_data(data), m_integrator(integrator), m_camera(camera), m_settings(settings), m_film(film) {
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
    if (settings.adaptive) {
        m_active.assign(std::size_t(data.width) * std::size_t(data.height), 0);
        m_tileActive.assign(m_tiles.size(), 0);
        m_tileSamples.assign(m_tiles.size(), 0);
        m_regionPixels = std::uint64_t(region.width()) * std::uint64_t(region.height());
        m_maxSpp = settings.spp > 0 ? settings.spp : kMaxSpp;
        m_importance = settings.importance;
    }
}

void PathPasses::setImportance(std::shared_ptr<const Image> weights) {
    checkImportanceMap(*weights, m_data.width, m_data.height, "Callbacks::importance");
    m_importance = std::move(weights);
}

std::uint64_t PathPasses::planAdaptivePass() {
    const int w = m_data.width, h = m_data.height;
    const Rect region = m_settings.region.value_or(Rect{0, w, 0, h});
    const Image* weights = m_importance.get();
    // Cycles' noise threshold is compared with 5x its error (its "more intuitive values").
    const double threshold = 5.0 * m_settings.noiseThreshold;
    // Per pixel: 0 converged, 1 not converged (the error estimate, times the pixel's weight, is
    // above the threshold), 2 weight 0 (only the start, whatever its error, even infinite).
    std::vector<std::uint8_t> state(m_active.size(), 0);
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) {
            const double weight = weights ? double((*weights)(x, y, 0)) : 1.0;
            state[std::size_t(y) * w + x] =
                weight <= 0.0                                                               ? 2
                : m_film.adaptiveError(x, y, m_settings.adaptiveError) * weight > threshold ? 1
                                                                                            : 0;
        }
    // The pass: the pixels not converged and their eight neighbours (Cycles' filter of the
    // convergence mask), within the region, of weight > 0 and below spp.
    std::uint64_t active = 0;
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) {
            bool near = false;
            for (int dy = -1; dy <= 1 && !near; ++dy)
                for (int dx = -1; dx <= 1 && !near; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    near = nx >= region.x0 && nx < region.x1 && ny >= region.y0 && ny < region.y1 &&
                           state[std::size_t(ny) * w + nx] == 1;
                }
            const std::size_t i = std::size_t(y) * w + x;
            const bool take = near && state[i] != 2 && int(m_film.taken(x, y)) < m_maxSpp;
            m_active[i] = take;
            active += take;
        }
    for (std::size_t t = 0; t < m_tiles.size(); ++t) {
        std::uint32_t open = 0;
        const Rect& tile = m_tiles[t];
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) open += m_active[std::size_t(y) * w + x];
        m_tileActive[t] = open;
    }
    return active;
}

void PathPasses::run(const PassInfo& pass, std::size_t item, const RenderLoop&) {
    // A tile with no open pixel: nothing to set up.
    if (pass.adaptive && m_tileActive[item] == 0) {
        m_tileSamples[item] = 0;
        return;
    }
    const bool halves = m_settings.halfBuffers;
    const std::uint64_t seed = m_settings.seed;
    // With half buffers, sample s is sample s/2 of half s mod 2's own scramble.
    switch (m_settings.sampler) {
        case SamplerKind::Sobol:
            // Every dimension from its own scrambled Sobol sequence (sampling/sobol.h).
            runBatches(pass, item, [&](std::uint64_t pixel, int, int, int s) {
                return halves ? SobolSampler(m_halfSeed[s & 1], pixel, std::uint32_t(s >> 1))
                              : SobolSampler(seed, pixel, std::uint32_t(s));
            });
            break;
        case SamplerKind::ZSobol:
            runBatches(pass, item, [&](std::uint64_t, int x, int y, int s) {
                return ZSobolSampler(halves ? m_halfSeed[s & 1] : seed, x, y,
                                     std::uint32_t(halves ? s >> 1 : s), m_log2Res, m_log2Spp);
            });
            break;
        case SamplerKind::Stratified:
        case SamplerKind::Independent: {
            const StratifiedPattern pattern(m_settings.sampler, seed, pass.first, pass.count);
            runBatches(pass, item, [&](std::uint64_t pixel, int, int, int s) {
                return StratifiedSampler(pattern, seed, pixel, s);
            });
            break;
        }
    }
}

FrameBuffers PathPasses::snapshot() {
    return m_film.resolve(m_settings.positionLayer);
}

template <PixelSampler Sampler>
Ray PathPasses::cameraRay(Sampler& sampler, int x, int y) const {
    const Vec2 jitter = sampler.camera2D(0);
    const Vec2 lens = m_thinLens ? sampler.camera2D(1) : Vec2{0.5f, 0.5f};
    const float time = m_sampleTime ? sampler.camera1D(2) : 0.0f;
    return m_camera.generateRay(float(x) + jitter.x, float(y) + jitter.y, lens, time);
}

template <class MakeSampler>
void PathPasses::runBatches(const PassInfo& pass, std::size_t item,
                            const MakeSampler& makeSampler) {
    const Rect& tile = m_tiles[item];
    std::uint64_t adaptiveSamples = 0;
    using Sampler = decltype(makeSampler(std::uint64_t(0), 0, 0, 0));
    static_assert(PixelSampler<Sampler>);
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
        for (int x = tile.x0; x < tile.x1; ++x) {
            const auto pixel = std::uint64_t(y) * std::uint64_t(m_data.width) + x;
            int begin = pass.begin, end = pass.end;
            if (pass.adaptive) {
                // A chosen pixel continues its own sequence: its next sample index is the
                // number it has taken.
                if (!m_active[pixel]) continue;
                begin = int(m_film.taken(x, y));
                end = std::min(begin + pass.count, m_maxSpp);
                adaptiveSamples += std::uint64_t(end - begin);
            }
            for (int s = begin; s < end; ++s) {
                // The path continues from the sampler the camera ray drew from.
                Sampler& sampler = samplers.emplace_back(makeSampler(pixel, x, y, s));
                cameraRays.push_back(cameraRay(sampler, x, y));
                targets.push_back({x, y, (s & 1) != 0});
                if (targets.size() == kBatch) flush();
            }
        }
    if (!targets.empty()) flush();
    m_rays += tileRays;
    if (pass.adaptive) m_tileSamples[item] = adaptiveSamples;
}

}  // namespace glint::render
