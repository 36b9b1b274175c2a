// glTF materials → Glint metallic-roughness materials, and their textures: base colour (colour),
// metallic-roughness and normal (data), emissive (colour) with KHR_texture_transform, samplers'
// wrap modes, images from files, bufferViews or data URIs. KHR_materials_emissive_strength,
// KHR_materials_ior and KHR_materials_transmission (factor and texture; rendered as a solid
// refracting surface, materials/metallic_roughness.cpp) are read; occlusion is not.
#include <tiny_gltf.h>

#include <cmath>
#include <memory>

#include "glint/image/error.h"
#include "scene/gltf_file.h"
#include "scene/gltf_import.h"
#include "scene/input_file.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

const tinygltf::Value* extensionOf(const tinygltf::ExtensionMap& map, const char* name) {
    const auto it = map.find(name);
    return it == map.end() || !it->second.IsObject() ? nullptr : &it->second;
}

/// A 3×3 matrix of homogeneous 2D texture coordinates, row-major.
struct Mat3 {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
};
Mat3 operator*(const Mat3& a, const Mat3& b) {
    Mat3 c;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            c.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return c;
}

TextureWrap wrapMode(int mode, bool& known) {
    known = true;
    switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return TextureWrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return TextureWrap::Mirror;
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return TextureWrap::Repeat;
        default:
            known = false;
            return TextureWrap::Repeat;
    }
}

}  // namespace

int GltfImport::material(int index) {
    // A shape-wide override: the instances replace every material; the mesh's are unused.
    if (m_overrides.material >= 0) return m_overrides.material;
    if (index >= 0 && std::size_t(index) >= m_model.materials.size())
        fail("materials", "a primitive names materials[" + std::to_string(index) +
                              "], but the asset has " + std::to_string(m_model.materials.size()));
    int& cached = index < 0 ? m_defaultMaterial : m_materials[std::size_t(index)];
    if (cached >= 0) return cached;
    // The glTF default material (spec 3.9.6): white, fully metallic and rough.
    const std::string name =
        index < 0 ? "glTF default" : m_model.materials[std::size_t(index)].name;
    // Overrides by name: the shape's "materials" map, then JSON materials of the same name.
    if (const auto it = m_overrides.byName.find(name); index >= 0 && it != m_overrides.byName.end())
        return cached = it->second;
    if (const int j = m_loader.materialIndex(name);
        j >= 0 && (m_scene.materials[std::size_t(j)].fromJson || index < 0))
        return cached = j;
    Material m;
    if (index >= 0) {
        m = convertMaterial(index);
    } else {
        m.name = name;
        m.type = MaterialType::MetallicRoughness;
        m.albedo = {1.0f, 1.0f, 1.0f};
        m.metallic = 1.0f;
        m.roughness = 1.0f;
        m.textureTimesFactor = true;
    }
    m.assetName = editName(index);
    m.assetShape = m_overrides.shape;
    if (const auto it = m_overrides.edits.find(m.assetName); it != m_overrides.edits.end())
        m_loader.applyLookEdits(m, it->second, m_overrides.editsPlace + "/" + it->first);
    // Names stay unique: two assets may both have a "Material.001".
    if (m_loader.materialIndex(m.name) >= 0) {
        const std::string base = m.name + " (" + m_file.filename().string() + ")";
        m.name = base;
        for (int k = 2; m_loader.materialIndex(m.name) >= 0; ++k)
            m.name = base + " " + std::to_string(k);
    }
    return cached = m_loader.addMaterial(std::move(m));
}

std::string GltfImport::editName(int index) const {
    if (index < 0) return "glTF default";
    const std::string& name = m_model.materials[std::size_t(index)].name;
    return name.empty() ? "materials[" + std::to_string(index) + "]" : name;
}

