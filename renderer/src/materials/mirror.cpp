// mirror — perfect specular reflection tinted by albedo.
//   scene.json: {"type": "mirror", "albedo": [r,g,b] (tint, default white)}
#include "materials/bsdf.h"

namespace glint::render {

bool mirrorSample(const Bsdf& b, const Vec3& wo, BsdfSample& out) {
    if (wo.z <= 0.0f) return false;
    out.wi = {-wo.x, -wo.y, wo.z};
    out.weight = b.albedo;
    out.pdf = 0.0f;
    out.specular = true;
    return true;
}

}  // namespace glint::render
