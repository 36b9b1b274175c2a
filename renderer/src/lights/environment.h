// Environment light: constant radiance (uniform sphere sampling) or a lat-long image
// importance-sampled with a 2D piecewise-constant distribution weighted by sin θ
// (PBR 3rd ed., sec. 14.2.4). Convention: +y up, θ from +y, u = 0.5 looks down -z, u grows
// towards +x; the image is looked up per texel (piecewise constant, matching the sampling pdf).
#pragma once

#include "sampling/distribution.h"
#include "scene/scene_data.h"
#include "vecmath.h"

namespace glint::render {

/// Environment radiance, importance sampling and pdf.
class Environment {
  public:
    /// Builds from the scene's description (Kind::None is not allowed here).
    explicit Environment(const detail::EnvironmentDesc& desc);

    /// Radiance arriving from world direction `dir` (unit).
    Vec3 eval(const Vec3& dir) const;
    /// Samples a world direction; sets the solid-angle pdf. False when the pdf is zero.
    bool sample(Vec2 u, Vec3& dir, float& pdf) const;
    /// Solid-angle pdf of sample() producing `dir`.
    float pdf(const Vec3& dir) const;
    /// Mean radiance luminance over the sphere (for power estimates).
    float meanLuminance() const { return m_meanLuminance; }

    /// Lat-long (u, v) of an environment-space direction and back.
    static Vec2 dirToUv(const Vec3& d);
    static Vec3 uvToDir(Vec2 uv);

  private:
    Vec3 toEnv(const Vec3& world) const;
    Vec3 toWorld(const Vec3& env) const;

    const detail::EnvironmentDesc* m_desc;
    float m_cosRot = 1.0f, m_sinRot = 0.0f;
    Distribution2D m_distribution;
    float m_meanLuminance = 0.0f;
};

}  // namespace glint::render
