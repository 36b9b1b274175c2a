// Unidirectional path tracer with next-event estimation and BSDF sampling combined by multiple
// importance sampling (Veach 1997, ch. 9), Russian roulette and a maximum depth.
#pragma once

#include <cstdint>

#include "embree/embree_scene.h"
#include "film/film.h"
#include "glint/render/settings.h"
#include "lights/light_sampler.h"
#include "sampling/rng.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

/// Estimates radiance along camera rays. Stateless apart from references; thread-safe.
class PathIntegrator {
  public:
    PathIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                   const LightSampler& lights, const Camera& camera, const Settings& settings);

    /// Traces one camera ray; fills colour and first-non-specular-hit features; counts rays.
    /// `Sampler` is Rng (path tracing) or MltSampler (Metropolis): it provides
    /// uniform(), and optionally uniformLight() for the numbers of next-event estimation.
    template <class Sampler>
    void trace(const Ray& cameraRay, Sampler& rng, FilmSample& out, std::uint64_t& rays) const;

  private:
    /// MIS weight of a strategy with density `pdf` against the other with `other`.
    float misWeight(float pdf, float other) const;

    const detail::SceneData& m_scene;
    const EmbreeScene& m_embree;
    const LightSampler& m_lights;
    const Camera& m_camera;
    MisHeuristic m_mis;
    bool m_useLightSampling;  // NEE at non-specular vertices
    bool m_useBsdfHits;       // emitters found by BSDF sampling count (after non-specular)
    int m_maxDepth, m_rrDepth;
};

}  // namespace glint::render
