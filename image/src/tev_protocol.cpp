// tev's IPC packets: encoding, decoding and stream splitting (glint/image/tev_protocol.h).
#include "glint/image/tev_protocol.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <functional>
#include <type_traits>

#include "glint/image/error.h"

namespace glint::tev {

namespace {

constexpr const char* kWhat = "tev packet";
constexpr long long kMaxSide = 1 << 16, kMaxPixels = 1LL << 28;
constexpr int kMaxChannels = 1024;

template <typename T>
T fromLittleEndian(T value) {
    if constexpr (std::endian::native == std::endian::big) {
        auto bytes = std::bit_cast<std::array<unsigned char, sizeof(T)>>(value);
        std::reverse(bytes.begin(), bytes.end());
        return std::bit_cast<T>(bytes);
    }
    return value;
}

/// Appends fields little-endian; the length field is filled in by bytes().
class Writer {
  public:
    explicit Writer(PacketType type) : m_bytes(4, 0) { put(std::uint8_t(type)); }

    template <typename T>
    void put(T value) {
        static_assert(std::is_trivially_copyable_v<T>);
        value = fromLittleEndian(value);
        const auto* p = reinterpret_cast<const unsigned char*>(&value);
        m_bytes.insert(m_bytes.end(), p, p + sizeof(T));
    }
    void putBool(bool value) { put(std::uint8_t(value ? 1 : 0)); }
    void putString(const std::string& s, const char* field) {
        if (s.find('\0') != std::string::npos)
            throw Error(ErrorKind::InvalidArgument,
                        std::string(field) +
                            " holds a NUL character, which ends a string of the "
                            "protocol",
                        kWhat, field);
        m_bytes.insert(m_bytes.end(), s.begin(), s.end());
        m_bytes.push_back(0);
    }
    void putFloats(const std::vector<float>& values) {
        const std::size_t at = m_bytes.size();
        m_bytes.resize(at + values.size() * sizeof(float));
        if constexpr (std::endian::native == std::endian::little)
            std::memcpy(m_bytes.data() + at, values.data(), values.size() * sizeof(float));
        else
            for (std::size_t i = 0; i < values.size(); ++i) {
                const float v = fromLittleEndian(values[i]);
                std::memcpy(m_bytes.data() + at + i * sizeof(float), &v, sizeof(float));
            }
    }

    std::vector<unsigned char> bytes() && {
        if (m_bytes.size() > kMaxPacketBytes)
            throw Error(ErrorKind::InvalidArgument,
                        "the packet would be " + std::to_string(m_bytes.size()) +
                            " bytes; expected at most " + std::to_string(kMaxPacketBytes),
                        kWhat, "length");
        const auto length = fromLittleEndian(std::uint32_t(m_bytes.size()));
        std::memcpy(m_bytes.data(), &length, 4);
        return std::move(m_bytes);
    }

  private:
    std::vector<unsigned char> m_bytes;
};

/// Reads fields in order; every read past the end throws Error(Format) naming its byte.
class Reader {
  public:
    explicit Reader(std::span<const unsigned char> bytes) : m_bytes(bytes) {}

    template <typename T>
    T get(const char* field) {
        need(sizeof(T), field);
        T value;
        std::memcpy(&value, m_bytes.data() + m_at, sizeof(T));
        m_at += sizeof(T);
        return fromLittleEndian(value);
    }
    bool getBool(const char* field) { return get<std::uint8_t>(field) != 0; }
    std::string getString(const char* field) {
        const auto* begin = m_bytes.data() + m_at;
        const auto* end =
            static_cast<const unsigned char*>(std::memchr(begin, 0, m_bytes.size() - m_at));
        if (!end) fail(std::string(field) + ": the string has no terminating NUL before the end");
        std::string s(reinterpret_cast<const char*>(begin), std::size_t(end - begin));
        m_at += s.size() + 1;
        return s;
    }
    std::vector<std::string> getStrings(int count, const char* field) {
        std::vector<std::string> out;
        for (int i = 0; i < count; ++i) out.push_back(getString(field));
        return out;
    }
    /// The float at index `i` of the data that starts here.
    float floatAt(std::size_t i) const {
        float v;
        std::memcpy(&v, m_bytes.data() + m_at + i * sizeof(float), sizeof(float));
        return fromLittleEndian(v);
    }
    std::size_t floatsLeft() const { return (m_bytes.size() - m_at) / sizeof(float); }

    [[noreturn]] void fail(const std::string& what) const {
        throw Error(ErrorKind::Format, what, kWhat, "byte " + std::to_string(m_at));
    }

  private:
    void need(std::size_t n, const char* field) const {
        if (m_bytes.size() - m_at < n)
            fail(std::string(field) + ": the packet ends after " + std::to_string(m_bytes.size()) +
                 " bytes");
    }

