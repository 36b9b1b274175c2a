// Light selection and sampling: every emissive triangle is an area light (two-sided), chosen with
// the punctual lights and the environment in proportion to power by a 1D distribution, and
// sampled by the solid angle it subtends where that is large enough (spherical_triangle.h), else
// uniformly by area. Punctual lights (point, spot, directional: glTF's KHR_lights_punctual) are
// delta lights: reached only by next-event estimation, never by a BSDF sample.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "lights/environment.h"
#include "sampling/distribution.h"
#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// A sampled light point as seen from a shading point.
struct LightSample {
    Vec3 wi;         ///< unit direction from the shading point to the light
    float distance;  ///< to the light point (infinity for the environment)
    Vec3 point;      ///< light point (area lights)
    Vec3 normal;     ///< geometric normal of the light point (area lights)
    Vec3 radiance;   ///< emitted radiance towards the shading point; for a delta light the
                     ///< irradiance it gives at unit cosine (intensity / distance², or lux)
    float pdf;       ///< solid-angle pdf including the choice of light; for a delta light the
                     ///< probability of choosing it
    bool environment;
    bool delta = false;  ///< a punctual light: no BSDF sample can reach it, so MIS weight 1
};

/// All lights of a scene. Empty when the scene has neither emitters nor an environment.
class LightSampler {
  public:
    explicit LightSampler(const detail::SceneData& scene);

    bool empty() const { return m_lightCount == 0; }
    std::size_t punctualLightCount() const { return m_punctual.size(); }
    std::size_t areaLightCount() const { return m_areaCount; }
    const Environment* environment() const { return m_environment ? &*m_environment : nullptr; }

    /// Samples a light for shading point p: uSelect picks the light, u the point on it.
    bool sample(const Vec3& p, float uSelect, Vec2 u, LightSample& out) const;
    /// Solid-angle pdf that sample() from p produces the point `lightPoint` on the triangle
    /// `surface` with geometric normal `ng` (unit).
    float pdfArea(detail::SurfaceId surface, const Vec3& p, const Vec3& lightPoint,
                  const Vec3& ng) const;
    /// Solid-angle pdf that sample() produces environment direction `dir`.
    float pdfEnvironment(const Vec3& dir) const;

  private:
    struct AreaLight {
        Vec3 v[3];  ///< world-space vertices
        float area;
        Vec3 normal;
        Vec3 emission;
        Vec3 centroid;                         ///< of the triangle (worthSolidAngle)
        std::uint32_t instance = 0, prim = 0;  ///< the triangle
        bool textured = false;  ///< its material's emission has a texture (and the mesh uvs)
        /// Its material's alphaMode is MASK or BLEND: the surface is not everywhere there.
        bool partial = false;
    };
    /// The radiance light `light` gives at `point` as a camera or BSDF ray finds it there: its
    /// emission times its texture, times its presence (BLEND: alpha; MASK: 0 where cut out).
    Vec3 emittedAt(const AreaLight& light, const Vec3& point) const {
        // Most lights are neither: no call at every light sample for them.
        if (!light.textured && !light.partial) return light.emission;
        return emittedThrough(light, point);
    }
    /// emittedAt() of a textured or partly present light.
    Vec3 emittedThrough(const AreaLight& light, const Vec3& point) const;

    const detail::SceneData* m_scene = nullptr;
    /// The light of triangle `prim` of `instance`, or -1 when it does not emit.
    int lightOf(detail::SurfaceId s) const {
        const std::int64_t first = m_firstOfInstance[s.instance];
        return first < 0 ? -1 : m_lightOfTriangle[std::size_t(first) + s.prim];
    }
    /// Samples punctual light `light` from p (the choice's probability `selectPdf`).
    bool samplePunctual(const detail::PunctualLight& light, const Vec3& p, float selectPdf,
                        LightSample& out) const;

    // The distribution's entries: area lights [0, m_areaCount), then the punctual lights, then
    // the environment, if any, last (m_lightCount entries in all).
    std::vector<AreaLight> m_lights;
    std::vector<detail::PunctualLight> m_punctual;
    std::size_t m_lightCount = 0;
    /// Per instance with an emissive triangle, where its triangles start in m_lightOfTriangle
    /// (-1 for the others); there, per triangle, its light or -1.
    std::vector<std::int64_t> m_firstOfInstance;
    std::vector<int> m_lightOfTriangle;
    std::optional<Environment> m_environment;
    std::size_t m_areaCount = 0;
    Distribution1D m_select;
};

}  // namespace glint::render
