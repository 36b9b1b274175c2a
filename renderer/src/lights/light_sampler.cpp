#include "lights/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "embree/alpha_filter.h"
#include "lights/spherical_triangle.h"
#include "sampling/warp.h"

namespace glint::render {

LightSampler::LightSampler(const detail::SceneData& scene) : m_scene(&scene) {
    std::vector<Vec3> textureMeans(scene.textures.size(), Vec3{-1.0f, 0.0f, 0.0f});
    std::vector<float> power;
    m_firstOfInstance.assign(scene.instances.size(), -1);
    for (std::uint32_t i = 0; i < scene.instances.size(); ++i) {
        const detail::Instance& inst = scene.instances[i];
        const detail::Mesh& mesh = scene.meshes[inst.mesh];
        // Area lights: power = π × area × luminance(Le) per side, two sides. Moving instances
        // never emit (the loader refuses it).
        if (inst.motion >= 0) continue;
        const std::size_t first = m_lightOfTriangle.size();
        bool emits = false;
        for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
            const detail::Material& m = scene.materials[scene.materialOf(i, t)];
            if (!m.emissive()) continue;
            const detail::TriangleView tri = scene.triangle(i, t);
            const float area = float(triangleArea(tri.p[0], tri.p[1], tri.p[2]));
            if (!(area > 0.0f)) continue;
            if (!emits) m_lightOfTriangle.resize(first + mesh.triangleCount(), -1);
            emits = true;
            m_lightOfTriangle[first + t] = int(m_lights.size());
            const Vec3 centroid = (tri.p[0] + tri.p[1] + tri.p[2]) * (1.0f / 3.0f);
            AreaLight light{
                {tri.p[0], tri.p[1], tri.p[2]}, area, tri.ng, m.emission, centroid, i, t};
            light.partial = m.alphaMode != detail::AlphaMode::Opaque;
            Vec3 mean = m.emission;
            if (m.emissionMap.present() && !mesh.uvs.empty()) {
                light.textured = true;
                Vec3& texMean = textureMeans[std::size_t(m.emissionMap.texture)];
                if (texMean.x < 0.0f)
                    texMean = scene.textures[std::size_t(m.emissionMap.texture)].meanColour();
                mean = m.emission * texMean;
            }
            m_lights.push_back(light);
            power.push_back(2.0f * kPi * area * luminance(mean));
        }
        if (emits) m_firstOfInstance[i] = std::int64_t(first);
    }
    m_areaCount = m_lights.size();
    // Lights at infinity light the scene's bounding sphere (the box of the shutter-open pose):
    // power ≈ π r² × radiance (or irradiance) for its radius r (PBR 12.6).
    const detail::Box& box = scene.bounds;
    const float radius =
        box.empty() ? 1.0f : std::max(0.5f * length(box.hi - box.lo), 1e-3f * scene.extent);
    for (const detail::PunctualLight& light : scene.punctualLights) {
        const float intensity = luminance(light.intensity);
        float lightPower = 0.0f;
        switch (light.kind) {
            case detail::PunctualLight::Kind::Point:
                lightPower = 4.0f * kPi * intensity;
                break;
            case detail::PunctualLight::Kind::Spot:
                // The cone out to halfway through the falloff: 2π (1 − cos θ).
                lightPower =
                    2.0f * kPi * (1.0f - 0.5f * (light.cosInner + light.cosOuter)) * intensity;
                break;
            case detail::PunctualLight::Kind::Directional:
                lightPower = kPi * radius * radius * intensity;
                break;
        }
        if (!(lightPower > 0.0f)) continue;  // a black light is never chosen
        m_punctual.push_back(light);
        power.push_back(lightPower);
    }
    if (scene.environment.kind != detail::EnvironmentDesc::Kind::None) {
        m_environment.emplace(scene.environment);
        power.push_back(kPi * radius * radius * m_environment->meanLuminance());
    }
    m_lightCount = power.size();
    if (m_lightCount > 0) m_select = Distribution1D(power);
}