    std::span<const unsigned char> m_bytes;
    std::size_t m_at = 0;
};

void checkSize(long long width, long long height, const std::string& what,
               const std::function<void(const std::string&)>& fail) {
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide ||
        width * height > kMaxPixels)
        fail(what + " is " + std::to_string(width) + "x" + std::to_string(height) +
             "; expected 1 … 65536 pixels per side and at most 2^28 in all");
}

int readChannelCount(Reader& in) {
    const auto n = in.get<std::int32_t>("channel count");
    if (n < 1 || n > kMaxChannels)
        in.fail("the channel count is " + std::to_string(n) + "; expected 1 … 1024");
    return n;
}

UpdateImage readUpdate(Reader& in, PacketType type) {
    UpdateImage u;
    u.grabFocus = in.getBool("grab focus");
    u.name = in.getString("image name");
    const int n = type == PacketType::UpdateImage ? 1 : readChannelCount(in);
    u.channels = in.getStrings(n, "channel name");
    u.x = in.get<std::int32_t>("x");
    u.y = in.get<std::int32_t>("y");
    u.width = in.get<std::int32_t>("width");
    u.height = in.get<std::int32_t>("height");
    checkSize(u.width, u.height, "the tile", [&](const std::string& m) { in.fail(m); });
    const auto pixels = std::uint64_t(u.width) * std::uint64_t(u.height);
    std::vector<std::int64_t> offsets(static_cast<std::size_t>(n), 0),
        strides(static_cast<std::size_t>(n), 1);
    if (type == PacketType::UpdateImageV3) {
        for (auto& o : offsets) o = in.get<std::int64_t>("channel offset");
        for (auto& s : strides) s = in.get<std::int64_t>("channel stride");
    } else {
        for (int c = 0; c < n; ++c) offsets[std::size_t(c)] = std::int64_t(pixels) * c;
    }
    // Every value a channel reads must lie among the floats sent (the sizes bound the product:
    // pixels ≤ 2^28 and a stride ≤ floatsLeft() ≤ 2^28).
    const std::uint64_t sent = in.floatsLeft();
    for (int c = 0; c < n; ++c) {
        const std::int64_t o = offsets[std::size_t(c)], s = strides[std::size_t(c)];
        if (o < 0 || s < 0 || std::uint64_t(o) >= sent || std::uint64_t(s) > sent ||
            std::uint64_t(o) + (pixels - 1) * std::uint64_t(s) >= sent)
            in.fail("channel " + std::to_string(c) + " (offset " + std::to_string(o) + ", stride " +
                    std::to_string(s) + ") reads past the " + std::to_string(sent) +
                    " values sent for a " + std::to_string(u.width) + "x" +
                    std::to_string(u.height) + " tile");
    }
    u.pixels.resize(pixels * std::size_t(n));
    for (std::uint64_t p = 0; p < pixels; ++p)
        for (int c = 0; c < n; ++c)
            u.pixels[p * std::size_t(n) + std::size_t(c)] =
                in.floatAt(std::size_t(offsets[std::size_t(c)]) +
                           std::size_t(p) * std::size_t(strides[std::size_t(c)]));
    return u;
}

}  // namespace

const char* packetName(const Packet& packet) {
    constexpr const char* names[] = {"OpenImage",   "ReloadImage", "CloseImage",
                                     "CreateImage", "UpdateImage", "VectorGraphics"};
    return names[packet.index()];
}

std::vector<unsigned char> encode(const Packet& packet) {
    const auto invalid = [](const std::string& message, const char* where) {
        throw Error(ErrorKind::InvalidArgument, message, kWhat, where);
    };
    const auto checkChannels = [&](const std::vector<std::string>& channels) {
        if (channels.empty() || channels.size() > std::size_t(kMaxChannels))
            invalid("expected 1 … 1024 channels, got " + std::to_string(channels.size()),
                    "channels");
    };
    if (const auto* p = std::get_if<OpenImage>(&packet)) {
        Writer out(PacketType::OpenImageV2);
        out.putBool(p->grabFocus);
        out.putString(p->path, "path");
        out.putString(p->channelSelector, "channel selector");
        return std::move(out).bytes();
    }
    if (const auto* p = std::get_if<ReloadImage>(&packet)) {
        Writer out(PacketType::ReloadImage);
        out.putBool(p->grabFocus);
        out.putString(p->name, "image name");
        return std::move(out).bytes();
    }
    if (const auto* p = std::get_if<CloseImage>(&packet)) {
        Writer out(PacketType::CloseImage);
        out.putString(p->name, "image name");
        return std::move(out).bytes();
    }
    if (const auto* p = std::get_if<CreateImage>(&packet)) {
        checkSize(p->width, p->height, "the image",
                  [&](const std::string& m) { invalid(m, "size"); });
        checkChannels(p->channels);
        Writer out(PacketType::CreateImage);
        out.putBool(p->grabFocus);
        out.putString(p->name, "image name");
        out.put(std::int32_t(p->width));
        out.put(std::int32_t(p->height));
        out.put(std::int32_t(p->channels.size()));
        for (const std::string& c : p->channels) out.putString(c, "channel name");
        return std::move(out).bytes();
    }
    if (const auto* p = std::get_if<UpdateImage>(&packet)) {
        checkSize(p->width, p->height, "the tile",
                  [&](const std::string& m) { invalid(m, "size"); });
        checkChannels(p->channels);
        const std::size_t n = p->channels.size();
        if (p->pixels.size() != std::size_t(p->width) * std::size_t(p->height) * n)
            invalid("expected " + std::to_string(p->width) + "x" + std::to_string(p->height) + "x" +
                        std::to_string(n) + " values, got " + std::to_string(p->pixels.size()),
                    "pixels");
        Writer out(PacketType::UpdateImageV3);
        out.putBool(p->grabFocus);
        out.putString(p->name, "image name");
        out.put(std::int32_t(n));
        for (const std::string& c : p->channels) out.putString(c, "channel name");
        for (int v : {p->x, p->y, p->width, p->height}) out.put(std::int32_t(v));
        // Interleaved: channel c starts at value c, each pixel `n` values on.
        for (std::size_t c = 0; c < n; ++c) out.put(std::int64_t(c));
        for (std::size_t c = 0; c < n; ++c) out.put(std::int64_t(n));
        out.putFloats(p->pixels);
        return std::move(out).bytes();
    }
    const auto& v = std::get<VectorGraphics>(packet);
    invalid("vector graphics of '" + v.name + "' cannot be encoded", "type");
    return {};
}

