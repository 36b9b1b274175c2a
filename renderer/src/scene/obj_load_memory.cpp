// The load of an OBJ, predicted before it is parsed (predictObjLoad, the OBJ format's
// predictLoad; load_memory.h): one streaming pass counting its statements and its distinct face
// corners. The rates are the sizes of the arrays tinyobjloader and the import make, checked
// against the peak resident size of loads of generated assets (docs/lab/mesh-memory.md).
#include <algorithm>
#include <cstdint>
#include <string_view>
#include <vector>

#include "glint/image/memory.h"
#include "scene/load_memory.h"
#include "scene/obj_scan.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

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

}  // namespace glint::render::detail
