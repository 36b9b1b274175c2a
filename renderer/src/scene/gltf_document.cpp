#include "scene/gltf_document.h"

#include <cmath>
#include <sstream>
#include <string>

#include "glint/image/error.h"
#include "scene/json_reader.h"
#include "scene/json_scan.h"

namespace glint::render::detail {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

[[noreturn]] void failDocument(const fs::path& file, const std::string& place,
                               const std::string& what) {
    throw Error(ErrorKind::Format, what, file.string(), place);
}

/// A value as written, cut to 40 characters.
std::string shown(const json& value) {
    std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return text;
}

/// The bytes of one component of an accessor's componentType, or 0 for an unknown type.
std::size_t componentBytes(const json& componentType) {
    if (!componentType.is_number_integer()) return 0;
    switch (componentType.get<long long>()) {
        case 5120:  // BYTE
        case 5121:  // UNSIGNED_BYTE
            return 1;
        case 5122:  // SHORT
        case 5123:  // UNSIGNED_SHORT
            return 2;
        case 5125:  // UNSIGNED_INT
        case 5126:  // FLOAT
            return 4;
        default:
            return 0;
    }
}

/// The non-negative integer `key` of `object` (0 when absent), or -1 when it is not one.
long long offsetOf(const json& object, const char* key) {
    if (!object.contains(key)) return 0;
    const json& v = object[key];
    return v.is_number_unsigned()
               ? (long long)std::min<std::uint64_t>(v.get<std::uint64_t>(), std::uint64_t(1) << 62)
               : -1;
}

/// The array `key` of the document, or null when it is absent or not an array.
const json* arrayOf(const json& doc, const char* key) {
    const auto it = doc.find(key);
    return it == doc.end() || !it->is_array() ? nullptr : &*it;
}

void checkExtensionLists(const json& doc, const fs::path& file) {
    for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
        if (!doc.contains(key)) continue;
        const json& list = doc[key];
        if (!list.is_array())
            failDocument(file, key,
                         "is " + shown(list) + ", expected an array of strings (extension names)");
        for (std::size_t i = 0; i < list.size(); ++i)
            if (!list[i].is_string())
                failDocument(file, std::string(key) + "[" + std::to_string(i) + "]",
                             "is " + shown(list[i]) + ", expected a string (an extension name)");
    }
}

void checkBuffers(const json& doc, const GltfText& text, const fs::path& file) {
    const json* buffers = arrayOf(doc, "buffers");
    if (!buffers) return;
    for (std::size_t i = 0; i < buffers->size(); ++i) {
        const json& b = (*buffers)[i];
        if (!b.is_object() || b.contains("uri")) continue;
        const std::string place = "buffers[" + std::to_string(i) + "]";
        // glTF 2.0, "Binary glTF Layout": only the first buffer of a .glb, which the BIN chunk
        // holds, may have no uri.
        if (!text.binary || i != 0)
            failDocument(file, place,
                         "has no uri; only the first buffer of a binary glTF (.glb), held by its "
                         "BIN chunk, may have none");
        if (!text.hasBin)
            failDocument(file, place,
                         "has no uri, and the binary glTF has no BIN chunk (or an empty one) to "
                         "hold it");
    }
}

void checkBufferViews(const json& doc, const fs::path& file) {
    const json* views = arrayOf(doc, "bufferViews");
    if (!views) return;
    for (std::size_t i = 0; i < views->size(); ++i) {
        const json& v = (*views)[i];
        if (!v.is_object() || !v.contains("byteStride")) continue;
        const json& stride = v["byteStride"];
        // glTF 2.0, bufferView.byteStride: minimum 4, maximum 252, a multiple of 4.
        const bool good = stride.is_number_unsigned() && stride.get<std::uint64_t>() >= 4 &&
                          stride.get<std::uint64_t>() <= 252 &&
                          stride.get<std::uint64_t>() % 4 == 0;
        if (!good)
            failDocument(file, "bufferViews[" + std::to_string(i) + "].byteStride",
                         "is " + shown(stride) + ", expected a multiple of 4 in [4, 252]");
    }
}

