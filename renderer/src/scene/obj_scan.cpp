#include "scene/obj_scan.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>

#include "glint/image/error.h"
#include "scene/input_file.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, int line, const std::string& what) {
    throw Error(ErrorKind::Format, what, path.string(), "line " + std::to_string(line));
}

std::string shorten(const std::string& s) {
    return s.size() > 40 ? s.substr(0, 37) + "..." : s;
}

// Whitespace as `>>` reads it (the "C" locale's, newline aside: lines are split at it).
constexpr bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// The whitespace-separated tokens of one line, read in place.
struct LineTokens {
    const char* at;
    const char* end;
    bool next(std::string_view& token) {
        while (at < end && isBlank(*at)) ++at;
        if (at == end) return false;
        const char* from = at;
        while (at < end && !isBlank(*at)) ++at;
        token = {from, std::size_t(at - from)};
        return true;
    }
};

// Finite numbers after the keyword, between lo and hi of them; returns their count.
// std::from_chars reads the plain ones, strtod (as C reads numbers) any token it does not read
// whole.
int checkNumberTokens(LineTokens in, const std::filesystem::path& path, int line,
                      std::string_view keyword, int lo, int hi) {
    std::string_view token;
    int count = 0;
    while (in.next(token)) {
        double v = 0.0;
        const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
        if (ec != std::errc() || end != token.data() + token.size()) {
            const std::string text(token);
            char* stop = nullptr;
            v = std::strtod(text.c_str(), &stop);
            if (stop == text.c_str() || *stop != '\0')
                fail(path, line,
                     "expected numbers after '" + std::string(keyword) + "', got '" +
                         shorten(text) + "'");
        }
        if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
            fail(path, line,
                 "'" + std::string(keyword) + "' has a non-finite or overflowing value '" +
                     shorten(std::string(token)) + "'");
        ++count;
    }
    if (count < lo || count > hi)
        fail(
            path, line,
            "'" + std::string(keyword) + "' needs " +
                (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi)) +
                " numbers, got " + std::to_string(count));
    return count;
}