Material GltfImport::convertMaterial(int index) {
    const tinygltf::Material& gm = m_model.materials[std::size_t(index)];
    const std::string place = "materials[" + std::to_string(index) + "]";
    auto number = [&](double v, const std::string& key, double lo, double hi) {
        // A hair outside the range (an exporter's rounding) is clamped; more is an error.
        const double slack = 1e-6 * std::max(1.0, std::abs(hi));
        if (!std::isfinite(v) || v < lo - slack || v > hi + slack)
            fail(place + "." + key, "is " + std::to_string(v) + ", expected a number in [" +
                                        std::to_string(lo) + ", " + std::to_string(hi) + "]");
        return float(std::clamp(v, lo, hi));
    };
    Material m;
    m.name = gm.name.empty() ? m_file.filename().string() + " " + place : gm.name;
    m.type = MaterialType::MetallicRoughness;
    m.textureTimesFactor = true;

    // Base colour, metallic, roughness (spec 3.9.2).
    const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4)
        fail(place + ".pbrMetallicRoughness.baseColorFactor", "expected 4 numbers");
    for (int c = 0; c < 3; ++c)
        m.albedo[c] = number(pbr.baseColorFactor[std::size_t(c)],
                             "pbrMetallicRoughness.baseColorFactor", 0.0, 1.0);
    m.opacity = number(pbr.baseColorFactor[3], "pbrMetallicRoughness.baseColorFactor", 0.0, 1.0);
    m.metallic = number(pbr.metallicFactor, "pbrMetallicRoughness.metallicFactor", 0.0, 1.0);
    m.roughness = number(pbr.roughnessFactor, "pbrMetallicRoughness.roughnessFactor", 0.0, 1.0);
    if (pbr.baseColorTexture.index >= 0) {
        const TextureSlot slot =
            textureSlot(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                        pbr.baseColorTexture.extensions, TextureUse::Color,
                        place + ".pbrMetallicRoughness.baseColorTexture");
        m.texture = slot.texture;
        m.textureTransform = slot.transform;
    }
    if (pbr.metallicRoughnessTexture.index >= 0)
        m.roughnessMetallicMap =
            textureSlot(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                        pbr.metallicRoughnessTexture.extensions, TextureUse::Data,
                        place + ".pbrMetallicRoughness.metallicRoughnessTexture");

    // Normal map (spec 3.9.3).
    if (gm.normalTexture.index >= 0) {
        m.normalMap =
            textureSlot(gm.normalTexture.index, gm.normalTexture.texCoord,
                        gm.normalTexture.extensions, TextureUse::Data, place + ".normalTexture");
        m.normalScale = number(gm.normalTexture.scale, "normalTexture.scale", -1e3, 1e3);
    }
    if (gm.occlusionTexture.index >= 0) {
        // A raster approximation of what a path tracer computes: ignored (docs/assets.md).
    }

    // Emission × KHR_materials_emissive_strength.
    if (!gm.emissiveFactor.empty() && gm.emissiveFactor.size() != 3)
        fail(place + ".emissiveFactor", "expected 3 numbers");
    double strength = 1.0;
    if (const tinygltf::Value* e = extensionOf(gm.extensions, "KHR_materials_emissive_strength");
        e && e->Has("emissiveStrength")) {
        const tinygltf::Value& s = e->Get("emissiveStrength");
        if (!s.IsNumber())
            fail(place + ".extensions.KHR_materials_emissive_strength.emissiveStrength",
                 "expected a number");
        strength = number(s.GetNumberAsDouble(),
                          "extensions.KHR_materials_emissive_strength.emissiveStrength", 0.0,
                          kMaxRadiance);
    }
    for (int c = 0; c < 3 && !gm.emissiveFactor.empty(); ++c) {
        const double e =
            number(gm.emissiveFactor[std::size_t(c)], "emissiveFactor", 0.0, 1.0) * strength;
        if (e > kMaxRadiance)
            fail(place + ".extensions.KHR_materials_emissive_strength",
                 "emissive factor × strength exceeds the largest radiance, 1e18");
        m.emission[c] = float(e);
    }
    if (gm.emissiveTexture.index >= 0)
        m.emissionMap = textureSlot(gm.emissiveTexture.index, gm.emissiveTexture.texCoord,
                                    gm.emissiveTexture.extensions, TextureUse::Color,
                                    place + ".emissiveTexture");

    // KHR_materials_ior, KHR_materials_transmission.
    if (const tinygltf::Value* e = extensionOf(gm.extensions, "KHR_materials_ior");
        e && e->Has("ior")) {
        if (!e->Get("ior").IsNumber())
            fail(place + ".extensions.KHR_materials_ior.ior", "expected a number");
        m.ior = number(e->Get("ior").GetNumberAsDouble(), "extensions.KHR_materials_ior.ior", 1.0,
                       10.0);
    }
    if (const tinygltf::Value* e = extensionOf(gm.extensions, "KHR_materials_transmission")) {
        if (e->Has("transmissionFactor")) {
            if (!e->Get("transmissionFactor").IsNumber())
                fail(place + ".extensions.KHR_materials_transmission.transmissionFactor",
                     "expected a number");
            m.transmission =
                number(e->Get("transmissionFactor").GetNumberAsDouble(),
                       "extensions.KHR_materials_transmission.transmissionFactor", 0.0, 1.0);
        }
        // The texture's R channel multiplies the factor (data, not colour).
        if (e->Has("transmissionTexture")) {
            const std::string tp = place + ".extensions.KHR_materials_transmission";
            const tinygltf::Value& t = e->Get("transmissionTexture");
            auto integer = [&](const char* key, int fallback) {
                if (!t.Has(key)) return fallback;
                const tinygltf::Value& v = t.Get(key);
                if (!v.IsNumber() || v.GetNumberAsDouble() != double(v.GetNumberAsInt()))
                    fail(tp + ".transmissionTexture." + key, "expected an integer");
                return v.GetNumberAsInt();
            };
            if (!t.IsObject() || !t.Has("index"))
                fail(tp + ".transmissionTexture", "expected an object with an index");
            const int index = integer("index", -1), texCoord = integer("texCoord", 0);
            tinygltf::ExtensionMap ext;
            if (t.Has("extensions") && t.Get("extensions").IsObject())
                for (const std::string& key : t.Get("extensions").Keys())
                    ext[key] = t.Get("extensions").Get(key);
            m.transmissionMap =
                textureSlot(index, texCoord, ext, TextureUse::Data, tp + ".transmissionTexture");
        }
    }

    // Alpha (spec 3.9.4).
    if (gm.alphaMode == "OPAQUE" || gm.alphaMode.empty())
        m.alphaMode = AlphaMode::Opaque;
    else if (gm.alphaMode == "MASK")
        m.alphaMode = AlphaMode::Mask;
    else if (gm.alphaMode == "BLEND")
        m.alphaMode = AlphaMode::Blend;
    else
        fail(place + ".alphaMode", "is '" + gm.alphaMode + "', expected OPAQUE, MASK or BLEND");
    m.alphaCutoff = number(gm.alphaCutoff, "alphaCutoff", 0.0, 1e30);
    return m;
}