void checkAccessorAlignment(const json& doc, const fs::path& file) {
    const json* accessors = arrayOf(doc, "accessors");
    if (!accessors) return;
    const json* views = arrayOf(doc, "bufferViews");
    for (std::size_t i = 0; i < accessors->size(); ++i) {
        const json& a = (*accessors)[i];
        if (!a.is_object() || !a.contains("componentType")) continue;
        const std::size_t size = componentBytes(a["componentType"]);
        const long long offset = offsetOf(a, "byteOffset");
        if (size == 0 || offset < 0) continue;  // tinygltf names these
        const std::string place = "accessors[" + std::to_string(i) + "].byteOffset";
        const std::string why =
            ", the size of its components (glTF requires an accessor's data "
            "to be aligned to its component size)";
        // glTF 2.0, "Data Alignment": accessor.byteOffset and bufferView.byteOffset +
        // accessor.byteOffset are multiples of the component size.
        if (offset % (long long)size != 0)
            failDocument(file, place,
                         "is " + std::to_string(offset) + ", not a multiple of " +
                             std::to_string(size) + why);
        if (!views || !a.contains("bufferView") || !a["bufferView"].is_number_unsigned() ||
            a["bufferView"].get<std::uint64_t>() >= views->size())
            continue;
        const std::uint64_t view = a["bufferView"].get<std::uint64_t>();
        const long long viewOffset = offsetOf((*views)[view], "byteOffset");
        if (viewOffset >= 0 && (viewOffset + offset) % (long long)size != 0)
            failDocument(file, place,
                         "bufferViews[" + std::to_string(view) + "].byteOffset " +
                             std::to_string(viewOffset) + " + byteOffset " +
                             std::to_string(offset) + " = " + std::to_string(viewOffset + offset) +
                             " is not a multiple of " + std::to_string(size) + why);
    }
}

void checkPrimitiveModes(const json& doc, const fs::path& file) {
    const json* meshes = arrayOf(doc, "meshes");
    if (!meshes) return;
    for (std::size_t m = 0; m < meshes->size(); ++m) {
        const json& mesh = (*meshes)[m];
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array())
            continue;
        const json& prims = mesh["primitives"];
        for (std::size_t p = 0; p < prims.size(); ++p) {
            if (!prims[p].is_object() || !prims[p].contains("mode")) continue;
            const json& mode = prims[p]["mode"];
            if (mode.is_number_unsigned() && mode.get<std::uint64_t>() <= 6) continue;
            failDocument(
                file,
                "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "].mode",
                "is " + shown(mode) +
                    ", expected an integer in [0, 6] (0 points, 1 lines, 2 line loop, 3 "
                    "line strip, 4 triangles, 5 triangle strip, 6 triangle fan)");
        }
    }
}

void checkNodeTransforms(const json& doc, const fs::path& file) {
    const json* nodes = arrayOf(doc, "nodes");
    if (!nodes) return;
    struct Key {
        const char* name;
        std::size_t count;
    };
    for (std::size_t n = 0; n < nodes->size(); ++n) {
        const json& node = (*nodes)[n];
        if (!node.is_object()) continue;
        for (const Key key :
             {Key{"translation", 3}, Key{"rotation", 4}, Key{"scale", 3}, Key{"matrix", 16}}) {
            if (!node.contains(key.name)) continue;
            const json& v = node[key.name];
            bool good = v.is_array() && v.size() == key.count;
            for (std::size_t i = 0; good && i < v.size(); ++i) good = v[i].is_number();
            if (!good)
                failDocument(file, "nodes[" + std::to_string(n) + "]." + key.name,
                             "is " + shown(v) + ", expected an array of " +
                                 std::to_string(key.count) + " numbers");
        }
    }
}