// The same over the rest of a line's stream.
void checkNumbers(std::istringstream& in, const std::filesystem::path& path, int line,
                  const std::string& keyword, int lo, int hi) {
    std::string rest;
    std::getline(in, rest);
    checkNumberTokens(LineTokens{rest.data(), rest.data() + rest.size()}, path, line, keyword, lo,
                      hi);
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

bool sameCaseless(const std::string& a, const std::string& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

// `relative` below `base`, each part matched exactly or else without regard to case.
std::filesystem::path findCaseless(std::filesystem::path base,
                                   const std::filesystem::path& relative) {
    namespace fs = std::filesystem;
    std::error_code ec;
    for (const fs::path& part : relative) {
        if (part.empty() || part == ".") continue;
        if (fs::exists(base / part, ec) || part == "..") {
            base /= part;
            continue;
        }
        fs::path found;
        for (auto it = fs::directory_iterator(base, ec); !ec && it != fs::directory_iterator();
             it.increment(ec))
            if (sameCaseless(it->path().filename().string(), part.string())) {
                found = it->path();
                break;
            }
        if (found.empty()) return {};
        base = found;
    }
    return fs::is_regular_file(base, ec) ? base : fs::path{};
}

std::string mtlTrimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// The MTL texture options (MTL specification, "Options for texture map statements") and how
// many values follow each; -o, -s and -t take 1 to 3 numbers.
int optionValues(const std::string& option) {
    static const std::map<std::string, int> counts{
        {"-blendu", 1}, {"-blendv", 1},  {"-bm", 1},     {"-boost", 1},     {"-cc", 1},
        {"-clamp", 1},  {"-imfchan", 1}, {"-texres", 1}, {"-type", 1},      {"-mm", 2},
        {"-o", 3},      {"-s", 3},       {"-t", 3},      {"-colorspace", 1}};
    const auto it = counts.find(option);
    return it == counts.end() ? 0 : it->second;
}

// Reads a texture statement after its keyword: options, then the file name (the rest of the
// line, spaces included, up to an option written after it), then options written after it.
// Options Glint does not read are added to `ignored`; a `-bm` that is not a finite number is
// refused with the MTL's file and line.
MtlTexture parseTexture(const std::string& rest, const std::filesystem::path& path, int line,
                        std::vector<std::string>& ignored) {
    MtlTexture tex;
    tex.line = line;
    std::size_t pos = 0;
    auto next = [&](std::string& token) {
        const auto b = rest.find_first_not_of(" \t\r", pos);
        if (b == std::string::npos) return std::string::npos;
        const auto e = rest.find_first_of(" \t\r", b);
        token = rest.substr(b, e == std::string::npos ? std::string::npos : e - b);
        pos = e == std::string::npos ? rest.size() : e;
        return b;
    };
    // Reads options from `at` (the start of `token`) while they are options; returns where the
    // first token that is not one starts (npos: the line ended).
    auto readOptions = [&](std::size_t at, std::string& token) {
        while (at != std::string::npos && optionValues(token) > 0) {
            const std::string option = token;
            std::vector<std::string> values;
            const bool numeric = option == "-o" || option == "-s" || option == "-t";
            for (int k = 0; k < optionValues(option); ++k) {
                const std::size_t save = pos;
                std::string value;
                if (next(value) == std::string::npos) break;
                char* end = nullptr;
                std::strtod(value.c_str(), &end);
                if (numeric && (end == value.c_str() || *end != '\0')) {
                    pos = save;  // the file name
                    break;
                }
                values.push_back(value);
            }
            auto number = [&](std::size_t i, float fallback) {
                return i < values.size() ? float(std::strtod(values[i].c_str(), nullptr))
                                         : fallback;
            };
            if (option == "-s") {
                tex.scale[0] = number(0, 1.0f), tex.scale[1] = number(1, 1.0f);
            } else if (option == "-o") {
                tex.offset[0] = number(0, 0.0f), tex.offset[1] = number(1, 0.0f);
            } else if (option == "-clamp") {
                tex.clamp = !values.empty() && values[0] == "on";
            } else if (option == "-bm") {
                // The bump multiplier: any finite number (a negative one turns bumps into dents).
                const std::string value = values.empty() ? std::string() : values[0];
                char* end = nullptr;
                const double v = std::strtod(value.c_str(), &end);
                if (value.empty() || end == value.c_str() || *end != '\0')
                    fail(
                        path, line,
                        "'-bm' needs a number (the bump multiplier), got '" + shorten(value) + "'");
                if (!std::isfinite(v) || std::fabs(v) > 3.0e38)
                    fail(path, line,
                         "'-bm' has a non-finite or overflowing value '" + shorten(value) + "'");
                tex.bumpMultiplier = float(v);
            } else if (option != "-colorspace") {
                ignored.push_back(option);
            }
            at = next(token);
        }
        return at;
    };
    std::string token;
    const std::size_t at = readOptions(next(token), token);
    if (at == std::string::npos) return tex;
    std::string name = rest.substr(at);
    // Options written after the name (" -bm 1.5"): read from there, and the name ends there.
    for (std::size_t dash = name.find(" -"); dash != std::string::npos;
         dash = name.find(" -", dash + 1)) {
        const std::string option = name.substr(dash + 1, name.find(' ', dash + 1) - dash - 1);
        if (optionValues(option) > 0) {
            pos = at + dash;
            std::string after;
            readOptions(next(after), after);  // text after them is dropped
            name.resize(dash);
            break;
        }
    }
    tex.name = mtlTrimmed(name);
    return tex;
}

// What Glint does not read of an MTL, by statement: the note its warning gives.
const char* unreadNote(const std::string& key) {
    static const std::map<std::string, const char*> notes{
        {"disp", "displacement is not read"},
        {"decal", "decal textures are not read"},
        {"refl", "reflection maps are not read (reflections are traced)"},
        {"map_Ks", "specular textures are not read"},
        {"map_Ns", "specular exponent textures are not read"},
        {"map_Ke", "emission textures are not read ('Ke' is)"},
        {"map_Pr", "roughness textures are not read ('Pr' is)"},
        {"map_Pm", "metallic textures are not read ('Pm' is)"},
        {"map_Ps", "sheen is not read"},
        {"Ps", "sheen is not read"},
        {"Pc", "clearcoat is not read"},
        {"Pcr", "clearcoat is not read"},
        {"aniso", "anisotropy is not read"},
        {"anisor", "anisotropy is not read"}};
    const auto it = notes.find(key);
    return it == notes.end() ? nullptr : it->second;
}

}  // namespace

std::filesystem::path findNamedFile(const std::filesystem::path& folder, const std::string& name) {
    namespace fs = std::filesystem;
    std::string slashed = name;
    std::replace(slashed.begin(), slashed.end(), '\\', '/');
    const fs::path written(slashed);
    std::error_code ec;
    const fs::path direct = written.is_absolute() ? written : folder / written;
    if (fs::is_regular_file(direct, ec)) return direct;
    if (!written.is_absolute())
        if (fs::path found = findCaseless(folder, written); !found.empty()) return found;
    // A path of the exporter's machine ("/Maps/rust.jpg", "C:/textures/wood.jpg"): below
    // the folder without its root, else its file name alone.
    if (written.is_absolute())
        if (fs::path found = findCaseless(folder, written.relative_path()); !found.empty())
            return found;
    if (written.has_parent_path()) return findCaseless(folder, written.filename());
    return {};
}

std::string readObjText(const std::filesystem::path& path, const char* kind) {
    // Read into a string of the file's size (a stream's buffer would grow by doubling).
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in ? std::streamoff(in.tellg()) : -1;
    std::string s(std::size_t(std::max<std::streamoff>(size, 0)), '\0');
    if (size < 0 || !in.seekg(0) || !in.read(s.data(), std::streamsize(s.size())))
        throw Error(ErrorKind::Io, std::string("cannot read the ") + kind + " file", path.string());
    if (s.rfind("\xEF\xBB\xBF", 0) == 0) s.erase(0, 3);
    return s;
}

void scanMtl(const std::filesystem::path& path, ObjLines& out) {
    checkText(path, "MTL");
    std::istringstream in(readObjText(path, "MTL"));
    int line = 0;
    MtlMaterialInfo* current = nullptr;  // the material being defined, when its first definition
    MtlMaterialInfo ignored;
    std::map<std::string, int> unread;  // statement or option Glint does not read → first line
    for (std::string text; std::getline(in, text);) {
        ++line;
        std::istringstream ls(text);
        std::string key;
        if (!(ls >> key)) continue;
        if (key == "newmtl") {
            std::string name;
            std::getline(ls >> std::ws, name);
            while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
            MtlMaterialInfo info;
            info.file = path;
            const auto [it, added] = out.materials.try_emplace(name, std::move(info));
            current = added ? &it->second : &ignored;
            // LightWave names every surface "Default": which one a face gets is the reader's
            // choice (Blender's importer and three.js take the last).
            if (!added) unread.try_emplace("newmtl " + name, line);
            continue;
        }
        MtlMaterialInfo& m = current ? *current : ignored;
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
            if (key == "Kd") m.greyKd = values.size() == 1;
            if (key == "Ks") m.greyKs = values.size() == 1;
            if (key == "Ke") m.greyKe = values.size() == 1;
        } else if (key == "Ns" || key == "Ni" || key == "d" || key == "Tr" || key == "illum" ||
                   key == "Pr" || key == "Pm") {
            std::istringstream again(text);
            again >> key;
            checkNumbers(ls, path, line, key, 1, 1);
            double v = 0.0;
            again >> v;
            if (key == "Ns" && v < 0.0)
                fail(path, line, "'Ns' " + std::to_string(v) + " is negative; expected >= 0");
            if ((key == "d" || key == "Tr" || key == "Pr" || key == "Pm") && (v < 0.0 || v > 1.0))
                fail(path, line,
                     "'" + key + "' " + std::to_string(v) + " is outside [0, 1] (a fraction)");
            if (key == "Pr" || key == "Pm") m.pbr = true;
        } else if (key == "map_Kd" || key == "norm" || key == "map_d" || key == "bump" ||
                   key == "map_Bump" || key == "map_bump") {
            std::string rest;
            std::getline(ls, rest);
            std::vector<std::string> options;
            MtlTexture tex = parseTexture(rest, path, line, options);
            for (const std::string& option : options) unread.try_emplace(key + " " + option, line);
            if (key == "map_Kd") m.mapKd = tex;
            if (key == "norm") m.norm = tex;
            if (key == "map_d") m.mapD = tex;
            // Crytek Sponza gives both `map_bump` and `bump` of one file: the first is read, a
            // later one naming another file is warned.
            const bool bump = key == "bump" || key == "map_Bump" || key == "map_bump";
            if (bump && m.bump.name.empty())
                m.bump = tex;
            else if (bump && tex.name != m.bump.name)
                unread.try_emplace(key + " naming a second bump map", line);
        } else if (unreadNote(key)) {
            unread.try_emplace(key, line);
        }
    }
    for (const auto& [what, first] : unread) {
        if (what.rfind("newmtl ", 0) == 0) {
            out.warnings.push_back(path.filename().string() + " line " + std::to_string(first) +
                                   ": material '" + what.substr(7) +
                                   "' is defined again; the first definition is used (Blender "
                                   "uses the last)");
            continue;
        }
        const auto space = what.find(' ');
        const char* note = unreadNote(what);
        if (what.find(" naming a second bump map") != std::string::npos) {
            out.warnings.push_back(path.filename().string() + " line " + std::to_string(first) +
                                   ": '" + what.substr(0, space) +
                                   "' is ignored (the material's first bump map is read)");
            continue;
        }
        out.warnings.push_back(
            path.filename().string() + " line " + std::to_string(first) + ": '" + what +
            "' is ignored" + (note ? std::string(" (") + note + ")" : "") +
            (space != std::string::npos ? " (the texture option is not read)" : ""));
    }
}

