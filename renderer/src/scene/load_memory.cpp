// The load's memory, predicted before an asset is parsed (load_memory.h). The rates are the
// sizes of the objects the readers make, checked against the peak resident size of loads of
// generated assets (docs/lab/mesh-memory.md, "The memory limit holds during loading").
#include "scene/load_memory.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "scene/gltf_import.h"
#include "scene/json_scan.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

/// Bytes of the file read at a time by the predictions' passes.
constexpr std::size_t kBlock = std::size_t(1) << 20;

/// Bytes a JSON value costs in the two documents alive while tinygltf parses (Glint's copy, in
/// which the buffers it reads itself are rewritten, and tinygltf's own): nlohmann-json's 16-byte
/// value in its parent's array, grown by half again on average, twice.
constexpr std::uint64_t kValueBytes = 2 * 24;
/// Bytes an object member costs there besides its value: a std::map node (links, key string,
/// value) of 96 bytes as glibc allocates it, twice.
constexpr std::uint64_t kMemberBytes = 2 * 96;
/// Glint's Mesh and Instance beside their arrays: the object, its name and the small arrays'
/// allocations (at least 32 bytes each under glibc).
constexpr std::uint64_t kMeshObjectBytes = sizeof(Mesh) + 8 * 32;
constexpr std::uint64_t kInstanceBytes = sizeof(Instance) + 32;
/// Glint's Material of a glTF material, its name, its entries in the loader's maps by name and
/// what converting it leaves in the heap: about 1.4 KB a material measured beyond the object
/// (a glb of 20000 one-triangle primitives with a material each, lab/bench/load_memory_assets.py).
constexpr std::uint64_t kMaterialBytes = sizeof(Material) + 1536;
/// What glibc's heap keeps beyond the objects counted (its chunk headers, rounding and the
/// freed text it holds): measured as up to 12 % on the many-mesh assets; 20 % is kept.
constexpr double kHeapSlack = 1.2;

std::uint32_t le32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}

std::uint64_t number(std::string_view text) {
    std::uint64_t v = 0;
    for (const char c : text) {
        if (c < '0' || c > '9') return v;
        v = saturatingAdd(saturatingMul(v, 10), std::uint64_t(c - '0'));
    }
    return v;
}