TextureSlot GltfImport::textureSlot(int index, int texCoord, const tinygltf::ExtensionMap& ext,
                                    TextureUse use, const std::string& place) {
    TextureSlot slot;
    slot.texture = texture(index, use, place);
    // KHR_texture_transform: uv' = T(offset) · R(rotation) · S(scale) · uv in glTF's texture
    // space (origin top-left); Glint's (origin bottom-left) is its conjugate by the flip
    // F(u, v) = (u, 1 − v): F · T · R · S · F.
    if (const tinygltf::Value* t = extensionOf(ext, "KHR_texture_transform")) {
        const std::string tp = place + ".extensions.KHR_texture_transform";
        auto pair = [&](const char* key, double fallback, double out[2]) {
            out[0] = out[1] = fallback;
            if (!t->Has(key)) return;
            const tinygltf::Value& v = t->Get(key);
            if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
                fail(tp + "." + key, "expected 2 numbers");
            out[0] = v.Get(0).GetNumberAsDouble(), out[1] = v.Get(1).GetNumberAsDouble();
            if (!std::isfinite(out[0]) || !std::isfinite(out[1]) || std::abs(out[0]) > 1e6 ||
                std::abs(out[1]) > 1e6)
                fail(tp + "." + key, "expected finite numbers of magnitude at most 1e6");
        };
        double offset[2], scale[2];
        pair("offset", 0.0, offset);
        pair("scale", 1.0, scale);
        double rotation = 0.0;
        if (t->Has("rotation")) {
            if (!t->Get("rotation").IsNumber()) fail(tp + ".rotation", "expected a number");
            rotation = t->Get("rotation").GetNumberAsDouble();
            if (!std::isfinite(rotation) || std::abs(rotation) > 1e6)
                fail(tp + ".rotation", "expected a finite number of magnitude at most 1e6");
        }
        if (t->Has("texCoord") && t->Get("texCoord").IsNumber())
            texCoord = t->Get("texCoord").GetNumberAsInt();
        Mat3 translate, rotate, scaleM, flip;
        translate.m[0][2] = offset[0], translate.m[1][2] = offset[1];
        const double c = std::cos(rotation), s = std::sin(rotation);
        rotate.m[0][0] = c, rotate.m[0][1] = s, rotate.m[1][0] = -s, rotate.m[1][1] = c;
        scaleM.m[0][0] = scale[0], scaleM.m[1][1] = scale[1];
        flip.m[1][1] = -1.0, flip.m[1][2] = 1.0;
        const Mat3 glint = flip * translate * rotate * scaleM * flip;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 3; ++j) slot.transform.m[i][j] = float(glint.m[i][j]);
        slot.transform.identity = false;
    }
    if (texCoord == 1)
        slot.transform.set = 1;
    else if (texCoord != 0)
        warn(place + " uses TEXCOORD_" + std::to_string(texCoord) +
             "; Glint reads TEXCOORD_0 and TEXCOORD_1 only and uses TEXCOORD_0 instead");
    return slot;
}

