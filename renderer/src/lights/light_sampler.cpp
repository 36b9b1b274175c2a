#include "lights/light_sampler.h"

#include <cmath>
#include <limits>

#include "sampling/warp.h"

namespace glint::render {

LightSampler::LightSampler(const detail::SceneData& scene) : m_scene(&scene) {
    std::vector<float> power;
    m_lightOfTriangle.assign(scene.triangleCount(), -1);
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const Vec3& p : scene.positions)
        for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    // Area lights: power = π × area × luminance(Le) per side, two sides.
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const detail::Material& m = scene.materials[scene.triangleMaterial[t]];
        if (!m.emissive()) continue;
        const Vec3& a = scene.positions[3 * t];
        const float area =
            float(triangleArea(a, scene.positions[3 * t + 1], scene.positions[3 * t + 2]));
        if (!(area > 0.0f)) continue;
        m_lightOfTriangle[t] = int(m_lights.size());
        m_lights.push_back({std::uint32_t(t), area, scene.faceNormals[t], m.emission});
        power.push_back(2.0f * kPi * area * luminance(m.emission));
    }
    m_areaCount = m_lights.size();
    if (scene.environment.kind != detail::EnvironmentDesc::Kind::None) {
        m_environment.emplace(scene.environment);
        // Environment power ≈ π r² × mean radiance for the scene's bounding sphere (PBR 12.6).
        const float radius =
            scene.positions.empty() ? 1.0f : std::max(0.5f * length(hi - lo), 1e-3f * scene.extent);
        m_lights.push_back({0, 0.0f, {}, {}});
        power.push_back(kPi * radius * radius * m_environment->meanLuminance());
    }
    if (!m_lights.empty()) m_select = Distribution1D(power);
}

bool LightSampler::sample(const Vec3& p, float uSelect, Vec2 u, LightSample& out) const {
    if (m_lights.empty()) return false;
    float selectPdf = 0.0f;
    const int index = m_select.sampleDiscrete(uSelect, &selectPdf);
    if (!(selectPdf > 0.0f)) return false;
    if (std::size_t(index) >= m_areaCount) {
        // Environment: direction from its own importance sampling.
        float pdf = 0.0f;
        if (!m_environment->sample(u, out.wi, pdf)) return false;
        out.pdf = pdf * selectPdf;
        out.distance = std::numeric_limits<float>::infinity();
        out.radiance = m_environment->eval(out.wi);
        out.environment = true;
        return true;
    }
    const AreaLight& light = m_lights[std::size_t(index)];
    const Vec3* v = &m_scene->positions[3 * std::size_t(light.triangle)];
    const Vec2 b = sampleUniformTriangle(u);
    out.point = v[0] * (1.0f - b.x - b.y) + v[1] * b.x + v[2] * b.y;
    out.normal = light.normal;
    const Vec3 d = out.point - p;
    const float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return false;
    out.distance = std::sqrt(dist2);
    out.wi = d / out.distance;
    const float cosLight = std::abs(dot(out.normal, out.wi));
    if (cosLight <= 0.0f) return false;
    // Area → solid angle: pdf_ω = pdf_A r² / |cos θ_l| (Veach 1997, eq. 8.10).
    out.pdf = selectPdf * dist2 / (light.area * cosLight);
    out.radiance = light.emission;
    out.environment = false;
    return true;
}

float LightSampler::pdfArea(std::uint32_t triangle, const Vec3& p, const Vec3& lightPoint,
                            const Vec3& ng) const {
    const int index = m_lightOfTriangle[triangle];
    if (index < 0) return 0.0f;
    const Vec3 d = lightPoint - p;
    const float dist2 = dot(d, d);
    const float cosLight = std::abs(dot(ng, d)) / std::sqrt(dist2);
    if (cosLight <= 0.0f) return 0.0f;
    return m_select.discretePdf(index) * dist2 / (m_lights[std::size_t(index)].area * cosLight);
}

float LightSampler::pdfEnvironment(const Vec3& dir) const {
    if (!m_environment) return 0.0f;
    return m_select.discretePdf(int(m_lights.size()) - 1) * m_environment->pdf(dir);
}

}  // namespace glint::render