Packet decode(std::span<const unsigned char> bytes) {
    Reader in(bytes);
    const auto length = in.get<std::uint32_t>("length");
    if (length != bytes.size())
        throw Error(ErrorKind::Format,
                    "the length field says " + std::to_string(length) + " bytes, the packet has " +
                        std::to_string(bytes.size()),
                    kWhat, "byte 0");
    const auto type = PacketType(in.get<std::uint8_t>("type"));
    switch (type) {
        case PacketType::OpenImage:
        case PacketType::OpenImageV2: {
            OpenImage p;
            p.grabFocus = in.getBool("grab focus");
            p.path = in.getString("path");
            if (type == PacketType::OpenImageV2) {
                p.channelSelector = in.getString("channel selector");
            } else if (const auto colon = p.path.find_last_of(':');
                       colon != std::string::npos && colon > 1) {
                // Version 1 held "path:channels" (a drive letter's colon is the path's).
                p.channelSelector = p.path.substr(colon + 1);
                p.path.resize(colon);
            }
            return p;
        }
        case PacketType::ReloadImage: {
            ReloadImage p;
            p.grabFocus = in.getBool("grab focus");
            p.name = in.getString("image name");
            return p;
        }
        case PacketType::CloseImage:
            return CloseImage{in.getString("image name")};
        case PacketType::CreateImage: {
            CreateImage p;
            p.grabFocus = in.getBool("grab focus");
            p.name = in.getString("image name");
            p.width = in.get<std::int32_t>("width");
            p.height = in.get<std::int32_t>("height");
            checkSize(p.width, p.height, "the image", [&](const std::string& m) { in.fail(m); });
            p.channels = in.getStrings(readChannelCount(in), "channel name");
            return p;
        }
        case PacketType::UpdateImage:
        case PacketType::UpdateImageV2:
        case PacketType::UpdateImageV3:
            return readUpdate(in, type);
        case PacketType::VectorGraphics: {
            in.getBool("grab focus");
            return VectorGraphics{in.getString("image name")};
        }
    }
    throw Error(ErrorKind::Format,
                "unknown packet type " + std::to_string(int(type)) + " (expected 0 … 8)", kWhat,
                "byte 4");
}

void PacketStream::append(std::span<const unsigned char> bytes) {
    // Drop what was returned before growing.
    if (m_start > 0 && m_start >= m_bytes.size() / 2) {
        m_bytes.erase(m_bytes.begin(), m_bytes.begin() + std::ptrdiff_t(m_start));
        m_start = 0;
    }
    m_bytes.insert(m_bytes.end(), bytes.begin(), bytes.end());
}

std::optional<std::vector<unsigned char>> PacketStream::next() {
    if (buffered() < 4) return std::nullopt;
    std::uint32_t length;
    std::memcpy(&length, m_bytes.data() + m_start, 4);
    length = fromLittleEndian(length);
    if (length < 5 || length > kMaxPacketBytes)
        throw Error(ErrorKind::Format,
                    "a packet's length field says " + std::to_string(length) +
                        " bytes; expected 5 … " + std::to_string(kMaxPacketBytes),
                    kWhat, "length");
    if (buffered() < length) return std::nullopt;
    const auto begin = m_bytes.begin() + std::ptrdiff_t(m_start);
    std::vector<unsigned char> packet(begin, begin + length);
    m_start += length;
    return packet;
}

}  // namespace glint::tev