int GltfImport::texture(int index, TextureUse use, const std::string& place) {
    if (index < 0 || std::size_t(index) >= m_model.textures.size())
        fail(place + ".index", "names textures[" + std::to_string(index) + "], but the asset has " +
                                   std::to_string(m_model.textures.size()));
    const auto key = std::pair{index, int(use)};
    if (const auto it = m_textures.find(key); it != m_textures.end()) return it->second;
    const tinygltf::Texture& gt = m_model.textures[std::size_t(index)];
    const std::string texturePlace = "textures[" + std::to_string(index) + "]";
    if (gt.source < 0)
        fail(texturePlace,
             "has no PNG or JPEG source image (an extension's image format, such "
             "as KTX2 or WebP, is not read)");
    if (std::size_t(gt.source) >= m_model.images.size())
        fail(texturePlace + ".source", "names images[" + std::to_string(gt.source) +
                                           "], but the asset has " +
                                           std::to_string(m_model.images.size()));
    Texture source;
    source.use = use;
    if (gt.sampler >= 0) {
        if (std::size_t(gt.sampler) >= m_model.samplers.size())
            fail(texturePlace + ".sampler", "names samplers[" + std::to_string(gt.sampler) +
                                                "], but the asset has " +
                                                std::to_string(m_model.samplers.size()));
        const tinygltf::Sampler& s = m_model.samplers[std::size_t(gt.sampler)];
        const std::string sp = "samplers[" + std::to_string(gt.sampler) + "]";
        bool known = false;
        source.wrapS = wrapMode(s.wrapS, known);
        if (!known)
            fail(sp + ".wrapS",
                 "is " + std::to_string(s.wrapS) + ", expected 33071, 33648 or 10497");
        source.wrapT = wrapMode(s.wrapT, known);
        if (!known)
            fail(sp + ".wrapT",
                 "is " + std::to_string(s.wrapT) + ", expected 33071, 33648 or 10497");
        // Pixel art asks for NEAREST magnification; Glint filters every texture.
        if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST)
            warnOnce("magFilter", sp + ".magFilter is NEAREST, which Glint does not honour: "
                                       "textures are filtered, so magnified texels have soft "
                                       "edges");
    }

    // The image: a file beside the asset, a bufferView, or a data URI.
    const tinygltf::Image& image = m_model.images[std::size_t(gt.source)];
    const std::string imagePlace = "images[" + std::to_string(gt.source) + "]";
    if (image.bufferView < 0 && !image.uri.empty()) {
        if (const auto problem = undecodedDataUri(image.uri)) fail(imagePlace + ".uri", *problem);
        const fs::path file = m_file.parent_path() / fs::path(decodeUri(image.uri));
        requireRegularFile(file, "image", "an image file", m_file.string(), imagePlace);
        source.path = file;
    } else if (image.bufferView >= 0) {
        if (std::size_t(image.bufferView) >= m_model.bufferViews.size())
            fail(imagePlace + ".bufferView", "names a missing bufferView");
        const tinygltf::BufferView& view = m_model.bufferViews[std::size_t(image.bufferView)];
        if (view.buffer < 0 || std::size_t(view.buffer) >= m_buffers.count())
            fail("bufferViews[" + std::to_string(image.bufferView) + "]", "names a missing buffer");
        const std::size_t size = m_buffers.size(std::size_t(view.buffer));
        if (view.byteOffset > size || view.byteLength > size - view.byteOffset)
            fail("bufferViews[" + std::to_string(image.bufferView) + "]",
                 "goes past the end of its buffer (" + std::to_string(size) + " bytes)");
        std::vector<unsigned char> scratch;
        const unsigned char* bytes = m_buffers.bytes(std::size_t(view.buffer), view.byteOffset,
                                                     view.byteOffset + view.byteLength, scratch);
        source.bytes =
            std::make_shared<const std::vector<unsigned char>>(bytes, bytes + view.byteLength);
        source.path = m_file.string() + "#" + imagePlace;
    } else {
        if (image.image.empty()) fail(imagePlace, "its data URI holds no image");
        source.bytes = std::make_shared<const std::vector<unsigned char>>(image.image);
        source.path = m_file.string() + "#" + imagePlace;
    }
    int loaded = -1;
    try {
        loaded = m_loader.loadTexture(source, imagePlace);
    } catch (const Error& e) {
        // Name the asset and the image, with the decoder's own place in the message.
        if (e.file().rfind(m_file.string(), 0) == 0)
            throw Error(e.kind(), e.message(), m_file.string(), e.where());
        throw Error(e.kind(),
                    "image '" + e.file() + "'" + (e.where().empty() ? "" : " (" + e.where() + ")") +
                        ": " + e.message(),
                    m_file.string(), imagePlace);
    }
    m_textures[key] = loaded;
    return loaded;
}

}  // namespace glint::render::detail
