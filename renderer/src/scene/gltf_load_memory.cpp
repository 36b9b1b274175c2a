// The load of a glTF asset, predicted before it is parsed (predictGltfLoad, the glTF format's
// predictLoad; load_memory.h): a streaming scan of its JSON (JsonScan) and its images' headers.
// The rates are the sizes of the objects tinygltf and the import make, checked against the peak
// resident size of loads of generated assets (docs/lab/mesh-memory.md).
#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include "glint/image/memory.h"
#include "scene/gltf_file.h"
#include "scene/gltf_import.h"
#include "scene/json_scan.h"
#include "scene/load_memory.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

/// Bytes a JSON value costs in the two documents alive while tinygltf parses (Glint's copy, in
/// which the buffers it reads itself are rewritten, and tinygltf's own): nlohmann-json's 16-byte
/// value in its parent's array, grown by half again on average, twice.
constexpr std::uint64_t kValueBytes = 2 * 24;
/// Bytes an object member costs there besides its value: a std::map node (links, key string,
/// value) of 96 bytes as glibc allocates it, twice.
constexpr std::uint64_t kMemberBytes = 2 * 96;
/// Glint's Material of a glTF material, its name, its entries in the loader's maps by name and
/// what converting it leaves in the heap: about 1.4 KB a material measured beyond the object
/// (a glb of 20000 one-triangle primitives with a material each, lab/bench/load_memory_assets.py).
constexpr std::uint64_t kMaterialBytes = sizeof(Material) + 1536;

std::uint64_t number(std::string_view text) {
    std::uint64_t v = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return v;
        v = saturatingAdd(saturatingMul(v, 10), std::uint64_t(c - '0'));
    }
    return v;
}

/// Width, height and channels of a PNG or JPEG image from its header (`in` positioned at its
/// first byte); zeros when it is neither or the header is damaged (its reader says so later).
struct ImageSize {
    std::uint64_t width = 0, height = 0, channels = 0;
};
ImageSize imageSize(std::istream& in) {
    unsigned char h[26] = {};
    if (!in.read(reinterpret_cast<char*>(h), 2)) return {};
    auto be16 = [](const unsigned char* p) { return std::uint64_t(p[0]) << 8 | p[1]; };
    if (h[0] == 0x89 && h[1] == 'P') {
        // PNG: the signature, then the IHDR chunk (width, height, bit depth, colour type).
        if (!in.read(reinterpret_cast<char*>(h + 2), 24) || std::memcmp(h + 12, "IHDR", 4) != 0)
            return {};
        const std::uint64_t w = be16(h + 16) << 16 | be16(h + 18),
                            hgt = be16(h + 20) << 16 | be16(h + 22);
        const std::uint64_t channels = h[25] == 0 ? 1 : h[25] == 4 ? 2 : h[25] == 6 ? 4 : 3;
        return {w, hgt, channels};
    }
    if (h[0] != 0xFF || h[1] != 0xD8) return {};
    // JPEG: markers and their lengths up to a start of frame (SOF0…SOF15 but DHT, JPG, DAC).
    for (int markers = 0; markers < 10000; ++markers) {
        unsigned char m[4];
        if (!in.read(reinterpret_cast<char*>(m), 4) || m[0] != 0xFF) return {};
        const unsigned code = m[1];
        const std::uint64_t length = be16(m + 2);
        if (code >= 0xC0 && code <= 0xCF && code != 0xC4 && code != 0xC8 && code != 0xCC) {
            unsigned char f[6];
            if (!in.read(reinterpret_cast<char*>(f), 6)) return {};
            return {be16(f + 3), be16(f + 1), f[5] >= 3 ? 3u : 1u};
        }
        if (length < 2 || !in.seekg(std::streamoff(length - 2), std::ios::cur)) return {};
    }
    return {};
}

/// Bytes an image of `size` takes while Glint decodes it (glint::readImage's float channels and
/// the RGBA float texture made from them), plus its `encoded` bytes held beside.
std::uint64_t decodedBytes(const ImageSize& size, std::uint64_t encoded) {
    const std::uint64_t texels = saturatingMul(size.width, size.height);
    return saturatingAdd(saturatingMul(texels, 4 * (4 + size.channels)), encoded);
}

