#include "scene/obj_scan.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "glint/image/error.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, int line, const std::string& what) {
    throw Error(ErrorKind::Format, what, path.string(), "line " + std::to_string(line));
}

std::string shorten(const std::string& s) {
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

// Parses whitespace-separated finite numbers after the keyword; between lo and hi of them.
void checkNumbers(std::istringstream& in, const std::filesystem::path& path, int line,
                  const std::string& keyword, int lo, int hi) {
    std::string token;
    int count = 0;
    while (in >> token) {
        char* end = nullptr;
        const double v = std::strtod(token.c_str(), &end);
        if (end == token.c_str() || *end != '\0')
            fail(path, line,
                 "expected numbers after '" + keyword + "', got '" + shorten(token) + "'");
        if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
            fail(
                path, line,
                "'" + keyword + "' has a non-finite or overflowing value '" + shorten(token) + "'");
        ++count;
    }
    if (count < lo || count > hi)
        fail(
            path, line,
            "'" + keyword + "' needs " +
                (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi)) +
                " numbers, got " + std::to_string(count));
}

// Resolves one OBJ index (1-based, or negative relative to `count` statements so far) and
// checks it against `total` statements in the file.
void checkIndex(const std::string& text, long long count, long long total, const char* what,
                const std::filesystem::path& path, int line) {
    char* end = nullptr;
    const long long i = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0')
        fail(path, line,
             std::string("expected a ") + what + " index in a face, got '" + shorten(text) + "'");
    const long long resolved = i < 0 ? count + i + 1 : i;
    if (i == 0 || resolved < 1 || resolved > total)
        fail(path, line,
             "face " + std::string(what) + " index " + text + " is out of range (the file has " +
                 std::to_string(total) + " " + what + " statement" + (total == 1 ? "" : "s") +
                 (i < 0 ? ", " + std::to_string(count) + " before this line" : "") + ")");
}

}  // namespace

namespace {

/// Refuses a file that is not text before reading it whole (a 2 GB file of zeros is decided by
/// its first bytes): a NUL or another control character than tab, CR, LF, FF or VT in the first
/// 64 KiB names its byte and line.
void checkText(const std::filesystem::path& path, const char* kind) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> head(1 << 16);
    in.read(head.data(), std::streamsize(head.size()));
    const std::size_t n = std::size_t(std::max<std::streamsize>(in.gcount(), 0));
    int line = 1;
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<unsigned char>(head[i]);
        if (c == '\n') ++line;
        if (c < 0x20 && c != '\t' && c != '\r' && c != '\n' && c != '\f' && c != '\v')
            throw Error(ErrorKind::Format,
                        std::string("not ") + kind + " text: byte " + std::to_string(i) + " is 0x" +
                            "0123456789abcdef"[c >> 4] + "0123456789abcdef"[c & 15],
                        path.string(), "line " + std::to_string(line));
    }
}

}  // namespace

void scanMtl(const std::filesystem::path& path, std::map<std::string, MtlMaterialInfo>& materials) {
    checkText(path, "MTL");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, "cannot read the MTL file", path.string());
    int line = 0;
    MtlMaterialInfo* current = nullptr;  // the material being defined, when its first definition
    MtlMaterialInfo ignored;
    for (std::string text; std::getline(in, text);) {
        ++line;
        std::istringstream ls(text);
        std::string key;
        if (!(ls >> key)) continue;
        if (key == "newmtl") {
            std::string name;
            std::getline(ls >> std::ws, name);
            while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
            const auto [it, added] = materials.try_emplace(name, MtlMaterialInfo{path});
            current = added ? &it->second : &ignored;
            continue;
        }
        if (key == "Ka" || key == "Kd" || key == "Ks" || key == "Ke" || key == "Tf") {
            std::istringstream again(text);
            again >> key;
            checkNumbers(ls, path, line, key, 1, 3);
            std::vector<double> values;
            for (double v; again >> v;) values.push_back(v);
            if (values.size() == 2)
                fail(path, line, "'" + key + "' needs 1 value (grey) or 3 (r g b), got 2");
            // The ranges of the JSON keys these become (albedo, specular, emission).
            const double hi = key == "Ke" ? kMaxRadiance : key == "Kd" || key == "Ks" ? 1.0 : 1e30;
            for (const double v : values)
                if (v < 0.0 || v > hi) {
                    std::ostringstream msg;
                    msg << "'" << key << "' " << v << " is outside [0, " << hi << "]"
                        << (key == "Ke" ? " (radiance is limited to 1e18 so that its variance "
                                          "fits a float EXR)"
                                        : " (a reflectance)");
                    fail(path, line, msg.str());
                }
            MtlMaterialInfo& m = current ? *current : ignored;
            if (key == "Kd") m.greyKd = values.size() == 1;
            if (key == "Ks") m.greyKs = values.size() == 1;
            if (key == "Ke") m.greyKe = values.size() == 1;
        } else if (key == "Ns" || key == "Ni" || key == "d" || key == "Tr" || key == "illum") {
            std::istringstream again(text);
            again >> key;
            checkNumbers(ls, path, line, key, 1, 1);
            double v = 0.0;
            again >> v;
            if (key == "Ns" && v < 0.0)
                fail(path, line, "'Ns' " + std::to_string(v) + " is negative; expected >= 0");
        }
    }
}

