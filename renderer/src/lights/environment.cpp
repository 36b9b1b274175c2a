#include "lights/environment.h"

#include <cmath>
#include <vector>

#include "glint/image/error.h"
#include "sampling/warp.h"

namespace glint::render {

using Kind = detail::EnvironmentDesc::Kind;

Environment::Environment(const detail::EnvironmentDesc& desc) : m_desc(&desc) {
    GLINT_CHECK(desc.kind != Kind::None);
    const float a = desc.rotateDeg * kPi / 180.0f;
    m_cosRot = std::cos(a);
    m_sinRot = std::sin(a);
    if (desc.kind == Kind::Constant) {
        m_meanLuminance = luminance(desc.color);
        return;
    }
    // Weight each texel by luminance × sin θ at its centre so the pdf follows radiance per solid
    // angle (texels of zero luminance emit nothing and need no samples).
    const int w = desc.image.width(), h = desc.image.height();
    std::vector<float> weights(std::size_t(w) * std::size_t(h));
    double sum = 0.0, sumSin = 0.0;
    for (int y = 0; y < h; ++y) {
        const float sinTheta = std::sin(kPi * (float(y) + 0.5f) / float(h));
        for (int x = 0; x < w; ++x) {
            const float lum = std::max(
                0.0f, luminance({desc.image(x, y, 0), desc.image(x, y, 1), desc.image(x, y, 2)}));
            weights[std::size_t(y) * w + x] = lum * sinTheta;
            sum += double(lum) * sinTheta;
            sumSin += sinTheta;
        }
    }
    m_meanLuminance = sumSin > 0.0 ? float(sum / sumSin) : 0.0f;
    m_distribution = Distribution2D(weights, w, h);
}

Vec2 Environment::dirToUv(const Vec3& d) {
    const float theta = std::acos(std::clamp(d.y, -1.0f, 1.0f));
    float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * kPi);
    if (u >= 1.0f) u -= 1.0f;
    if (u < 0.0f) u += 1.0f;
    return {u, theta * kInvPi};
}

Vec3 Environment::uvToDir(Vec2 uv) {
    const float theta = uv.y * kPi, phi = (uv.x - 0.5f) * 2.0f * kPi;
    const float s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

Vec3 Environment::toEnv(const Vec3& v) const {
    return {m_cosRot * v.x - m_sinRot * v.z, v.y, m_sinRot * v.x + m_cosRot * v.z};
}

Vec3 Environment::toWorld(const Vec3& v) const {
    return {m_cosRot * v.x + m_sinRot * v.z, v.y, -m_sinRot * v.x + m_cosRot * v.z};
}

Vec3 Environment::eval(const Vec3& dir) const {
    if (m_desc->kind == Kind::Constant) return m_desc->color;
    const Image& img = m_desc->image;
    const Vec2 uv = dirToUv(toEnv(dir));
    const int x = std::clamp(int(uv.x * float(img.width())), 0, img.width() - 1);
    const int y = std::clamp(int(uv.y * float(img.height())), 0, img.height() - 1);
    return {img(x, y, 0), img(x, y, 1), img(x, y, 2)};
}

bool Environment::sample(Vec2 u, Vec3& dir, float& pdf) const {
    if (m_desc->kind == Kind::Constant) {
        dir = sampleUniformSphere(u);
        pdf = kUniformSpherePdf;
        return true;
    }
    float pdfUv = 0.0f;
    const Vec2 uv = m_distribution.sample(u, &pdfUv);
    const float sinTheta = std::sin(uv.y * kPi);
    if (!(pdfUv > 0.0f) || sinTheta <= 0.0f) return false;
    // Change of variables (u, v) → ω: dω = 2π² sin θ du dv.
    pdf = pdfUv / (2.0f * kPi * kPi * sinTheta);
    dir = toWorld(uvToDir(uv));
    return true;
}

float Environment::pdf(const Vec3& dir) const {
    if (m_desc->kind == Kind::Constant) return kUniformSpherePdf;
    const Vec2 uv = dirToUv(toEnv(dir));
    const float sinTheta = std::sin(uv.y * kPi);
    if (sinTheta <= 0.0f) return 0.0f;
    return m_distribution.pdf(uv) / (2.0f * kPi * kPi * sinTheta);
}

}  // namespace glint::render