/// The first bytes of base64 `text` decoded (as far as it goes).
std::string base64Head(std::string_view text) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    std::string out;
    unsigned bits = 0, have = 0;
    for (const char c : text) {
        const int v = value(c);
        if (v < 0) break;
        bits = bits << 6 | unsigned(v);
        if ((have += 6) >= 8) out.push_back(char((bits >> (have -= 8)) & 0xFF));
    }
    return out;
}

/// Glint's bytes an element of a primitive's attribute becomes (Mesh's arrays), 0 for one it
/// does not keep.
std::uint64_t glintElementBytes(std::string_view attribute) {
    if (attribute == "POSITION" || attribute == "NORMAL") return 12;
    if (attribute == "TANGENT" || attribute == "COLOR_0") return 16;
    if (attribute == "TEXCOORD_0" || attribute == "TEXCOORD_1") return 8;
    return 0;
}

/// What the scan of a glTF's JSON counted.
struct GltfCensus {
    std::uint64_t values = 0, members = 0, stringHeap = 0;
    std::uint64_t meshes = 0, primitives = 0, nodes = 0, accessors = 0, materials = 0, textures = 0,
                  images = 0, bufferViews = 0, buffers = 0, others = 0;
    bool normalTextures = false;
    /// Per accessor: count; per use by a primitive: the accessor and Glint's element bytes.
    std::vector<std::uint64_t> accessorCount;
    struct Use {
        enum Kind { Indices, Positions, Other };
        std::uint64_t accessor = 0, bytes = 0;
        Kind kind = Other;
        std::uint64_t mesh = 0;
    };
    std::vector<std::uint32_t> meshPrimitives;  ///< per mesh: its primitives
    std::vector<Use> uses;
    /// Per primitive being read: its POSITION accessor and whether it has indices.
    std::int64_t position = -1;
    bool indexed = false;
    /// Per buffer view: buffer, byteOffset; per image: uri head, its length, bufferView.
    struct View {
        std::uint64_t buffer = 0, offset = 0, length = 0;
    };
    std::vector<View> views;
    struct Img {
        std::string uri;
        std::uint64_t uriLength = 0;
        std::int64_t view = -1;
    };
    std::vector<Img> imgs;
    std::vector<std::string> bufferUris;  ///< per buffer: its uri (empty: none)

    /// Records one token of the scan.
    void token(const JsonToken& t, const JsonScan& scan);
};

void GltfCensus::token(const JsonToken& t, const JsonScan& scan) {
    using Kind = JsonToken::Kind;
    if (t.kind == Kind::Close) {
        // A primitive ends: without indices its positions become 4-byte indices.
        if (t.depth == 5 && !t.array && scan.frame(1).key == "meshes" &&
            scan.frame(3).key == "primitives" && !indexed && position >= 0)
            uses.push_back({std::uint64_t(position), 4, Use::Indices, meshes - 1});
        return;
    }
    if (t.kind == Kind::Key) {
        ++members;
        if (t.length > 15) stringHeap += t.length + 1;
        if (t.text == "normalTexture" && scan.frame(1).key == "materials") normalTextures = true;
        return;
    }
    ++values;
    if (t.kind == Kind::String && t.length > 15) stringHeap += t.length + 1;
    const int d = t.depth;
    if (d < 2 || scan.frame(1).array) return;
    const std::string& section = scan.frame(1).key;
    // An element of a top-level array: one tinygltf object.
    if (d == 3 && t.kind == Kind::Open && scan.frame(2).array) {
        if (section == "meshes")
            ++meshes, meshPrimitives.push_back(0);
        else if (section == "nodes")
            ++nodes;
        else if (section == "accessors")
            ++accessors, accessorCount.push_back(0);
        else if (section == "materials")
            ++materials;
        else if (section == "textures")
            ++textures;
        else if (section == "images")
            ++images, imgs.emplace_back();
        else if (section == "bufferViews")
            ++bufferViews, views.emplace_back();
        else if (section == "buffers")
            ++buffers, bufferUris.emplace_back();
        else
            ++others;
        return;
    }
    if (d < 3 || !scan.frame(2).array || scan.frame(3).array) return;
    const std::string& key = scan.frame(3).key;
    const bool scalar = t.kind == Kind::Scalar, text = t.kind == Kind::String;
    if (section == "accessors" && d == 3 && scalar && key == "count" && !accessorCount.empty()) {
        accessorCount.back() = number(t.text);
    } else if (section == "bufferViews" && d == 3 && scalar && !views.empty()) {
        if (key == "buffer") views.back().buffer = number(t.text);
        if (key == "byteOffset") views.back().offset = number(t.text);
        if (key == "byteLength") views.back().length = number(t.text);
    } else if (section == "images" && d == 3 && !imgs.empty()) {
        if (text && key == "uri") imgs.back().uri = t.text, imgs.back().uriLength = t.length;
        if (scalar && key == "bufferView") imgs.back().view = std::int64_t(number(t.text));
    } else if (section == "buffers" && d == 3 && text && key == "uri" && !bufferUris.empty()) {
        bufferUris.back() = t.text;
    } else if (section == "meshes" && key == "primitives" && d >= 4 && scan.frame(4).array) {
        // meshes[m].primitives[p]: a primitive starts, names its indices or an attribute.
        if (d == 5 && t.kind == Kind::Open && !t.array) {
            ++primitives;
            if (!meshPrimitives.empty()) ++meshPrimitives.back();
            position = -1;
            indexed = false;
        } else if (d == 5 && scalar && scan.frame(5).key == "indices") {
            indexed = true;
            uses.push_back({number(t.text), 4, Use::Indices, meshes - 1});
        } else if (d == 6 && scalar && scan.frame(5).key == "attributes") {
            const std::string& attribute = scan.frame(6).key;
            if (attribute == "POSITION") position = std::int64_t(number(t.text));
            if (const std::uint64_t bytes = glintElementBytes(attribute))
                uses.push_back({number(t.text), bytes,
                                attribute == "POSITION" ? Use::Positions : Use::Other, meshes - 1});
        }
    }
}