ObjLines scanObj(const std::filesystem::path& path) {
    checkText(path, "OBJ");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, "cannot read the OBJ file", path.string());
    std::vector<std::string> lines;
    for (std::string l; std::getline(in, l);) lines.push_back(std::move(l));
    if (in.bad()) throw Error(ErrorKind::Io, "cannot read the OBJ file", path.string());

    // First pass: every v / vn / vt, so positive face indices can be checked against totals.
    ObjLines out;
    for (std::size_t n = 0; n < lines.size(); ++n) {
        std::istringstream ls(lines[n]);
        std::string key;
        if (!(ls >> key)) continue;
        const int line = int(n) + 1;
        if (key == "v") {
            checkNumbers(ls, path, line, key, 3, 7);  // x y z [w] or x y z r g b
            out.vertices.push_back(line);
        } else if (key == "vn") {
            checkNumbers(ls, path, line, key, 3, 3);
            out.normals.push_back(line);
        } else if (key == "vt") {
            checkNumbers(ls, path, line, key, 1, 3);
            out.texcoords.push_back(line);
        }
    }
    // Material libraries, where they exist (tinyobjloader reports missing ones).
    for (std::size_t n = 0; n < lines.size(); ++n) {
        std::istringstream ls(lines[n]);
        std::string key, name;
        if (!(ls >> key) || key != "mtllib") continue;
        while (ls >> name) {
            const std::filesystem::path mtl = path.parent_path() / name;
            std::error_code ec;
            if (std::filesystem::is_regular_file(mtl, ec))
                scanMtl(mtl, out.materials);
            else if (std::filesystem::exists(mtl, ec))  // a folder, a device, a pipe...
                fail(path, int(n) + 1,
                     "mtllib '" + shorten(name) + "' is not a regular file (expected an MTL file)");
        }
    }
    // Second pass: faces.
    long long v = 0, vn = 0, vt = 0, faces = 0;
    const auto nv = (long long)out.vertices.size(), nn = (long long)out.normals.size(),
               nt = (long long)out.texcoords.size();
    for (std::size_t n = 0; n < lines.size(); ++n) {
        std::istringstream ls(lines[n]);
        std::string key;
        if (!(ls >> key)) continue;
        const int line = int(n) + 1;
        if (key == "v")
            ++v;
        else if (key == "vn")
            ++vn;
        else if (key == "vt")
            ++vt;
        if (key != "f") continue;
        std::string corner;
        int corners = 0;
        while (ls >> corner) {
            // v, v/vt, v//vn or v/vt/vn
            const std::size_t a = corner.find('/');
            const std::size_t b = a == std::string::npos ? a : corner.find('/', a + 1);
            checkIndex(corner.substr(0, a), v, nv, "vertex", path, line);
            if (a != std::string::npos) {
                const std::string t = corner.substr(a + 1, b == std::string::npos ? b : b - a - 1);
                // "v/" names no texture coordinate and no normal: not one of the four forms.
                if (t.empty() && b == std::string::npos)
                    fail(path, line,
                         "malformed face corner '" + shorten(corner) +
                             "': expected v, v/vt, v//vn or v/vt/vn");
                if (!t.empty()) checkIndex(t, vt, nt, "texture coordinate", path, line);
                if (b != std::string::npos)
                    checkIndex(corner.substr(b + 1), vn, nn, "normal", path, line);
            }
            ++corners;
        }
        if (corners < 3)
            fail(path, line, "a face needs at least 3 corners, got " + std::to_string(corners));
        if (std::size_t(corners) > kMaxObjFaceCorners)
            fail(path, line,
                 "a face has " + std::to_string(corners) + " corners; at most " +
                     std::to_string(kMaxObjFaceCorners) +
                     " are read (split it into faces of fewer corners)");
        ++faces;
    }
    // Text without a face is no mesh (HTML, a log, an OBJ of points or lines only).
    if (faces == 0)
        throw Error(ErrorKind::Format,
                    "no faces ('f' statements): not an OBJ mesh (" + std::to_string(lines.size()) +
                        " lines read)",
                    path.string(), "faces");
    return out;
}

}  // namespace glint::render::detail
