#include "scene/scene_hash.h"

#include <algorithm>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "glint/image/random.h"

namespace glint::render {

namespace {

/// Folds bytes into a 64-bit state eight at a time with glint::hash64.
class Hasher {
  public:
    void bytes(const void* data, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        m_state = hash64(m_state, size);
        for (std::size_t i = 0; i < size; i += 8) {
            std::uint64_t word = 0;
            std::memcpy(&word, p + i, std::min<std::size_t>(8, size - i));
            m_state = hash64(m_state, word);
        }
    }
    /// A value of a type without padding (floats, integers, float vectors).
    template <typename T>
    void value(const T& v) {
        static_assert(std::has_unique_object_representations_v<T> || std::is_floating_point_v<T> ||
                      std::is_same_v<T, Vec3> || std::is_same_v<T, Vec2>);
        bytes(&v, sizeof v);
    }
    template <typename T>
    void vector(const std::vector<T>& v) {
        bytes(v.data(), v.size() * sizeof(T));
    }
    void string(const std::string& s) { bytes(s.data(), s.size()); }
    void image(const Image& im) {
        value(im.width()), value(im.height()), value(im.channels());
        bytes(im.data().data(), im.data().size_bytes());
    }
    std::uint64_t state() const { return m_state; }

  private:
    std::uint64_t m_state = 0x61c8864680b583ebULL;
};

}  // namespace

std::uint64_t sceneContentHash(const detail::SceneData& d) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Vec2) == 2 * sizeof(float));
    Hasher h;
    h.value(d.width), h.value(d.height);
    // Camera.
    const detail::CameraDesc& c = d.camera;
    for (const Vec3& v : {c.position, c.lookAt, c.up, c.motionPosition, c.motionLookAt}) h.value(v);
    for (float f : {c.fovY, c.lensRadius, c.focusDistance, c.shutterOpen, c.shutterClose})
        h.value(f);
    h.value(int(c.hasMotion));
    // Materials (as edited) and textures.
    for (const detail::Material& m : d.materials) {
        h.string(m.name);
        h.value(int(m.type)), h.value(m.texture), h.value(int(m.hasEtaK));
        for (const Vec3& v : {m.albedo, m.emission, m.eta, m.k, m.specular}) h.value(v);
        h.value(m.ior), h.value(m.roughness);
        // Metallic-roughness (glTF) properties.
        h.value(m.metallic), h.value(m.transmission), h.value(m.normalScale), h.value(m.opacity);
        h.value(m.alphaCutoff), h.value(int(m.alphaMode)), h.value(int(m.textureTimesFactor));
        for (const detail::TextureSlot* slot :
             {&m.roughnessMetallicMap, &m.normalMap, &m.emissionMap}) {
            h.value(slot->texture);
            h.bytes(slot->transform.m, sizeof slot->transform.m);
        }
        // Hashed only when present, so that the hashes of scenes without one stay as they were.
        if (m.transmissionMap.present()) {
            h.value(m.transmissionMap.texture);
            h.bytes(m.transmissionMap.transform.m, sizeof m.transmissionMap.transform.m);
        }
        if (m.bumpMap.present()) {
            h.value(m.bumpMap.texture), h.value(m.bumpMultiplier);
            h.bytes(m.bumpMap.transform.m, sizeof m.bumpMap.transform.m);
        }
        h.bytes(m.textureTransform.m, sizeof m.textureTransform.m);
        // The second uv set and vertex colours likewise only where they are read.
        for (const detail::UvTransform* t :
             {&m.textureTransform, &m.roughnessMetallicMap.transform, &m.normalMap.transform,
              &m.emissionMap.transform, &m.transmissionMap.transform})
            if (t->set != 0) h.value(int(t->set));
    }
    for (const detail::PunctualLight& l : d.punctualLights) {
        h.value(int(l.kind)), h.value(l.position), h.value(l.direction), h.value(l.intensity);
        h.value(l.cosInner), h.value(l.cosOuter);
    }
    // A texture file by its content hash (taken once at load), an image in memory by its texels.
    for (const detail::Texture& t : d.textures) {
        h.value(int(t.use)), h.value(int(t.wrapS)), h.value(int(t.wrapT));
        if (t.store)
            h.value(t.contentHash);
        else
            h.image(t.image);
    }
    // Geometry.
    for (const detail::Mesh& m : d.meshes) {
        h.vector(m.positions), h.vector(m.normals), h.vector(m.uvs);
        for (const Vec4& t : m.tangents) h.bytes(&t, sizeof t);
        if (!m.uvs1.empty()) h.vector(m.uvs1);
        for (const Vec4& c : m.colors) h.bytes(&c, sizeof c);
        h.vector(m.indices), h.vector(m.materials);
    }
    auto affine = [&](const detail::Affine& a) {
        h.bytes(a.m, sizeof a.m), h.bytes(a.nm, sizeof a.nm);
        h.value(a.t);
    };
    for (const detail::Instance& i : d.instances) {
        h.value(i.mesh), h.value(i.motion), h.value(i.material), h.value(int(i.identity));
        affine(i.transform);
    }
    for (const detail::InstanceMotion& m : d.motions)
        for (const detail::Affine& a : m.steps) affine(a);
    // Environment.
    const detail::EnvironmentDesc& e = d.environment;
    h.value(int(e.kind)), h.value(e.color), h.value(e.scale), h.value(e.rotateDeg);
    h.image(e.image);
    return h.state();
}

}  // namespace glint::render