/// The decoded size of image `img` of the asset `path` (JSON chunk or BIN chunk at `binOffset`
/// in a .glb): from its data URI's first bytes, its file's header or its bytes in a buffer.
std::uint64_t imageBytes(const GltfCensus& c, const GltfCensus::Img& img, const fs::path& path,
                         std::uint64_t binOffset) {
    if (img.uri.rfind("data:", 0) == 0) {
        const std::size_t comma = img.uri.find(',');
        if (comma == std::string::npos) return 0;
        std::istringstream head(base64Head(std::string_view(img.uri).substr(comma + 1)));
        return decodedBytes(imageSize(head), (img.uriLength - comma) / 4 * 3);
    }
    if (!img.uri.empty()) {
        const fs::path file = path.parent_path() / fs::path(decodeUri(img.uri));
        std::ifstream in(file, std::ios::binary);
        return in ? decodedBytes(imageSize(in), 0) : 0;
    }
    if (img.view < 0 || std::uint64_t(img.view) >= c.views.size()) return 0;
    const GltfCensus::View& v = c.views[std::size_t(img.view)];
    fs::path file = path;
    std::uint64_t offset = binOffset + v.offset;
    if (v.buffer < c.bufferUris.size() && !c.bufferUris[v.buffer].empty()) {
        if (c.bufferUris[v.buffer].rfind("data:", 0) == 0) return 0;
        file = path.parent_path() / fs::path(decodeUri(c.bufferUris[v.buffer]));
        offset = v.offset;
    } else if (binOffset == 0) {
        return 0;
    }
    std::ifstream in(file, std::ios::binary);
    if (!in || !in.seekg(std::streamoff(offset))) return 0;
    return decodedBytes(imageSize(in), v.length);
}

}  // namespace

