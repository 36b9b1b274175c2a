#include "scene/texture_store.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include "glint/image/error.h"
#include "glint/image/internal/modules.h"
#include "glint/image/io.h"
#include "glint/image/random.h"
#include "scene/half_float.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace {

/// A filtered value as the renderer may use it: non-finite 0, the rest in [0, kMaxRadiance].
float sane(float v) {
    return std::isfinite(v) ? std::clamp(v, 0.0f, float(kMaxRadiance)) : 0.0f;
}

/// A footprint axis as OIIO takes it: finite and not absurdly large (a grazing hit can give a
/// huge or infinite one; beyond a few periods the filter is the texture's mean anyway).
float saneDerivative(float d) {
    return std::isfinite(d) ? std::clamp(d, -16.0f, 16.0f) : 0.0f;
}

/// A new tile cache from the module (texture_cache.h), loaded by the first call. Throws
/// glint::Error(Io) naming `sceneFile` and `where` when the module cannot be had.
std::unique_ptr<TextureCache> newTextureCache(const std::string& sceneFile,
                                              const std::string& where) {
    using Entry = TextureCache* (*)();
    static const glint::detail::ModuleEntry module = glint::detail::loadModule(
        "libglint_textures.so", "GLINT_TEXTURES_MODULE", kTextureCacheEntry);
    if (!module.entry)
        throw Error(ErrorKind::Io, "cannot read texture files: " + module.failure, sceneFile,
                    where);
    return std::unique_ptr<TextureCache>(reinterpret_cast<Entry>(module.entry)());
}

}  // namespace

TextureStore::TextureStore(int cacheMb) : m_cacheMb(cacheMb) {}

TextureStore::~TextureStore() = default;

void TextureStore::setCacheMb(int megabytes) {
    m_cacheMb = megabytes;
    if (m_cache) m_cache->setMaxMemoryMb(tileCacheMb());
}

float TextureStore::tileCacheMb() const {
    const float resident = float(double(m_residentBytes) / double(1 << 20));
    return std::max(float(m_cacheMb) - resident, 0.25f * float(m_cacheMb));
}

void TextureStore::addResidentBytes(std::size_t bytes) {
    m_residentBytes += bytes;
    setCacheMb(m_cacheMb);
}

std::vector<std::pair<int, int>> TextureStore::levelSizes(int file) const {
    std::vector<std::pair<int, int>> sizes;
    for (const CachedLevel& level : m_files[std::size_t(file)].levels)
        sizes.emplace_back(level.width, level.height);
    return sizes;
}

namespace {

/// Texel value `i` of a tile's pixels as a float (integer formats 0 … 1).
float tileValue(const TextureCache& cache, const TilePin& pin, std::size_t i) {
    switch (pin.format) {
        case TexelFormat::Half:
            return halfToFloat(static_cast<const std::uint16_t*>(pin.pixels)[i]);
        case TexelFormat::Float:
            return static_cast<const float*>(pin.pixels)[i];
        case TexelFormat::UInt8:
            return float(static_cast<const std::uint8_t*>(pin.pixels)[i]) * (1.0f / 255.0f);
        case TexelFormat::UInt16:
            return float(static_cast<const std::uint16_t*>(pin.pixels)[i]) * (1.0f / 65535.0f);
        case TexelFormat::Other:
            break;
    }
    return cache.otherTexel(pin.pixels, pin.otherFormat, i);
}

}  // namespace