/// Reads `count` bytes of the file from `offset` a block at a time into `feed(std::string_view)`;
/// false when the file is shorter or cannot be read.
template <class Feed>
bool readBlocks(const fs::path& path, std::uint64_t offset, std::uint64_t count, Feed&& feed) {
    std::ifstream in(path, std::ios::binary);
    if (!in || !in.seekg(std::streamoff(offset))) return false;
    std::vector<char> block(std::size_t(std::min<std::uint64_t>(count, kBlock)));
    while (count > 0) {
        const std::size_t n = std::size_t(std::min<std::uint64_t>(count, block.size()));
        if (!in.read(block.data(), std::streamsize(n))) return false;
        feed(std::string_view(block.data(), n));
        count -= n;
    }
    return true;
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

/// What the count of an OBJ's statements found.
struct ObjCensus {
    std::uint64_t v = 0, vt = 0, vn = 0, f = 0, corners = 0, usemtl = 0;
    bool smoothing = false;     ///< an `s` statement other than `s off` / `s 0`
    std::uint64_t triples = 0;  ///< distinct (v, vt, vn) corners, estimated (DistinctCount)
};

/// The number of distinct 64-bit keys among those added, estimated in 4 KiB by HyperLogLog
/// (Flajolet et al. 2007, with its small-range correction): within about 5 % (three standard
/// errors of 1.6 %).
class DistinctCount {
  public:
    void add(std::uint64_t key) {
        // SplitMix64's finaliser spreads the key's bits.
        key += 0x9e3779b97f4a7c15ULL;
        key = (key ^ (key >> 30)) * 0xbf58476d1ce4e5b9ULL;
        key = (key ^ (key >> 27)) * 0x94d049bb133111ebULL;
        key ^= key >> 31;
        const std::size_t bucket = std::size_t(key >> (64 - kBits));
        const std::uint64_t rest = key << kBits | (std::uint64_t(1) << (kBits - 1));
        const auto rank = std::uint8_t(__builtin_clzll(rest) + 1);
        m_rank[bucket] = std::max(m_rank[bucket], rank);
    }
    std::uint64_t estimate() const {
        constexpr double m = double(std::size_t(1) << kBits);
        double sum = 0.0;
        int empty = 0;
        for (const std::uint8_t r : m_rank) {
            sum += 1.0 / double(std::uint64_t(1) << r);
            empty += r == 0;
        }
        const double raw = 0.7213 / (1.0 + 1.079 / m) * m * m / sum;
        if (raw <= 2.5 * m && empty > 0) return std::uint64_t(m * std::log(m / empty));
        return std::uint64_t(raw);
    }

  private:
    static constexpr int kBits = 12;
    std::vector<std::uint8_t> m_rank = std::vector<std::uint8_t>(std::size_t(1) << kBits, 0);
};

/// Counts the statements of OBJ text given a piece at a time, and its distinct face corners.
class ObjCount {
  public:
    void feed(std::string_view piece) {
        for (const char c : piece) {
            const bool space = c == ' ' || c == '\t' || c == '\r';
            if (c == '\n') {
                endLine();
                continue;
            }
            switch (m_state) {
                case State::Start:
                    if (space) break;
                    m_state = State::Keyword;
                    m_word.clear();
                    [[fallthrough]];
                case State::Keyword:
                    if (!space) {
                        if (m_word.size() < 3) m_word.push_back(c);
                        break;
                    }
                    m_state = State::Rest;
                    if (m_word == "v")
                        ++m_count.v;
                    else if (m_word == "vt")
                        ++m_count.vt;
                    else if (m_word == "vn")
                        ++m_count.vn;
                    else if (m_word == "f")
                        ++m_count.f;
                    else if (m_word == "use")  // usemtl (the word is kept to 3 letters)
                        ++m_count.usemtl;
                    m_value.clear();
                    m_inToken = false;
                    break;
                case State::Rest:
                    if (m_word == "f" && !space && !m_inToken) ++m_count.corners, m_corner.clear();
                    if (m_word == "f" && !space && m_corner.size() < 64) m_corner.push_back(c);
                    if (m_word == "f" && space && m_inToken) addCorner();
                    if (m_word == "s" && !space && m_value.size() < 4) m_value.push_back(c);
                    m_inToken = !space;
                    break;
            }
        }
    }
    const ObjCensus& finish() {
        endLine();
        m_count.triples = std::min(m_count.corners, m_distinct.estimate());
        return m_count;
    }

  private:
    enum class State { Start, Keyword, Rest };
    /// A face corner's indices (v, v/vt, v//vn, v/vt/vn; negative: relative to the statements
    /// so far) resolved and counted as one key.
    void addCorner() {
        std::int64_t index[3] = {0, 0, 0};
        const std::uint64_t count[3] = {m_count.v, m_count.vt, m_count.vn};
        std::size_t part = 0;
        bool negative = false;
        for (std::size_t i = 0; i <= m_corner.size() && part < 3; ++i) {
            const char ch = i < m_corner.size() ? m_corner[i] : '/';
            if (ch == '-') negative = true;
            if (ch >= '0' && ch <= '9') index[part] = index[part] * 10 + (ch - '0');
            if (ch != '/') continue;
            if (negative) index[part] = std::int64_t(count[part]) + 1 - index[part];
            negative = false;
            ++part;
        }
        m_distinct.add(std::uint64_t(index[0]) * 0x100000001b3ULL ^
                       std::uint64_t(index[1]) * 0xc6a4a7935bd1e995ULL ^ std::uint64_t(index[2]));
    }
    void endLine() {
        if (m_state == State::Rest && m_word == "f" && m_inToken) addCorner();
        m_inToken = false;
        if (m_state == State::Keyword && m_word == "f") ++m_count.f;  // "f" alone: no corners
        if (m_word == "s" && m_state == State::Rest && !m_value.empty() && m_value != "off" &&
            m_value != "0")
            m_count.smoothing = true;
        m_state = State::Start;
        m_word.clear();
    }
    State m_state = State::Start;
    std::string m_word, m_value, m_corner;
    bool m_inToken = false;
    ObjCensus m_count;
    DistinctCount m_distinct;
};

std::string plural(std::uint64_t n, const char* what) {
    return std::to_string(n) + " " + what + (n == 1 ? "" : "s");
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
        if (in.gcount() >= 20 && le32(h) == 0x46546C67) {  // "glTF"
            jsonOffset = 20;
            jsonSize = le32(h + 12);
            if (jsonSize > size - 20) return {};
            const std::uint64_t bin = 20 + jsonSize;
            unsigned char b[8];
            if (size >= bin + 8 && in.seekg(std::streamoff(bin)) &&
                in.read(reinterpret_cast<char*>(b), 8) && le32(b + 4) == 0x004E4942)
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

LoadPrediction predictObjLoad(const fs::path& path) {
    LoadPrediction p;
    p.advice =
        "the same mesh as a .glb loads in about its mesh data (the OBJ reader's text and arrays "
        "are the larger part)";
    std::error_code ec;
    const std::uint64_t size = fs::file_size(path, ec);
    if (ec) return p;
    ObjCount count;
    if (!readBlocks(path, 0, size, [&](std::string_view piece) { count.feed(piece); })) return p;
    const ObjCensus& c = count.finish();
    // The check (obj_scan.cpp) holds the text and the line of every vertex.
    const std::uint64_t check = size + 8 * c.v;
    // tinyobjloader's arrays (floats per v, vn, vt; 12 bytes a corner; a face's corner count,
    // material and smoothing group) and its block of the file; the conversion's tables (the
    // first corner and vertex at each position, the smoothing keys) and the mesh: its vertices,
    // 4-byte indices, a material per triangle (with several usemtl) and a face normal per
    // triangle in scenes of up to kFaceNormalTriangles.
    const std::uint64_t triangles = c.corners > 2 * c.f ? c.corners - 2 * c.f : 0;
    const std::uint64_t reader = 12 * c.v + 12 * c.vn + 8 * c.vt + 12 * c.corners + 9 * c.f +
                                 std::min<std::uint64_t>(size, std::uint64_t(1) << 22);
    const bool normals = c.vn > 0 || c.smoothing;
    // A mesh vertex per distinct corner (estimated within 5 %); each beyond the first at its
    // position is held in the conversion's map (a node of about 64 bytes).
    const std::uint64_t vertices = std::min(c.corners, c.triples + c.triples / 20);
    const std::uint64_t map = vertices > c.v ? 64 * (vertices - c.v) : 0;
    const std::uint64_t tables = 16 * c.v + map + (c.smoothing && c.vn == 0 ? 8 * vertices : 0);
    p.meshes = vertices * (12 + (normals ? 12 : 0) + (c.vt > 0 ? 8 : 0)) +
               triangles * (c.usemtl > 1 ? 16 : 12) +
               (triangles <= kFaceNormalTriangles ? triangles * 12 : 0) + kMeshObjectBytes;
    // The peak: the check's; or the reader's arrays (the largest grown once more) and the
    // tables as the conversion starts; or the mesh and the tables as it ends (the reader's
    // arrays are handed back as they are converted).
    const std::uint64_t parse = reader + tables + 12 * std::max(c.v, c.vn);
    const std::uint64_t peak = std::max({check, parse, p.meshes + tables});
    p.reader = peak > p.meshes ? peak - p.meshes : 0;
    p.bytes = std::uint64_t(double(peak) * kHeapSlack);
    p.counted = plural(c.v, "vertex statement") + ", " + plural(c.vt, "texture coordinate") + ", " +
                plural(c.vn, "normal") + ", " + plural(c.f, "face") + " of " +
                plural(c.corners, "corner") + "; mesh data " + formatBytes(p.meshes) +
                ", the OBJ reader's text and arrays " + formatBytes(p.reader);
    return p;
}

void checkLoadMemory(const LoadPrediction& prediction, std::uint64_t held, std::uint64_t limit,
                     const fs::path& asset, const fs::path& sceneFile, const std::string& where) {
    const std::uint64_t need = saturatingAdd(held, prediction.bytes);
    if (limit == 0 || need <= limit) return;
    // A bare asset is named as the file; an asset of a scene.json by the shape's place.
    const bool bare = asset == sceneFile;
    std::string text = (bare ? std::string("loading it") : "loading " + asset.string()) +
                       " would take about " + formatBytes(prediction.bytes) +
                       " at its peak (predicted before reading it: " + prediction.counted + ")";
    if (held > 0) text += " on top of the " + formatBytes(held) + " the scene already holds";
    text += " but only " + formatBytes(limit) +
            " is allowed (memory limit); nothing of it was read. A limit of " + formatBytes(need) +
            " would load it";
    if (!prediction.advice.empty()) text += "; " + prediction.advice;
    throw Error(ErrorKind::OutOfMemory, text, sceneFile.string(), bare ? "" : where);
}

}  // namespace glint::render::detail
