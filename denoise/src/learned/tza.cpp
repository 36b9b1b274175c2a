// Open Image Denoise weight blobs (.tza), as OIDN's core/tza.cpp writes them (version 2):
//
//   offset 0   uint16 magic 0x41D7, uint8 major version (2), uint8 minor version
//   offset 4   uint64 offset of the tensor table
//   table      uint32 tensor count, then per tensor: uint16 name length, the name, uint8 rank,
//              rank × uint32 dimensions, rank layout characters ("oihw" or "x"), one data type
//              character ('h' fp16, 'f' fp32), uint64 offset of its data
//
// All integers are little-endian. Every read is bounds-checked so that a damaged file is a clear
// Format error instead of a crash.
#include "learned/tza.h"

#include <cstring>

#include "glint/image/error.h"

namespace glint::denoise::learned {

namespace {

// Bounds-checked little-endian cursor over the blob.
class Reader {
  public:
    Reader(const std::vector<std::uint8_t>& blob, const std::string& file)
        : m_blob(blob), m_file(file) {}

    void seek(std::uint64_t offset) {
        if (offset > m_blob.size()) fail(offset, "offset past the end of the file");
        m_pos = std::size_t(offset);
    }
    std::size_t pos() const { return m_pos; }

    template <typename T>
    T read() {
        need(sizeof(T));
        T v{};
        // Little-endian hosts only (x86-64, AArch64), like OIDN.
        std::memcpy(&v, m_blob.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        return v;
    }
    std::string readString(std::size_t n) {
        need(n);
        std::string s(reinterpret_cast<const char*>(m_blob.data() + m_pos), n);
        m_pos += n;
        return s;
    }
    const std::uint8_t* span(std::uint64_t offset, std::uint64_t bytes) const {
        if (offset > m_blob.size() || bytes > m_blob.size() - offset)
            fail(offset, "tensor data past the end of the file (" + std::to_string(bytes) +
                             " bytes at " + std::to_string(offset) + ", file has " +
                             std::to_string(m_blob.size()) + ")");
        return m_blob.data() + offset;
    }
    [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
        throw Error(ErrorKind::Format, "corrupt OIDN weight blob: " + what, m_file,
                    "byte " + std::to_string(at));
    }

  private:
    void need(std::size_t n) const {
        if (n > m_blob.size() - m_pos)
            fail(m_pos, "truncated (needs " + std::to_string(n) + " more bytes)");
    }
    const std::vector<std::uint8_t>& m_blob;
    const std::string& m_file;
    std::size_t m_pos = 0;
};

constexpr std::uint16_t kMagic = 0x41D7;
constexpr std::uint64_t kMaxElements = std::uint64_t(1) << 28;  // 1 GiB of fp32: surely corrupt

}  // namespace

float halfToFloat(std::uint16_t h) {
    const std::uint32_t sign = std::uint32_t(h & 0x8000u) << 16;
    std::uint32_t exp = (h >> 10) & 0x1fu;
    std::uint32_t mant = h & 0x3ffu;
    std::uint32_t bits = 0;
    if (exp == 0x1f) {
        bits = sign | 0x7f800000u | (mant << 13);  // Inf or NaN
    } else if (exp != 0) {
        bits = sign | ((exp + 112) << 23) | (mant << 13);
    } else if (mant != 0) {
        // Subnormal half: normalise the mantissa.
        int e = -1;
        do {
            mant <<= 1;
            ++e;
        } while ((mant & 0x400u) == 0);
        bits = sign | (std::uint32_t(112 - e) << 23) | ((mant & 0x3ffu) << 13);
    } else {
        bits = sign;
    }
    float f = 0.0f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}

TzaTensors parseTza(const std::vector<std::uint8_t>& blob, const std::string& file) {
    Reader r(blob, file);
    // Header: magic, version, table offset.
    if (r.read<std::uint16_t>() != kMagic) r.fail(0, "bad magic (expected 0x41D7)");
    const auto major = r.read<std::uint8_t>();
    r.read<std::uint8_t>();  // minor version
    if (major != 2) r.fail(2, "unsupported version " + std::to_string(major) + " (expected 2)");
    r.seek(r.read<std::uint64_t>());

    // Tensor table.
    TzaTensors tensors;
    const auto count = r.read<std::uint32_t>();
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::size_t at = r.pos();
        const std::string name = r.readString(r.read<std::uint16_t>());
        const auto rank = r.read<std::uint8_t>();
        if (rank == 0 || rank > 4)
            r.fail(at, "tensor '" + name + "' has rank " + std::to_string(rank));
        TzaTensor t;
        std::uint64_t n = 1;
        for (int d = 0; d < rank; ++d) {
            const auto dim = r.read<std::uint32_t>();
            n *= dim;
            if (dim == 0 || n > kMaxElements) r.fail(at, "tensor '" + name + "' has a bad shape");
            t.shape.push_back(int(dim));
        }
        t.layout = r.readString(rank);
        if (t.layout != "oihw" && t.layout != "x")
            r.fail(at, "tensor '" + name + "' has layout '" + t.layout + "' (expected oihw or x)");
        const char type = char(r.read<std::uint8_t>());
        const auto offset = r.read<std::uint64_t>();
        if (type != 'h' && type != 'f')
            r.fail(at, "tensor '" + name + "' has data type '" + std::string(1, type) +
                           "' (expected h or f)");
        const std::uint64_t elem = type == 'h' ? 2 : 4;
        const std::uint8_t* src = r.span(offset, n * elem);
        // Convert to fp32.
        t.data.resize(std::size_t(n));
        for (std::size_t k = 0; k < t.data.size(); ++k) {
            if (type == 'h') {
                std::uint16_t h = 0;
                std::memcpy(&h, src + 2 * k, 2);
                t.data[k] = halfToFloat(h);
            } else {
                std::memcpy(&t.data[k], src + 4 * k, 4);
            }
        }
        if (!tensors.emplace(name, std::move(t)).second)
            r.fail(at, "tensor '" + name + "' appears twice");
    }
    return tensors;
}

}  // namespace glint::denoise::learned