bool TextureStore::texelQuad(int file, int level, int x0, int x1, int y0, int y1, Vec4 out[4],
                             TilePin& pin) const {
    const File& f = m_files[std::size_t(file)];
    const CachedLevel& tiles = f.levels[std::size_t(level)];
    TextureCache& cache = *m_cache;
    if (!pin.thread) pin.thread = cache.perThread();
    const int channels = f.info.channels, n = std::min(channels, 4);
    const int xs[4] = {x0, x1, x0, x1}, ys[4] = {y0, y0, y1, y1};
    // Each texel's tile origin: two divisions for the quad, not eight (x1 is mostly x0 + 1, in
    // x0's tile).
    auto origin = [](int i, int size) { return (i / size) * size; };
    const int ox0 = origin(x0, tiles.tileWidth), oy0 = origin(y0, tiles.tileHeight);
    const int ox1 = x1 >= ox0 && x1 - ox0 < tiles.tileWidth ? ox0 : origin(x1, tiles.tileWidth);
    const int oy1 = y1 >= oy0 && y1 - oy0 < tiles.tileHeight ? oy0 : origin(y1, tiles.tileHeight);
    const int oxs[4] = {ox0, ox1, ox0, ox1}, oys[4] = {oy0, oy0, oy1, oy1};
    // The four texels, and a lookup's taps, mostly share a tile: it is fetched once.
    bool ok = true;
    for (int k = 0; k < 4; ++k) {
        const int x = tiles.x + xs[k], y = tiles.y + ys[k];
        const int tx = tiles.x + oxs[k], ty = tiles.y + oys[k];
        if (!pin.tile || tx != pin.x || ty != pin.y || level != pin.level || file != pin.file) {
            release(pin);
            CachedTile held;
            if (!cache.tile(f.imageHandle, pin.thread, level, x, y, held)) {
                ok = false;
                break;
            }
            pin.tile = held.tile;
            pin.pixels = held.pixels;
            pin.format = held.format;
            pin.otherFormat = held.otherFormat;
            pin.file = file, pin.level = level, pin.x = tx, pin.y = ty;
        }
        const std::size_t at =
            (std::size_t(y - ty) * std::size_t(tiles.tileWidth) + std::size_t(x - tx)) *
            std::size_t(channels);
        float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int c = 0; c < n; ++c) v[c] = tileValue(cache, pin, at + std::size_t(c));
        // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
        out[k] = n <= 2 ? Vec4{v[0], v[0], v[0], n == 2 ? v[1] : 1.0f}
                        : Vec4{v[0], v[1], v[2], n == 4 ? v[3] : 1.0f};
    }
    if (!ok) {
        for (int k = 0; k < 4; ++k) out[k] = {};
        recordFailure(file);
    }
    return ok;
}

void TextureStore::release(TilePin& pin) const {
    if (!pin.tile) return;
    m_cache->release(pin.tile);
    pin.tile = nullptr;
}

bool TextureStore::readLevel(int file, int level, std::vector<float>& rgba) const {
    const File& f = m_files[std::size_t(file)];
    const CachedLevel& spec = f.levels[std::size_t(level)];
    const int n = std::min(f.info.channels, 4);
    const std::size_t texels = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<float> stored(texels * std::size_t(n));
    if (!m_cache->texels(f.handle, level, spec.x, spec.x + spec.width, spec.y, spec.y + spec.height,
                         n, stored.data())) {
        recordFailure(file);
        return false;
    }
    // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
    rgba.resize(texels * 4);
    for (std::size_t i = 0; i < texels; ++i) {
        const float* v = stored.data() + i * std::size_t(n);
        float* out = rgba.data() + i * 4;
        if (n <= 2)
            out[0] = out[1] = out[2] = v[0], out[3] = n == 2 ? v[1] : 1.0f;
        else
            out[0] = v[0], out[1] = v[1], out[2] = v[2], out[3] = n == 4 ? v[3] : 1.0f;
    }
    return true;
}