namespace {

// The names of an `mtllib` statement after the keyword, as Blender's importer splits them: a
// name runs to the next ".mtl" (3ds Max writes "mtllib my model.mtl" for my model.obj), and
// tinyobjloader's "\ " is a space.
std::vector<std::string> mtllibNames(std::string rest) {
    for (std::size_t at = rest.find("\\ "); at != std::string::npos; at = rest.find("\\ ", at))
        rest.erase(at, 1);
    rest = mtlTrimmed(rest);
    std::string lower = rest;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    std::vector<std::string> names;
    std::size_t from = 0;
    while (from < rest.size()) {
        std::size_t end = lower.find(".mtl", from);
        end = end == std::string::npos ? rest.size() : end + 4;
        if (std::string name = mtlTrimmed(rest.substr(from, end - from)); !name.empty())
            names.push_back(name);
        from = end;
    }
    return names;
}

/// Calls `f(line, tokens)` for each line of `text` (as std::getline splits it), 1-based;
/// returns the number of lines.
template <typename F>
int forEachLine(const std::string& text, F&& f) {
    int line = 0;
    for (std::size_t at = 0; at < text.size();) {
        std::size_t nl = text.find('\n', at);
        if (nl == std::string::npos) nl = text.size();
        f(++line, LineTokens{text.data() + at, text.data() + nl});
        at = nl + 1;
    }
    return line;
}

// As checkIndex, in place: an index of plain digits is resolved here, anything else (and every
// index out of range) by checkIndex, which names it.
void checkIndexToken(std::string_view text, long long count, long long total, const char* what,
                     const std::filesystem::path& path, int line) {
    const bool negative = !text.empty() && text[0] == '-';
    const std::string_view digits = text.substr(negative ? 1 : 0);
    if (!digits.empty() && digits.size() <= 18 &&
        std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        long long i = 0;
        for (const char c : digits) i = 10 * i + (c - '0');
        if (negative) i = -i;
        const long long resolved = i < 0 ? count + i + 1 : i;
        if (i != 0 && resolved >= 1 && resolved <= total) return;
    }
    checkIndex(std::string(text), count, total, what, path, line);
}

}  // namespace