void checkCameras(const json& doc, const fs::path& file) {
    const json* cameras = arrayOf(doc, "cameras");
    if (!cameras) return;
    for (std::size_t c = 0; c < cameras->size(); ++c) {
        const json& cam = (*cameras)[c];
        if (!cam.is_object() || !cam.contains("perspective") || !cam["perspective"].is_object() ||
            !cam["perspective"].contains("aspectRatio"))
            continue;
        const json& aspect = cam["perspective"]["aspectRatio"];
        if (aspect.is_number() && aspect.get<double>() >= kMinGltfAspectRatio &&
            aspect.get<double>() <= kMaxGltfAspectRatio)
            continue;
        std::ostringstream msg;
        msg << "is " << shown(aspect) << ", expected a width / height ratio in ["
            << kMinGltfAspectRatio << ", " << kMaxGltfAspectRatio
            << "] (or none, to leave the film's shape open)";
        failDocument(file, "cameras[" + std::to_string(c) + "].perspective.aspectRatio", msg.str());
    }
}

void checkMaterials(const json& doc, const fs::path& file) {
    const json* materials = arrayOf(doc, "materials");
    if (!materials) return;
    for (std::size_t m = 0; m < materials->size(); ++m) {
        const json& mat = (*materials)[m];
        if (!mat.is_object() || !mat.contains("alphaCutoff")) continue;
        const json& cutoff = mat["alphaCutoff"];
        if (cutoff.is_number() && cutoff.get<double>() >= 0.0 &&
            std::isfinite(cutoff.get<double>()))
            continue;
        failDocument(file, "materials[" + std::to_string(m) + "].alphaCutoff",
                     "is " + shown(cutoff) +
                         ", expected a number >= 0 (the alpha below which a MASK material is "
                         "transparent)");
    }
}

}  // namespace

void checkGltfNesting(const GltfText& text, const fs::path& file) {
    JsonScan scan;
    scan.feed(text.text, [&](const JsonToken& t, const JsonScan&) {
        if (t.kind != JsonToken::Kind::Open || t.depth <= kMaxGltfNesting) return;
        failDocument(file,
                     "line " + std::to_string(t.line) + ", column " + std::to_string(t.column) +
                         (text.binary ? " of the JSON chunk" : ""),
                     "arrays and objects nested " + std::to_string(t.depth) + " deep (byte " +
                         std::to_string(text.chunkOffset + t.byte) +
                         "); Glint reads glTF JSON nested at most " +
                         std::to_string(kMaxGltfNesting) + " deep (real assets nest about 10)");
    });
}

json parseGltfDocument(const GltfText& text, const fs::path& file) {
    // nlohmann-json's DOM builder with each data URI string cut to its scheme. (A parse
    // callback would do the same, but its builder searches every element of the enclosing
    // array for a discarded value at each object's end: quadratic in the length of an array of
    // objects, hours for a glb of a million meshes.)
    struct CutDataUris : nlohmann::detail::json_sax_dom_parser<json> {
        using json_sax_dom_parser::json_sax_dom_parser;
        bool string(std::string& value) {
            if (value.rfind("data:", 0) == 0) value = "data:";
            return json_sax_dom_parser::string(value);
        }
    };
    try {
        json doc;
        CutDataUris builder(doc, true);
        json::sax_parse(text.text.begin(), text.text.end(), &builder);
        return doc;
    } catch (const json::exception& e) {
        throwMalformedJson(e, text.text, file.string(), text.binary ? " of the JSON chunk" : "");
    }
}

void checkGltfDocument(const json& doc, const GltfText& text, const fs::path& file) {
    if (!doc.is_object())
        failDocument(file, "", "the document is " + shown(doc) + ", expected a JSON object");
    checkExtensionLists(doc, file);
    checkBuffers(doc, text, file);
    checkBufferViews(doc, file);
    checkAccessorAlignment(doc, file);
    checkPrimitiveModes(doc, file);
    checkNodeTransforms(doc, file);
    checkCameras(doc, file);
    checkMaterials(doc, file);
}

}  // namespace glint::render::detail
