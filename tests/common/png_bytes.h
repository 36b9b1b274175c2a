// A PNG file built byte by byte for tests of bad images: its IHDR may claim any size (a 0x0
// image, which no writer produces), the image data is an empty zlib stream.
#pragma once

#include <cstdint>
#include <string>

namespace glint::test {

/// The bytes of a PNG whose IHDR says `width` x `height`, 8-bit RGB, with CRCs that hold.
inline std::string pngOfSize(std::uint32_t width, std::uint32_t height) {
    auto crc = [](const std::string& bytes) {
        std::uint32_t c = 0xffffffffu;  // CRC-32 (ISO 3309), bit by bit
        for (unsigned char b : bytes) {
            c ^= b;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
        }
        return c ^ 0xffffffffu;
    };
    auto u32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
    };
    auto chunk = [&](const std::string& type, const std::string& data) {
        return u32(std::uint32_t(data.size())) + type + data + u32(crc(type + data));
    };
    const std::string header = u32(width) + u32(height) + std::string{8, 2, 0, 0, 0};
    // A zlib stream of one empty stored block (RFC 1950/1951), Adler-32 of nothing = 1.
    const std::string empty{'\x78', '\x01', '\x01', '\x00', '\x00', '\xff',
                            '\xff', '\x00', '\x00', '\x00', '\x01'};
    return std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", header) + chunk("IDAT", empty) +
           chunk("IEND", "");
}

}  // namespace glint::test