namespace {
/// Whether a triangle of solid angle `omega` is sampled by solid angle (else by area).
bool bySolidAngle(float omega) {
    return omega >= float(kMinSphericalSolidAngle) && omega <= float(kMaxSphericalSolidAngle);
}

/// Whether a triangle is worth sampling by solid angle from p: when area / (distance to its
/// centroid)², about its solid angle, is at least 0.1 sr. Farther, 1/r² and cos θ hardly vary
/// over the triangle, area sampling is nearly as good and costs no trigonometry: on the Cornell
/// box this keeps almost all the error reduction of sampling every light by solid angle for
/// little of its cost (docs/renderer.md, "Lights").
bool worthSolidAngle(const Vec3& p, const Vec3& centroid, float area) {
    constexpr float kWorthIt = 0.1f;
    const Vec3 d = centroid - p;
    return area >= kWorthIt * dot(d, d);
}
}  // namespace

bool LightSampler::sample(const Vec3& p, float uSelect, Vec2 u, LightSample& out) const {
    if (m_lightCount == 0) return false;
    float selectPdf = 0.0f;
    const int index = m_select.sampleDiscrete(uSelect, &selectPdf);
    if (!(selectPdf > 0.0f)) return false;
    out.delta = false;
    if (std::size_t(index) >= m_areaCount && std::size_t(index) - m_areaCount < m_punctual.size())
        return samplePunctual(m_punctual[std::size_t(index) - m_areaCount], p, selectPdf, out);
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
    const Vec3* v = light.v;
    out.normal = light.normal;
    out.environment = false;
    // A light that fills a good part of the view is sampled by solid angle (Arvo 1995): no
    // 1/r² or cos θ in the weight, the variance near a large light drops.
    if (worthSolidAngle(p, light.centroid, light.area)) {
        const Vec3 a = normalizeOrZero(v[0] - p), b = normalizeOrZero(v[1] - p),
                   c = normalizeOrZero(v[2] - p);
        const float omega = sphericalTriangleSolidAngle(a, b, c);
        if (bySolidAngle(omega)) {
            Vec3 w;
            if (!sampleSphericalTriangle(a, b, c, omega, u, w)) return false;
            // Where the direction meets the light's plane.
            const float cosW = dot(w, light.normal);
            const float distance = dot(v[0] - p, light.normal) / cosW;
            if (!(distance > 0.0f) || !std::isfinite(distance)) return false;
            out.wi = w;
            out.distance = distance;
            out.point = p + w * distance;
            out.pdf = selectPdf / omega;
            out.radiance = emittedAt(light, out.point);
            return true;
        }
    }
    const Vec2 bary = sampleUniformTriangle(u);
    out.point = v[0] * (1.0f - bary.x - bary.y) + v[1] * bary.x + v[2] * bary.y;
    const Vec3 d = out.point - p;
    const float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return false;
    out.distance = std::sqrt(dist2);
    out.wi = d / out.distance;
    const float cosLight = std::abs(dot(out.normal, out.wi));
    if (cosLight <= 0.0f) return false;
    // Area → solid angle: pdf_ω = pdf_A r² / |cos θ_l| (Veach 1997, eq. 8.10).
    out.pdf = selectPdf * dist2 / (light.area * cosLight);
    out.radiance = emittedAt(light, out.point);
    return true;
}