LoadPrediction predictGltfLoad(const fs::path& path) {
    std::error_code ec;
    const std::uint64_t size = fs::file_size(path, ec);
    if (ec) return {};
    // The JSON: a .glb's first chunk, or the whole .gltf.
    std::uint64_t jsonOffset = 0, jsonSize = size, binOffset = 0;
    {
        std::ifstream in(path, std::ios::binary);
        unsigned char h[28] = {};
        in.read(reinterpret_cast<char*>(h), 28);
        if (in.gcount() >= 20 && le32(h) == kGlbMagic) {
            jsonOffset = 20;
            jsonSize = le32(h + 12);
            if (jsonSize > size - 20) return {};
            const std::uint64_t bin = 20 + jsonSize;
            unsigned char b[8];
            if (size >= bin + 8 && in.seekg(std::streamoff(bin)) &&
                in.read(reinterpret_cast<char*>(b), 8) && le32(b + 4) == kGlbChunkBin)
                binOffset = bin + 8;
        }
    }
    GltfCensus c;
    JsonScan scan;
    auto onToken = [&](const JsonToken& t, const JsonScan& s) { c.token(t, s); };
    if (!readBlocks(path, jsonOffset, jsonSize,
                    [&](std::string_view piece) { scan.feed(piece, onToken); }))
        return {};
    scan.finish(onToken);

    LoadPrediction p;
    // Glint's meshes: the accessors the primitives use, at Glint's element sizes; a material per
    // triangle of a mesh of several primitives, a face normal per triangle in a scene of up to
    // kFaceNormalTriangles; tangents where normal maps need them.
    std::uint64_t indices = 0, positions = 0;
    for (const GltfCensus::Use& use : c.uses) {
        if (use.accessor >= c.accessorCount.size()) continue;
        const std::uint64_t count = c.accessorCount[std::size_t(use.accessor)];
        p.meshes = saturatingAdd(p.meshes, saturatingMul(count, use.bytes));
        if (use.kind == GltfCensus::Use::Positions) positions = saturatingAdd(positions, count);
        if (use.kind != GltfCensus::Use::Indices) continue;
        indices = saturatingAdd(indices, count);
        if (use.mesh < c.meshPrimitives.size() && c.meshPrimitives[std::size_t(use.mesh)] > 1)
            p.meshes = saturatingAdd(p.meshes, saturatingMul(count / 3, 4));
    }
    const std::uint64_t triangles = indices / 3;
    if (triangles <= kFaceNormalTriangles)
        p.meshes = saturatingAdd(p.meshes, saturatingMul(triangles, 12));
    if (c.normalTextures) p.meshes = saturatingAdd(p.meshes, saturatingMul(positions, 16));
    p.meshes = saturatingAdd(p.meshes, saturatingMul(c.meshes, kMeshObjectBytes));
    p.meshes = saturatingAdd(p.meshes, saturatingMul(c.nodes, kInstanceBytes));
    p.meshes = saturatingAdd(p.meshes, saturatingMul(c.materials, kMaterialBytes));
    for (const GltfCensus::Img& img : c.imgs)
        p.images = saturatingAdd(p.images, imageBytes(c, img, path, binOffset));
    // The reader's: the JSON text three times (the file's, the rewritten one, tinygltf's
    // string), both documents' values and members, tinygltf's objects.
    std::uint64_t reader = saturatingMul(jsonSize, 3);
    reader = saturatingAdd(reader, saturatingMul(c.values, kValueBytes));
    reader = saturatingAdd(reader, saturatingMul(c.members, kMemberBytes));
    reader = saturatingAdd(reader, saturatingMul(c.stringHeap, 2));
    const std::uint64_t objects =
        c.meshes * sizeof(tinygltf::Mesh) + c.primitives * sizeof(tinygltf::Primitive) +
        c.nodes * sizeof(tinygltf::Node) + c.accessors * sizeof(tinygltf::Accessor) +
        c.materials * sizeof(tinygltf::Material) + c.textures * sizeof(tinygltf::Texture) +
        c.images * sizeof(tinygltf::Image) + c.bufferViews * sizeof(tinygltf::BufferView) +
        c.buffers * sizeof(tinygltf::Buffer) + c.others * sizeof(tinygltf::Node);
    p.reader = saturatingAdd(reader, objects);
    const double total = double(p.meshes) + double(p.images) + double(p.reader);
    p.bytes = std::uint64_t(std::min(total * kHeapSlack, 1.8e19));
    p.counted = (c.meshes == 1 ? std::string("1 mesh") : std::to_string(c.meshes) + " meshes") +
                " (" + plural(c.primitives, "primitive") + "), " + plural(c.nodes, "node") + ", " +
                plural(c.accessors, "accessor") + ", " + plural(c.images, "image") +
                "; mesh data " + formatBytes(p.meshes) + ", images " + formatBytes(p.images) +
                ", the glTF reader's document " + formatBytes(p.reader);
    if (p.reader > p.meshes + p.images)
        p.advice =
            "fewer, larger meshes (joined in the modelling tool) load in less (the glTF reader's "
            "document is the larger part)";
    return p;
}

}  // namespace glint::render::detail
