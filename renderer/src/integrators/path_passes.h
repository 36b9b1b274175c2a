// The path tracer's passes for the render loop (integrators/render_loop.h): work item i traces
// tile i's pixels for one pass, each pixel's samples in sample-index order, every random number
// from (seed, pixel, sample), so the film does not depend on threads.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "film/film.h"
#include "glint/render/settings.h"
#include "integrators/path_integrator.h"
#include "integrators/render_loop.h"
#include "sampling/sampler.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

/// ZSobol's index layout (log2Res, log2Spp): the film's larger side and a pixel's samples (a
/// half's, with half buffers) in bits.
std::pair<int, int> zsobolLayout(const detail::SceneData& data, const Settings& settings);

/// The path tracer's work for the render loop: tiles on a grid fixed in film coordinates,
/// clipped to the render region, traced in batches (PathIntegrator::traceMany) into `film`.
class PathPasses final : public PassWork {
  public:
    PathPasses(const detail::SceneData& data, const PathIntegrator& integrator,
               const Camera& camera, const Settings& settings, Film& film);

    std::size_t items() const override { return m_tiles.size(); }
    std::optional<Rect> itemRect(std::size_t item) const override { return m_tiles[item]; }
    void run(const PassInfo& pass, std::size_t item, const RenderLoop& loop) override;
    std::uint64_t planAdaptivePass() override;
    void setImportance(std::shared_ptr<const Image> weights) override;
    std::uint64_t adaptivePixels() const override { return m_regionPixels; }
    std::uint64_t adaptiveItemSamples(std::size_t item) const override {
        return m_tileSamples[item];
    }
    FrameBuffers snapshot() override;

    /// Rays traced so far.
    std::uint64_t rays() const { return m_rays.load(); }

  private:
    /// The tile's pixels for one pass, each pixel's samples in sample-index order, traced in
    /// batches and added to the film in that same order; makeSampler(pixel, x, y, s) gives the
    /// sampler of sample s of pixel (x, y).
    template <class MakeSampler>
    void runBatches(const PassInfo& pass, std::size_t item, const MakeSampler& makeSampler);

    /// The camera ray of pixel (x, y) from a sampler's camera numbers (film, lens, time).
    template <PixelSampler Sampler>
    Ray cameraRay(Sampler& sampler, int x, int y) const;

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
    // Adaptive sampling: the pixels of the next adaptive pass (1: takes it) and how many each
    // tile holds (a tile without any is skipped), the samples each tile took in the last one,
    // the region's pixels and the most samples a pixel takes.
    std::vector<std::uint8_t> m_active;
    std::vector<std::uint32_t> m_tileActive;
    std::vector<std::uint64_t> m_tileSamples;
    std::uint64_t m_regionPixels = 0;
    int m_maxSpp = 0;
    std::shared_ptr<const Image> m_importance;  // Settings::importance, or the callback's
};

}  // namespace glint::render