int TextureStore::open(const std::filesystem::path& file, const std::filesystem::path& sceneFile,
                       const std::string& where) {
    for (std::size_t i = 0; i < m_files.size(); ++i)
        if (m_files[i].path == file) return int(i);
    if (!m_cache) {
        m_cache = newTextureCache(sceneFile.string(), where);
        m_cache->setMaxMemoryMb(tileCacheMb());
    }
    CachedFile cached;
    if (const std::string problem = m_cache->open(file.string(), cached); !problem.empty())
        throw Error(ErrorKind::Format, "texture '" + file.string() + "' " + problem,
                    sceneFile.string(), where);
    File f;
    f.path = file;
    f.handle = cached.handle;
    f.imageHandle = cached.imageHandle;
    f.levels = std::move(cached.levels);
    f.info.width = cached.width;
    f.info.height = cached.height;
    f.info.channels = cached.channels;
    f.info.tiled = cached.tiled;
    f.info.mipmapped = cached.mipmapped;
    f.info.srgb = srgbEncodedFile(cached.colorSpace, cached.eightBit);
    f.info.fingerprint = std::move(cached.fingerprint);
    m_files.push_back(std::move(f));
    return int(m_files.size()) - 1;
}

std::uint64_t TextureStore::contentHash(int file) const {
    const File& f = m_files[std::size_t(file)];
    std::uint64_t h = 0x7f4a7c15cbf29ce4ULL;
    auto fold = [&h](const char* data, std::size_t size) {
        h = hash64(h, size);
        for (std::size_t i = 0; i < size; i += 8) {
            std::uint64_t word = 0;
            std::memcpy(&word, data + i, std::min<std::size_t>(8, size - i));
            h = hash64(h, word);
        }
    };
    if (!f.info.fingerprint.empty()) {
        fold(f.info.fingerprint.data(), f.info.fingerprint.size());
        return h;
    }
    std::ifstream in(f.path, std::ios::binary);
    std::vector<char> buffer(std::size_t(1) << 20);
    while (in) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        if (in.gcount() > 0) fold(buffer.data(), std::size_t(in.gcount()));
    }
    return h;
}

Vec4 TextureStore::lookup(int file, float s, float t, const TexFootprint& footprint,
                          TextureWrap wrapS, TextureWrap wrapT, bool decodeSrgb) const {
    const File& f = m_files[std::size_t(file)];
    // Ask for what the file has (at most RGBA) and spread it out below.
    const int n = std::min(f.info.channels, 4);
    float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const bool ok = m_cache->filter(f.handle, s, t, saneDerivative(footprint.dx.x),
                                    saneDerivative(footprint.dx.y), saneDerivative(footprint.dy.x),
                                    saneDerivative(footprint.dy.y), wrapS, wrapT, n, v);
    if (!ok) {
        recordFailure(file);
        return {0.0f, 0.0f, 0.0f, 1.0f};
    }
    // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
    const Vec4 out = n <= 2 ? Vec4{v[0], v[0], v[0], n == 2 ? v[1] : 1.0f}
                            : Vec4{v[0], v[1], v[2], n == 4 ? v[3] : 1.0f};
    return usableTextureValue(out, decodeSrgb);
}

Vec4 usableTextureValue(Vec4 v, bool decodeSrgb) {
    Vec4 out{sane(v.x), sane(v.y), sane(v.z), sane(v.w)};
    // Decoded after filtering, as Cycles does for 8-bit sRGB images.
    if (decodeSrgb) out = {srgbDecode(out.x), srgbDecode(out.y), srgbDecode(out.z), out.w};
    return out;
}

void TextureStore::recordFailure(int file) const {
    const std::string reason = m_cache->error();
    const std::lock_guard<std::mutex> lock(m_failureMutex);
    if (m_failed.exchange(true)) return;  // the first failure is the one reported
    m_failure = reason;
    m_failedFile = file;
}

void TextureStore::clearFailure() const {
    const std::lock_guard<std::mutex> lock(m_failureMutex);
    m_failed = false;
    m_failure.clear();
    m_failedFile = -1;
}

void TextureStore::throwIfFailed() const {
    if (!m_failed) return;
    const std::lock_guard<std::mutex> lock(m_failureMutex);
    throw Error(ErrorKind::Io,
                "texture could not be read while rendering (damaged or truncated?): " + m_failure,
                m_files[std::size_t(m_failedFile)].path.string(), "pixels");
}

std::uint64_t TextureStore::cacheBytesUsed() const {
    return m_cache ? m_cache->bytesUsed() : 0;
}

}  // namespace glint::render::detail
