// A check of an OpenEXR file's headers before OpenEXR reads them: OpenEXR 3.1 allocates what an
// attribute's size field claims before it finds the file too short, so a 2 KB file whose
// string attribute claims 2 GB took 2 GB and seconds to refuse (found by fuzz_shard_merge).
// Each header's attributes are walked (name, type, size, value) without reading the values; a
// size beyond the end of the file is one glint::Error naming the attribute and its byte.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "glint/image/error.h"
#include "image_files.h"

namespace glint::detail {

namespace {

constexpr unsigned char kExrMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr std::uint32_t kMultiPartFlag = 0x1000;
constexpr int kMaxNameLength = 255;  // with the long-names flag; 31 without

/// Reads a NUL-terminated name of at most kMaxNameLength characters at the stream's position;
/// false at the end of the file or for a longer one.
bool readName(std::istream& in, std::string& name) {
    name.clear();
    for (int c; (c = in.get()) != EOF;) {
        if (c == 0) return true;
        if (int(name.size()) == kMaxNameLength) return false;
        name.push_back(char(c));
    }
    return false;
}

}  // namespace

bool isExr(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    unsigned char magic[4] = {};
    return in.read(reinterpret_cast<char*>(magic), 4) && std::equal(magic, magic + 4, kExrMagic);
}

void checkExrHeaders(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::ifstream in(path, std::ios::binary);
    std::error_code ec;
    const auto size = (long long)std::filesystem::file_size(path, ec);
    if (!in || ec) throw Error(ErrorKind::Io, "cannot read the file", file, "open");
    unsigned char head[8] = {};
    if (!in.read(reinterpret_cast<char*>(head), 8))
        throw Error(ErrorKind::Format, "truncated OpenEXR file: no version field", file, "header");
    // The version field: the version number in its low byte, flags above (OpenEXR file layout).
    const std::uint32_t version = std::uint32_t(head[4]) | std::uint32_t(head[5]) << 8 |
                                  std::uint32_t(head[6]) << 16 | std::uint32_t(head[7]) << 24;
    const bool multiPart = (version & kMultiPartFlag) != 0;
    for (int part = 0;; ++part) {
        const std::string where = multiPart ? "header of part " + std::to_string(part) : "header";
        std::string name, type;
        int attributes = 0;
        for (;; ++attributes) {
            const long long at = (long long)in.tellg();
            if (!readName(in, name))
                throw Error(ErrorKind::Format,
                            "damaged or truncated OpenEXR header at byte " + std::to_string(at) +
                                ": an attribute name runs past the file or its 255 characters",
                            file, where);
            if (name.empty()) break;  // the end of this header
            unsigned char length[4] = {};
            if (!readName(in, type) || !in.read(reinterpret_cast<char*>(length), 4))
                throw Error(ErrorKind::Format,
                            "truncated OpenEXR header: attribute '" + name + "' at byte " +
                                std::to_string(at) + " has no type or size",
                            file, where);
            const std::int32_t claimed =
                std::int32_t(std::uint32_t(length[0]) | std::uint32_t(length[1]) << 8 |
                             std::uint32_t(length[2]) << 16 | std::uint32_t(length[3]) << 24);
            const long long left = size - (long long)in.tellg();
            if (claimed < 0 || claimed > left)
                throw Error(ErrorKind::Format,
                            "OpenEXR header attribute '" + name + "' (" + type + ") at byte " +
                                std::to_string(at) + " claims " + std::to_string(claimed) +
                                " bytes; the file has " + std::to_string(left) + " left",
                            file, where);
            in.seekg(claimed, std::ios::cur);
        }
        // A single-part file has one header; a multi-part file's list of headers ends with an
        // empty one (a header with no attribute).
        if (!multiPart || attributes == 0) return;
    }
}

}  // namespace glint::detail
