// Primary-sample-space Metropolis light transport (Kelemen et al. 2002) over the path
// integrator: bootstrap normalisation, many independent chains in parallel, four mutation
// kinds, expected-value splatting, batch-means variance (docs/metropolis.md).
#pragma once

#include <array>
#include <cstdint>

#include "embree/embree_scene.h"
#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "glint/render/settings.h"
#include "integrators/path_integrator.h"
#include "lights/light_sampler.h"
#include "sampling/primary_sample.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

/// The settings of the short path-traced pass that gives an MLT frame its feature layers.
Settings mltFeatureSettings(const Settings& settings);

/// What one Metropolis render did, per mutation kind.
struct MltStats {
    std::array<std::uint64_t, kMutationKinds> proposed{};
    std::array<std::uint64_t, kMutationKinds> accepted{};
    std::uint64_t mutations = 0;
    std::uint64_t bootstrap = 0;
    double b = 0.0;           ///< mean luminance of the image (bootstrap estimate)
    double bRelStdErr = 0.0;  ///< relative standard error of b
    double mutationSeconds = 0.0;
};

/// Renders the colour of a frame with Metropolis chains. Stateless apart from references.
class MltIntegrator {
  public:
    MltIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                  const LightSampler& lights, const Camera& camera, const Settings& settings);

    /// Replaces the colour and variance layers of `features` (a path-traced frame) by the
    /// Metropolis estimate; records statistics in its metadata and in `stats` (which holds the
    /// feature pass's figures on entry and is extended).
    FrameBuffers render(FrameBuffers features, const Callbacks& callbacks, RenderStats& stats);

    /// Statistics of the last render() (valid after it returns).
    const MltStats& mltStats() const { return m_mltStats; }

  private:
    /// Evaluates the path of the sampler's current proposal: contribution L, film point.
    void evaluate(PrimarySampleSampler& sampler, Vec3& radiance, Vec2& raster, std::uint64_t& rays,
                  std::int64_t& nonFinite) const;

    const detail::SceneData& m_scene;
    const Camera& m_camera;
    const LightSampler& m_lights;
    Settings m_settings;
    PathIntegrator m_path;
    bool m_thinLens, m_sampleTime;
    MltStats m_mltStats;
};

}  // namespace glint::render
