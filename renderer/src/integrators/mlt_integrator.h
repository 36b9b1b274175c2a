// Primary-sample-space Metropolis light transport (Kelemen et al. 2002) over the path
// integrator: bootstrap normalisation, many independent chains in parallel, four mutation
// kinds, expected-value splatting, batch-means variance (docs/metropolis.md). The bootstrap and
// the chains' passes are integrators/mlt_passes.h; this class sets them up and records what
// they did.
#pragma once

#include <array>
#include <cstdint>

#include <tbb/task_arena.h>

#include "embree/embree_scene.h"
#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "glint/render/settings.h"
#include "integrators/path_integrator.h"
#include "integrators/render_loop.h"
#include "lights/light_sampler.h"
#include "sampling/mlt_sampler.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

/// The settings of the short path-traced pass that gives an MLT frame its feature layers.
Settings mltFeatureSettings(const Settings& settings);

/// Renders the colour of a frame with Metropolis chains. Stateless apart from references.
class MltIntegrator {
  public:
    MltIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                  const LightSampler& lights, const Camera& camera, const Settings& settings);

    /// Replaces the colour and variance layers of `features` (a path-traced frame) by the
    /// Metropolis estimate, running the bootstrap and then the chains' passes through the
    /// shared RenderLoop in `arena` within `timeBudget` seconds (0: no limit) and reporting
    /// progress from `progressBegin` to 1.
    /// Records the statistics in `stats` (which holds the feature pass's figures on entry and
    /// is extended, stats.mlt set) and, as text, in the frame's metadata.
    FrameBuffers render(FrameBuffers features, const Callbacks& callbacks, tbb::task_arena& arena,
                        double timeBudget, double progressBegin, RenderStats& stats);

    /// Evaluates the path of the sampler's current proposal: contribution L (zero for a
    /// non-finite one, counted in `nonFinite`), film point; counts rays. Thread-safe.
    void evaluate(MltSampler& sampler, Vec3& radiance, Vec2& raster, std::uint64_t& rays,
                  std::int64_t& nonFinite) const;

  private:
    const detail::SceneData& m_scene;
    const Camera& m_camera;
    const LightSampler& m_lights;
    Settings m_settings;
    PathIntegrator m_path;
    bool m_thinLens, m_sampleTime;
};

}  // namespace glint::render
