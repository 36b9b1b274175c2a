// tev's IPC protocol (github.com/Tom94/tev, src/Ipc.cpp): the packets a renderer sends to a
// running tev and that the studio accepts, their encoding and decoding, and the splitting of a
// TCP byte stream into packets (docs/renderer.md, "Watching a render in tev"; docs/studio.md,
// "Receiving images"). A packet is a little-endian uint32 holding its whole length (these four
// bytes included), a type byte, then its fields: bools as one byte, strings NUL-terminated,
// int32/int64/float little-endian.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace glint::tev {

/// The port tev listens on by default (on 127.0.0.1).
inline constexpr int kDefaultPort = 14158;
/// The longest packet accepted (1 GiB): a longer length field is a broken stream.
inline constexpr std::uint32_t kMaxPacketBytes = 1u << 30;

/// The type byte of a packet.
enum class PacketType : std::uint8_t {
    OpenImage = 0,    ///< "path:channels" in one string (read only)
    ReloadImage = 1,  ///< reload a file tev opened
    CloseImage = 2,
    UpdateImage = 3,     ///< one channel, its pixels (pbrt-v4 sends these)
    CreateImage = 4,     ///< name, size, channel names
    UpdateImageV2 = 5,   ///< several channels, one plane each (read only)
    UpdateImageV3 = 6,   ///< several channels with offsets and strides (what Glint sends)
    OpenImageV2 = 7,     ///< path and channel selector apart (what Glint sends)
    VectorGraphics = 8,  ///< drawing commands over an image (recognised, not used)
};

/// Opens an image file in the viewer.
struct OpenImage {
    std::string path;
    std::string channelSelector;
    bool grabFocus = false;
};
/// Reloads an image file the viewer opened.
struct ReloadImage {
    std::string name;
    bool grabFocus = false;
};
/// Closes an image.
struct CloseImage {
    std::string name;
};
/// Creates an image of `width` × `height` pixels with these channels, all zero.
struct CreateImage {
    std::string name;
    bool grabFocus = false;
    int width = 0, height = 0;
    std::vector<std::string> channels;  ///< "R", "G", "B", "albedo.R", …: tev groups by prefix
};
/// Sets a tile of some channels of an image.
struct UpdateImage {
    std::string name;
    bool grabFocus = false;
    std::vector<std::string> channels;
    int x = 0, y = 0, width = 0, height = 0;  ///< the tile in the image
    /// width × height × channels values, row-major, channels interleaved (glint::Image's layout)
    std::vector<float> pixels;
};
/// Vector graphics over an image: only its image's name is read.
struct VectorGraphics {
    std::string name;
};

using Packet =
    std::variant<OpenImage, ReloadImage, CloseImage, CreateImage, UpdateImage, VectorGraphics>;

/// The packet's kind as the protocol names it ("CreateImage", …).
const char* packetName(const Packet& packet);

/// The bytes of `packet`, length field first: UpdateImage as UpdateImageV3 (offsets c, strides
/// the channel count), OpenImage as OpenImageV2. Throws glint::Error(InvalidArgument) for a
/// name holding a NUL, no channels, a size outside 1 … 65536 per side, pixels that do not
/// match the size, or more than kMaxPacketBytes.
std::vector<unsigned char> encode(const Packet& packet);

/// The packet `bytes` hold (one whole packet, length field first; every version of every
/// type). Throws glint::Error(Format) naming "tev packet" and the byte for a length field that
/// differs from the bytes, an unknown type, a field past the end, a size outside 1 … 65536 per
/// side (2^28 pixels in all), 0 or more than 1024 channels, offsets or strides that reach
/// past the pixels sent.
Packet decode(std::span<const unsigned char> bytes);

/// Splits a byte stream (one TCP connection) into whole packets.
class PacketStream {
  public:
    /// Adds bytes received.
    void append(std::span<const unsigned char> bytes);
    /// The next whole packet's bytes (for decode), or nullopt until all of it arrived. Throws
    /// glint::Error(Format) for a length field below 5 or above kMaxPacketBytes: the stream
    /// cannot be followed past it (the connection must be dropped).
    std::optional<std::vector<unsigned char>> next();
    /// Bytes received and not yet returned.
    std::size_t buffered() const { return m_bytes.size() - m_start; }

  private:
    std::vector<unsigned char> m_bytes;
    std::size_t m_start = 0;
};

}  // namespace glint::tev