Vec3 LightSampler::emittedThrough(const AreaLight& light, const Vec3& point) const {
    // Barycentrics of the point (in double: the triangle may be tiny or far from the origin).
    auto d3 = [](const Vec3& a, const Vec3& b) {
        return double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z;
    };
    const Vec3 e1 = light.v[1] - light.v[0], e2 = light.v[2] - light.v[0], d = point - light.v[0];
    const double d00 = d3(e1, e1), d01 = d3(e1, e2), d11 = d3(e2, e2), d20 = d3(d, e1),
                 d21 = d3(d, e2);
    const double denom = d00 * d11 - d01 * d01;
    float b1 = 1.0f / 3.0f, b2 = 1.0f / 3.0f;
    if (denom > 0.0) {
        b1 = float(std::clamp((d11 * d20 - d01 * d21) / denom, 0.0, 1.0));
        b2 = float(std::clamp((d00 * d21 - d01 * d20) / denom, 0.0, 1.0 - b1));
    }
    const detail::SceneData& scene = *m_scene;
    const detail::Material& m = scene.materials[scene.materialOf(light.instance, light.prim)];
    Vec3 le = light.emission;
    if (light.textured) {
        // The texture coordinates of the point on the mesh.
        const detail::Mesh& mesh = scene.meshes[scene.instances[light.instance].mesh];
        const Vec2 uv = detail::surfaceUv(mesh, m.emissionMap.transform.set, light.prim, b1, b2);
        const Vec4 t = scene.textures[std::size_t(m.emissionMap.texture)].lookup(
            m.emissionMap.transform.apply(uv));
        le = le * Vec3{t.x, t.y, t.z};
    }
    if (light.partial) {
        // A camera or BSDF ray meets a BLEND surface with probability alpha and passes a MASK
        // one where alpha < cut-off (embree/alpha_filter.cpp): next-event estimation gives the
        // point the same expected radiance, so both MIS strategies estimate alpha × Le.
        const float alpha = surfaceAlpha(scene, light.instance, light.prim, b1, b2);
        if (m.alphaMode == detail::AlphaMode::Mask)
            le = alpha < m.alphaCutoff ? Vec3{} : le;
        else
            le = le * alpha;
    }
    return le;
}

bool LightSampler::samplePunctual(const detail::PunctualLight& light, const Vec3& p,
                                  float selectPdf, LightSample& out) const {
    using Kind = detail::PunctualLight::Kind;
    out.delta = true;
    out.environment = false;
    out.pdf = selectPdf;
    out.normal = {};
    if (light.kind == Kind::Directional) {
        // Irradiance from one direction: the light shines along `direction`.
        out.wi = -light.direction;
        out.distance = std::numeric_limits<float>::infinity();
        out.point = {};
        out.radiance = light.intensity;
        return true;
    }
    const Vec3 d = light.position - p;
    const float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return false;
    out.distance = std::sqrt(dist2);
    out.wi = d / out.distance;
    out.point = light.position;
    // Intensity falls off as 1/r² (glTF gives no range attenuation that Glint models).
    out.radiance = light.intensity / dist2;
    if (light.kind == Kind::Spot) {
        // glTF's smooth cone: full inside the inner angle, none outside the outer, the square
        // of a linear ramp in cos θ between.
        const float cosTheta = dot(-out.wi, light.direction);
        const float width = std::max(light.cosInner - light.cosOuter, 1e-3f);
        const float t = std::clamp((cosTheta - light.cosOuter) / width, 0.0f, 1.0f);
        out.radiance = out.radiance * (t * t);
    }
    return true;
}

float LightSampler::pdfArea(detail::SurfaceId surface, const Vec3& p, const Vec3& lightPoint,
                            const Vec3& ng) const {
    const int index = lightOf(surface);
    if (index < 0) return 0.0f;
    // The same choice of measure as sample() makes from p.
    const AreaLight& light = m_lights[std::size_t(index)];
    const Vec3* v = light.v;
    if (worthSolidAngle(p, light.centroid, light.area)) {
        const float omega = sphericalTriangleSolidAngle(
            normalizeOrZero(v[0] - p), normalizeOrZero(v[1] - p), normalizeOrZero(v[2] - p));
        if (bySolidAngle(omega)) return m_select.discretePdf(index) / omega;
    }
    const Vec3 d = lightPoint - p;
    const float dist2 = dot(d, d);
    const float cosLight = std::abs(dot(ng, d)) / std::sqrt(dist2);
    if (cosLight <= 0.0f) return 0.0f;
    return m_select.discretePdf(index) * dist2 / (light.area * cosLight);
}

float LightSampler::pdfEnvironment(const Vec3& dir) const {
    if (!m_environment) return 0.0f;
    return m_select.discretePdf(int(m_lightCount) - 1) * m_environment->pdf(dir);
}

}  // namespace glint::render
