// Unidirectional path tracer with next-event estimation and BSDF sampling combined by multiple
// importance sampling (Veach 1997, ch. 9), Russian roulette and a maximum depth.
#pragma once

#include <cstdint>
#include <vector>

#include "embree/embree_scene.h"
#include "film/film.h"
#include "glint/render/settings.h"
#include "lights/light_sampler.h"
#include "materials/bsdf.h"
#include "sampling/sampler.h"
#include "scene/camera.h"
#include "scene/scene_data.h"

namespace glint::render {

/// One path between two ray queries: what trace() keeps in its locals, so that many paths can
/// take turns (traceMany) and share packet queries.
struct PathState {
    Ray ray;  ///< the ray to intersect next
    Vec3 radiance, beta{1.0f, 1.0f, 1.0f};
    Vec3 prevP;  ///< the vertex `ray` leaves from
    float prevPdf = 0.0f;
    int depth = 0;
    bool specularBounce = false, featuresDone = false;
    bool alive = true;
    /// The choice at BLEND surfaces met by this bounce's ray (meetsBlend): the bounce's
    /// component number once drawn, rescaled by every choice made with it; the width of the
    /// interval it has been narrowed to (the bits of it left) and the surfaces passed so far.
    bool blendDrawn = false;
    float blendU = 0.0f, blendWidth = 1.0f;
    int blendPasses = 0;
    /// Next-event estimation of this bounce, waiting for its shadow ray: `shadowContribution`
    /// counts times the fraction of light `shadow` lets through (EmbreeScene::visibility).
    bool shadowPending = false;
    ShadowRay shadow;
    Vec3 shadowContribution;
    FilmSample out;
};

/// Estimates radiance along camera rays. Stateless apart from references; thread-safe.
class PathIntegrator {
  public:
    PathIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                   const LightSampler& lights, const Camera& camera, const Settings& settings);

    /// Traces one camera ray; fills colour and first-non-specular-hit features; counts rays.
    /// The path reads its numbers from `rng` by bounce and slot (sampling/sampler.h).
    template <PathSampler Sampler>
    void trace(const Ray& cameraRay, Sampler& rng, FilmSample& out, std::uint64_t& rays) const;

    /// trace() of many camera rays at once: each bounce intersects every live path's ray, and
    /// then occlusion-tests every pending shadow ray, as packets (EmbreeScene::intersectMany).
    /// Path i draws from samplers[i] in the same order as trace(), so out[i] is what trace()
    /// gives for it, up to Embree's packet and single-ray kernels rounding differently. A
    /// PrefetchingSampler computes each bounce's numbers of all paths together.
    template <PathSampler Sampler>
    void traceMany(std::size_t count, const Ray* cameraRays, Sampler* samplers, FilmSample* out,
                   std::uint64_t& rays) const;

  private:
    /// Consumes the intersection of p.ray (`found` and `hit`, whose material is `material`:
    /// materialAt(hit), null when nothing was found) at bounce p.depth: emission, features,
    /// next-event estimation (leaving its shadow ray pending) and the next ray, or the end of
    /// the path (p.alive false).
    template <PathSampler Sampler>
    void advance(PathState& p, bool found, const Hit& hit, const detail::Material* material,
                 Sampler& rng, std::uint64_t& rays) const;

    /// At a hit on a BLEND surface of presence alpha: true when p.ray meets it (then the
    /// surface is shaded and p.blendU is the component number of its BSDF), else false with
    /// p.ray moved past it, same direction, throughput and bounce. The choice reads the
    /// bounce's component number u — met when u < alpha, u / alpha left for the BSDF, else
    /// passed with (u − alpha) / (1 − alpha) left for the next surface: uniform and independent
    /// of the choice either way, so the estimate stays unbiased and the first choice stratified.
    /// Past kMaxBlendPasses surfaces, or when u has too few bits left, a hash of the ray and
    /// the triangle takes its place (blendHash).
    template <PathSampler Sampler>
    bool meetsBlend(PathState& p, const Hit& hit, Sampler& rng) const;

    /// The bounce numbers (slotBit() mask) p's next advance() will read at a hit on `material`,
    /// as far as the material tells: a prefetch that may compute one or two numbers the path
    /// then does not use (a path that ends).
    unsigned numbersNeeded(const PathState& p, const detail::Material& material) const;

    /// The material of the surface `hit` found (SceneData::materialOf, through
    /// m_instanceMaterials; found once a hit: traceMany keeps it).
    const detail::Material& materialAt(const Hit& hit) const {
        const InstanceMaterials& m = m_instanceMaterials[hit.surface.instance];
        return m.only ? *m.only : m_scene.materials[m.perTriangle[hit.surface.prim]];
    }

    /// What `material`'s BSDF does (materialFlags, found once in the constructor).
    const BsdfFlags& flagsOf(const detail::Material& material) const {
        return m_materialFlags[std::size_t(&material - m_scene.materials.data())];
    }

    /// MIS weight of a strategy with density `pdf` against the other with `other`.
    float misWeight(float pdf, float other) const;

    const detail::SceneData& m_scene;
    const EmbreeScene& m_embree;
    const LightSampler& m_lights;
    const Camera& m_camera;
    MisHeuristic m_mis;
    bool m_useLightSampling;  // NEE at non-specular vertices
    bool m_useBsdfHits;       // emitters found by BSDF sampling count (after non-specular)
    bool m_hasBlend;          // some material is alphaMode BLEND (meetsBlend)
    /// Where an instance's triangles find their material: the one of all of them (the
    /// instance's own, or its mesh's only one), else its mesh's index per triangle into
    /// SceneData::materials (Mesh::materials).
    struct InstanceMaterials {
        const detail::Material* only = nullptr;
        const std::uint32_t* perTriangle = nullptr;
    };
    std::vector<InstanceMaterials> m_instanceMaterials;
    std::vector<BsdfFlags> m_materialFlags;  ///< of SceneData::materials, by index
    int m_maxDepth, m_rrDepth;
};

}  // namespace glint::render
