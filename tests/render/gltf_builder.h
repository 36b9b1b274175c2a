// Small glTF assets written by the tests (gltf_import_test.cpp, gltf_hostile_test.cpp): a
// document and its one binary buffer, written as a .gltf with a base64 data URI or as a .glb
// built byte by byte.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace glint::render::test_gltf {

namespace fs = std::filesystem;
using nlohmann::json;

inline std::string base64(const std::vector<unsigned char>& bytes) {
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::uint32_t n = std::uint32_t(bytes[i]) << 16 |
                                (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                                (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
        out += table[(n >> 18) & 63];
        out += table[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(n >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

/// Builds a glTF document and its one binary buffer.
class GltfBuilder {
  public:
    json doc = {{"asset", {{"version", "2.0"}}}};
    std::vector<unsigned char> bin;

    /// A bufferView over `bytes` appended to the buffer (4-byte aligned).
    int view(const void* data, std::size_t bytes) {
        while (bin.size() % 4) bin.push_back(0);
        const std::size_t offset = bin.size();
        const auto* p = static_cast<const unsigned char*>(data);
        bin.insert(bin.end(), p, p + bytes);
        doc["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
        return int(doc["bufferViews"].size()) - 1;
    }
    int accessor(int view, int componentType, const char* type, std::size_t count) {
        doc["accessors"].push_back({{"bufferView", view},
                                    {"componentType", componentType},
                                    {"type", type},
                                    {"count", count}});
        return int(doc["accessors"].size()) - 1;
    }
    int floats(const std::vector<float>& v, const char* type, int components) {
        return accessor(view(v.data(), v.size() * 4), 5126, type,
                        v.size() / std::size_t(components));
    }
    int u16(const std::vector<std::uint16_t>& v) {
        return accessor(view(v.data(), v.size() * 2), 5123, "SCALAR", v.size());
    }
    /// A unit quad in z = 0 facing +z (two triangles), with normals and glTF uvs (top-left
    /// origin); indexed or not. Returns the mesh index.
    int quad(int material = -1, bool indexed = true, const std::string& name = "quad") {
        std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        std::vector<float> n = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
        std::vector<float> uv = {0, 1, 1, 1, 1, 0, 0, 0};
        const std::vector<int> order = {0, 1, 2, 0, 2, 3};
        if (!indexed) {
            std::vector<float> p2, n2, uv2;
            for (int i : order) {
                for (int c = 0; c < 3; ++c) p2.push_back(p[std::size_t(3 * i + c)]);
                for (int c = 0; c < 3; ++c) n2.push_back(n[std::size_t(3 * i + c)]);
                for (int c = 0; c < 2; ++c) uv2.push_back(uv[std::size_t(2 * i + c)]);
            }
            p = p2, n = n2, uv = uv2;
        }
        json prim = {{"attributes",
                      {{"POSITION", floats(p, "VEC3", 3)},
                       {"NORMAL", floats(n, "VEC3", 3)},
                       {"TEXCOORD_0", floats(uv, "VEC2", 2)}}}};
        if (indexed) prim["indices"] = u16({0, 1, 2, 0, 2, 3});
        if (material >= 0) prim["material"] = material;
        doc["meshes"].push_back({{"name", name}, {"primitives", json::array({prim})}});
        return int(doc["meshes"].size()) - 1;
    }
    int node(json n) {
        doc["nodes"].push_back(std::move(n));
        return int(doc["nodes"].size()) - 1;
    }
    /// The scene of the given root nodes.
    void scene(const std::vector<int>& roots) {
        doc["scenes"] = json::array({{{"nodes", roots}}});
        doc["scene"] = 0;
    }

    /// The .gltf text with the buffer as a base64 data URI.
    std::string gltf() const {
        json d = doc;
        d["buffers"] =
            json::array({{{"byteLength", bin.size()},
                          {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
        return d.dump();
    }
    /// The .glb bytes (JSON chunk, then BIN chunk). `declaredLength` > 0 replaces buffer 0's
    /// byteLength; `withBin` false leaves the BIN chunk out (both for bad-input tests).
    std::vector<unsigned char> glb(std::size_t declaredLength = 0, bool withBin = true) const {
        json d = doc;
        d["buffers"] =
            json::array({{{"byteLength", declaredLength ? declaredLength : bin.size()}}});
        return glbOf(d.dump(), withBin);
    }
    /// The .glb bytes of the document text `text` (as written, e.g. nested too deep for a json
    /// value) and, with `withBin`, the buffer as its BIN chunk.
    std::vector<unsigned char> glbOf(std::string text, bool withBin = true) const {
        while (text.size() % 4) text += ' ';
        std::vector<unsigned char> data = bin;
        while (data.size() % 4) data.push_back(0);
        std::vector<unsigned char> out;
        auto u32 = [&](std::uint32_t v) {
            for (int i = 0; i < 4; ++i) out.push_back((unsigned char)(v >> (8 * i)));
        };
        if (!withBin) data.clear();
        const std::size_t binChunk = withBin ? 8 + data.size() : 0;
        u32(0x46546C67), u32(2), u32(std::uint32_t(12 + 8 + text.size() + binChunk));
        u32(std::uint32_t(text.size())), u32(0x4E4F534A);
        out.insert(out.end(), text.begin(), text.end());
        if (withBin) {
            u32(std::uint32_t(data.size())), u32(0x004E4942);
            out.insert(out.end(), data.begin(), data.end());
        }
        return out;
    }
};

inline fs::path writeBytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path;
}

/// A scene.json placing `asset` (no camera block unless given).
inline std::string sceneJson(const std::string& asset, const std::string& extra = "",
                             const std::string& shapeExtra = "") {
    return R"({"film": {"width": 8, "height": 6}, "environment": {"color": [1, 1, 1]},
               "shapes": [{"gltf": ")" +
           asset + "\"" + shapeExtra + "}]" + extra + "}";
}

}  // namespace glint::render::test_gltf
