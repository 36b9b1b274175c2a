// Structural checks of PNG and JPEG files before their libraries see them: libpng's own
// message for a truncated or damaged file names no byte (and OpenImageIO's module prints it on
// stderr), and a truncated JPEG decodes to a partly grey image. The damage is found here and
// reported as one glint::Error naming the byte.
#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "image_files.h"

namespace glint::detail {

namespace {

// CRC-32 (ISO 3309, the PNG chunk checksum), table-driven.
std::uint32_t crc32(const unsigned char* data, std::size_t n, std::uint32_t crc = 0xffffffffu) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xffu] ^ (crc >> 8);
    return crc;
}

std::uint32_t bigEndian(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
           std::uint32_t(p[3]);
}

}  // namespace

std::vector<unsigned char> fileHead(const std::filesystem::path& path, std::size_t limit) {
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes(limit);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(limit));
    bytes.resize(std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
    return bytes;
}

std::vector<unsigned char> fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error(ErrorKind::Io, "cannot open file for reading", path.string(), "open");
    const std::streamoff size = in.tellg();
    std::vector<unsigned char> bytes(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    if (in.gcount() != std::streamsize(bytes.size()))
        throw Error(ErrorKind::Io, "cannot read the whole file", path.string(),
                    "byte " + std::to_string(in.gcount()));
    return bytes;
}

bool isPng(std::span<const unsigned char> bytes) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return bytes.size() >= 8 && std::equal(bytes.begin(), bytes.begin() + 8, signature);
}

bool isPng(const std::filesystem::path& path) {
    return isPng(fileHead(path, 8));
}

void checkPngStructure(std::span<const unsigned char> bytes, const std::string& file) {
    auto fail = [&](std::size_t at, const std::string& what) {
        throw Error(ErrorKind::Format, "damaged PNG: " + what, file, "byte " + std::to_string(at));
    };
    std::size_t at = 8;
    bool sawHeader = false, sawData = false;
    while (true) {
        if (at + 12 > bytes.size()) fail(at, "truncated (the file ends inside a chunk header)");
        const std::uint32_t length = bigEndian(&bytes[at]);
        const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
        if (length > 0x7fffffffu || at + 12 + std::size_t(length) > bytes.size())
            fail(at, "truncated (chunk '" + type + "' of " + std::to_string(length) +
                         " bytes goes past the end of the file)");
        const std::uint32_t stored = bigEndian(&bytes[at + 8 + length]);
        if ((crc32(&bytes[at + 4], 4 + std::size_t(length)) ^ 0xffffffffu) != stored)
            fail(at, "chunk '" + type + "' fails its CRC");
        if (!sawHeader && type != "IHDR") fail(at, "the first chunk is not IHDR");
        // libpng prints its own lines for a zero width or height (PNG 1.2, 11.2.2: both >= 1).
        if (!sawHeader && length >= 8 &&
            (bigEndian(&bytes[at + 8]) == 0 || bigEndian(&bytes[at + 12]) == 0))
            fail(at, "IHDR says the image is " + std::to_string(bigEndian(&bytes[at + 8])) + "x" +
                         std::to_string(bigEndian(&bytes[at + 12])) +
                         " pixels; a PNG is at least 1x1");
        sawHeader = true;
        sawData = sawData || type == "IDAT";
        at += 12 + std::size_t(length);
        if (type == "IEND") break;
    }
    if (!sawData) fail(at, "no image data (IDAT)");
}

void checkPngStructure(const std::filesystem::path& path) {
    checkPngStructure(fileBytes(path), path.string());
}

bool isJpeg(std::span<const unsigned char> bytes) {
    return bytes.size() >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff;
}

bool isJpeg(const std::filesystem::path& path) {
    return isJpeg(fileHead(path, 3));
}

void checkJpegStructure(std::span<const unsigned char> bytes, const std::string& file) {
    // The end-of-image marker closes the file (a few trailing bytes are tolerated).
    const std::size_t tail = std::min<std::size_t>(bytes.size(), 64);
    for (std::size_t i = bytes.size() - tail; i + 1 < bytes.size(); ++i)
        if (bytes[i] == 0xff && bytes[i + 1] == 0xd9) return;
    throw Error(ErrorKind::Format, "truncated JPEG (no end-of-image marker)", file,
                "byte " + std::to_string(bytes.size()));
}

void checkJpegStructure(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    const std::streamoff size = in.tellg();
    const std::streamoff tail = std::min<std::streamoff>(size, 64);
    std::vector<unsigned char> end(static_cast<std::size_t>(tail));
    in.seekg(size - tail);
    in.read(reinterpret_cast<char*>(end.data()), tail);
    for (std::size_t i = 0; i + 1 < end.size(); ++i)
        if (end[i] == 0xff && end[i + 1] == 0xd9) return;
    throw Error(ErrorKind::Format, "truncated JPEG (no end-of-image marker)", path.string(),
                "byte " + std::to_string(size));
}

}  // namespace glint::detail