ObjLines scanObj(const std::filesystem::path& path) {
    checkText(path, "OBJ");
    ObjLines out;
    const std::string text = readObjText(path, "OBJ");  // released when the scan returns

    // First pass: every v / vn / vt, so positive face indices can be checked against totals.
    bool colours = false;
    const int lineCount = forEachLine(text, [&](int line, LineTokens ls) {
        std::string_view key;
        if (!ls.next(key)) return;
        if (key == "v") {
            const int values = checkNumberTokens(ls, path, line, key, 3, 7);  // x y z [w] / rgb
            if (values >= 6 && !colours)
                out.warnings.push_back(path.filename().string() + " line " + std::to_string(line) +
                                       ": vertex colours ('v x y z r g b') are ignored");
            colours = colours || values >= 6;
            out.vertices.push_back(line);
        } else if (key == "vn") {
            checkNumberTokens(ls, path, line, key, 3, 3);
            ++out.normalCount;
        } else if (key == "vt") {
            checkNumberTokens(ls, path, line, key, 1, 3);
            ++out.texcoordCount;
        }
    });
    // Material libraries: each must exist (tinyobjloader reads only the first it finds of a line
    // and calls the others missing).
    forEachLine(text, [&](int line, LineTokens ls) {
        std::string_view key;
        if (!ls.next(key) || key != "mtllib") return;
        for (const std::string& name : mtllibNames(std::string(ls.at, ls.end))) {
            const std::filesystem::path mtl = findNamedFile(path.parent_path(), name);
            if (mtl.empty()) {
                const std::filesystem::path there = path.parent_path() / name;
                if (const InputKind kind = inputKind(there); kind != InputKind::Missing)
                    fail(path, line,
                         "mtllib '" + shorten(name) + "' " + notARegularFile(kind, "an MTL file"));
                throw Error(ErrorKind::Io,
                            "mtllib '" + name + "' not found (looked for " + there.string() + ")",
                            path.string(), "line " + std::to_string(line));
            }
            if (std::find(out.mtlFiles.begin(), out.mtlFiles.end(), mtl) != out.mtlFiles.end())
                continue;
            out.mtlFiles.push_back(mtl);
            scanMtl(mtl, out);
        }
    });
    // Second pass: faces.
    long long v = 0, vn = 0, vt = 0, faces = 0;
    const auto nv = (long long)out.vertices.size(), nn = (long long)out.normalCount,
               nt = (long long)out.texcoordCount;
    forEachLine(text, [&](int line, LineTokens ls) {
        std::string_view key;
        if (!ls.next(key)) return;
        if (key == "v")
            ++v;
        else if (key == "vn")
            ++vn;
        else if (key == "vt")
            ++vt;
        if (key != "f") return;
        std::string_view corner;
        int corners = 0;
        while (ls.next(corner)) {
            // v, v/vt, v//vn or v/vt/vn
            const std::size_t a = corner.find('/');
            const std::size_t b = a == std::string::npos ? a : corner.find('/', a + 1);
            checkIndexToken(corner.substr(0, a), v, nv, "vertex", path, line);
            if (a != std::string::npos) {
                const std::string_view t =
                    corner.substr(a + 1, b == std::string::npos ? b : b - a - 1);
                // "v/" names no texture coordinate and no normal: not one of the four forms.
                if (t.empty() && b == std::string::npos)
                    fail(path, line,
                         "malformed face corner '" + shorten(std::string(corner)) +
                             "': expected v, v/vt, v//vn or v/vt/vn");
                // A file with no vt (or no vn) whose faces name some anyway (OpenSubdiv's Maya
                // shapes): the indices name nothing and are ignored, with a warning.
                if (!t.empty() && nt == 0 && out.unnamedTexcoordLine == 0)
                    out.unnamedTexcoordLine = line;
                if (!t.empty() && nt > 0)
                    checkIndexToken(t, vt, nt, "texture coordinate", path, line);
                if (b != std::string::npos) {
                    if (nn > 0)
                        checkIndexToken(corner.substr(b + 1), vn, nn, "normal", path, line);
                    else if (out.unnamedNormalLine == 0)
                        out.unnamedNormalLine = line;
                }
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
    });
    for (const auto& [first, what] : {std::pair{out.unnamedTexcoordLine, "texture coordinates"},
                                      std::pair{out.unnamedNormalLine, "normals"}})
        if (first > 0)
            out.warnings.push_back(path.filename().string() + " line " + std::to_string(first) +
                                   ": faces name " + what + " but the file has none; ignored");
    // Text without a face is no mesh (HTML, a log, an OBJ of points or lines only).
    if (faces == 0)
        throw Error(ErrorKind::Format,
                    "no faces ('f' statements): not an OBJ mesh (" + std::to_string(lineCount) +
                        " lines read)",
                    path.string(), "faces");
    return out;
}

}  // namespace glint::render::detail
