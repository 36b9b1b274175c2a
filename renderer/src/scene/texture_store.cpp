#include "scene/texture_store.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/random.h"
#include "scene/half_float.h"
#include "scene/scene_data.h"

namespace glint::render::detail {

namespace {

/// The first line of an OIIO message (its errors may span several).
std::string firstLine(const std::string& message) {
    const std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? std::string("unknown error") : line;
}

OIIO::TextureOpt::Wrap oiioWrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::Clamp:
            return OIIO::TextureOpt::WrapClamp;
        case TextureWrap::Mirror:
            return OIIO::TextureOpt::WrapMirror;
        case TextureWrap::Repeat:
            break;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}

/// A filtered value as the renderer may use it: non-finite 0, the rest in [0, kMaxRadiance].
float sane(float v) {
    return std::isfinite(v) ? std::clamp(v, 0.0f, float(kMaxRadiance)) : 0.0f;
}

/// A footprint axis as OIIO takes it: finite and not absurdly large (a grazing hit can give a
/// huge or infinite one; beyond a few periods the filter is the texture's mean anyway).
float saneDerivative(float d) {
    return std::isfinite(d) ? std::clamp(d, -16.0f, 16.0f) : 0.0f;
}

/// TextureSystems no store uses, for the next store to take. OIIO 2.4's TextureSystem::destroy
/// deletes its object through a type of the wrong size (AddressSanitizer's
/// new-delete-type-mismatch, inside libOpenImageIO), so a store gives its TextureSystem back
/// here, emptied, instead of destroying it: a process holds as many as it ever had scenes with
/// tiled textures alive at once. Held through a pointer that is never freed, so that they stay
/// reachable (not leaks) to the end.
struct TextureSystemPool {
    std::mutex mutex;
    std::vector<OIIO::TextureSystem*> idle;
};
TextureSystemPool& pool() {
    static auto* const instance = new TextureSystemPool;
    return *instance;
}

}  // namespace

struct TextureStore::Impl {
    OIIO::TextureSystem* ts = nullptr;
};

TextureStore::TextureStore(int cacheMb) : m_impl(std::make_unique<Impl>()) {
    // A private TextureSystem with a private ImageCache (shared = false): no other scene's
    // tiles in it. One an earlier store gave back (emptied) is taken first.
    {
        TextureSystemPool& idle = pool();
        const std::lock_guard lock(idle.mutex);
        if (!idle.idle.empty()) {
            m_impl->ts = idle.idle.back();
            idle.idle.pop_back();
        }
    }
    if (!m_impl->ts) m_impl->ts = OIIO::TextureSystem::create(false);
    OIIO::TextureSystem& ts = *m_impl->ts;
    // Untiled files (PNG, JPEG, scanline EXR) are cached in 64² tiles and get MIP levels made
    // on first need, so that they too are filtered by footprint.
    ts.attribute("autotile", 64);
    ts.attribute("automip", 1);
    // Only the calling renderer reports errors; OIIO's own log lines would repeat them.
    ts.attribute("max_errors_per_file", 1);
    setCacheMb(cacheMb);
}

TextureStore::~TextureStore() {
    if (!m_impl || !m_impl->ts) return;
    // Its tiles and open files go now; the object goes back to the pool (see pool()).
    m_impl->ts->invalidate_all(true);
    TextureSystemPool& idle = pool();
    const std::lock_guard lock(idle.mutex);
    idle.idle.push_back(m_impl->ts);
}

void TextureStore::setCacheMb(int megabytes) {
    m_cacheMb = megabytes;
    m_impl->ts->attribute("max_memory_MB", tileCacheMb());
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
    for (const LevelTiles& level : m_files[std::size_t(file)].levels)
        sizes.emplace_back(level.width, level.height);
    return sizes;
}

namespace {

/// Channel `c` of texel `i` of tile pixels of `format` as a float (OIIO's normalisation of
/// integer formats: 0 … 1).
float tileValue(const void* pixels, OIIO::TypeDesc format, std::size_t i) {
    switch (format.basetype) {
        case OIIO::TypeDesc::HALF:
            return halfToFloat(static_cast<const std::uint16_t*>(pixels)[i]);
        case OIIO::TypeDesc::FLOAT:
            return static_cast<const float*>(pixels)[i];
        case OIIO::TypeDesc::UINT8:
            return float(static_cast<const std::uint8_t*>(pixels)[i]) * (1.0f / 255.0f);
        case OIIO::TypeDesc::UINT16:
            return float(static_cast<const std::uint16_t*>(pixels)[i]) * (1.0f / 65535.0f);
        default: {
            float v = 0.0f;
            const char* bytes = static_cast<const char*>(pixels) + i * format.size();
            OIIO::convert_pixel_values(format, bytes, OIIO::TypeDesc::FLOAT, &v, 1);
            return v;
        }
    }
}

}  // namespace

bool TextureStore::texelQuad(int file, int level, int x0, int x1, int y0, int y1, Vec4 out[4],
                             TilePin& pin) const {
    const File& f = m_files[std::size_t(file)];
    const LevelTiles& tiles = f.levels[std::size_t(level)];
    OIIO::ImageCache& cache = *m_impl->ts->imagecache();
    if (!pin.thread) pin.thread = cache.get_perthread_info();
    auto* handle = static_cast<OIIO::ImageCache::ImageHandle*>(f.imageHandle);
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
            pin.tile = cache.get_tile(handle, static_cast<OIIO::ImageCache::Perthread*>(pin.thread),
                                      0, level, x, y, 0);
            if (!pin.tile) {
                ok = false;
                break;
            }
            OIIO::TypeDesc format;
            pin.pixels = cache.tile_pixels(static_cast<OIIO::ImageCache::Tile*>(pin.tile), format);
            pin.format = int(format.basetype);
            pin.file = file, pin.level = level, pin.x = tx, pin.y = ty;
        }
        const std::size_t at =
            (std::size_t(y - ty) * std::size_t(tiles.tileWidth) + std::size_t(x - tx)) *
            std::size_t(channels);
        const OIIO::TypeDesc format{OIIO::TypeDesc::BASETYPE(pin.format)};
        float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int c = 0; c < n; ++c) v[c] = tileValue(pin.pixels, format, at + std::size_t(c));
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
    m_impl->ts->imagecache()->release_tile(static_cast<OIIO::ImageCache::Tile*>(pin.tile));
    pin.tile = nullptr;
}

bool TextureStore::readLevel(int file, int level, std::vector<float>& rgba) const {
    const File& f = m_files[std::size_t(file)];
    OIIO::TextureSystem& ts = *m_impl->ts;
    const LevelTiles& spec = f.levels[std::size_t(level)];
    const int n = std::min(f.info.channels, 4);
    const std::size_t texels = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<float> stored(texels * std::size_t(n));
    OIIO::TextureOpt opt;
    if (!ts.get_texels(static_cast<OIIO::TextureSystem::TextureHandle*>(f.handle),
                       ts.get_perthread_info(), opt, level, spec.x, spec.x + spec.width, spec.y,
                       spec.y + spec.height, 0, 1, 0, n, OIIO::TypeDesc::FLOAT, stored.data())) {
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
    OIIO::TextureSystem& ts = *m_impl->ts;
    OIIO::TextureSystem::Perthread* thread = ts.get_perthread_info();
    OIIO::TextureSystem::TextureHandle* handle =
        ts.get_texture_handle(OIIO::ustring(file.string()), thread);
    const OIIO::ImageSpec* spec = handle ? ts.imagespec(handle, thread) : nullptr;
    if (!spec || !ts.good(handle)) {
        const std::string reason = firstLine(ts.geterror());
        throw Error(ErrorKind::Format, "texture '" + file.string() + "' cannot be read: " + reason,
                    sceneFile.string(), where);
    }
    if (spec->width < 1 || spec->height < 1 || spec->nchannels < 1 || spec->depth != 1 ||
        spec->deep)
        throw Error(ErrorKind::Format,
                    "texture '" + file.string() + "' is not a flat 2D image with pixels",
                    sceneFile.string(), where);
    File f;
    f.path = file;
    f.handle = handle;
    f.info.width = spec->width;
    f.info.height = spec->height;
    f.info.channels = spec->nchannels;
    // The file's own layout, from its header (the TextureSystem shows its cache's tiles and MIP
    // levels for every file).
    if (auto in = OIIO::ImageInput::open(file.string())) {
        const OIIO::ImageSpec& header = in->spec();
        f.info.tiled = header.tile_width > 0;
        f.info.srgb = srgbEncodedFile(header.get_string_attribute("oiio:ColorSpace"),
                                      header.format == OIIO::TypeDesc::UINT8);
        f.info.mipmapped = in->seek_subimage(0, 1);
    }
    // Where each MIP level's texels lie in the cache's tiles, for texelQuad().
    OIIO::ImageCache& cache = *ts.imagecache();
    const OIIO::ustring name(file.string());
    f.imageHandle = cache.get_image_handle(name);
    while (const OIIO::ImageSpec* level = cache.imagespec(name, 0, int(f.levels.size()))) {
        LevelTiles tiles;
        tiles.x = level->x;
        tiles.y = level->y;
        tiles.width = level->width;
        tiles.height = level->height;
        tiles.tileWidth = level->tile_width > 0 ? level->tile_width : level->width;
        tiles.tileHeight = level->tile_height > 0 ? level->tile_height : level->height;
        f.levels.push_back(tiles);
    }
    (void)cache.geterror();  // asking one level past the last is not a failure
    f.info.fingerprint = spec->get_string_attribute("oiio:SHA-1");
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
    OIIO::TextureSystem& ts = *m_impl->ts;
    OIIO::TextureOpt opt;
    opt.swrap = oiioWrap(wrapS);
    opt.twrap = oiioWrap(wrapT);
    // Bilinear taps (not OIIO's default bicubic, which needs 16 texels a level): with a zero
    // footprint this is the bilinear lookup of the finest level.
    opt.interpmode = OIIO::TextureOpt::InterpBilinear;
    opt.fill = 1.0f;  // alpha where the file has none
    // OIIO's anisotropic filter with at most 8 samples along the footprint's long axis (its
    // default 32 costs 1.5-2x more at grazing angles for little visible difference).
    opt.anisotropic = 8;
    // Ask for what the file has (at most RGBA) and spread it out below.
    const int n = std::min(f.info.channels, 4);
    float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    const bool ok = ts.texture(static_cast<OIIO::TextureSystem::TextureHandle*>(f.handle),
                               ts.get_perthread_info(), opt, s, t, saneDerivative(footprint.dx.x),
                               saneDerivative(footprint.dx.y), saneDerivative(footprint.dy.x),
                               saneDerivative(footprint.dy.y), n, v);
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
    const std::string reason = firstLine(m_impl->ts->geterror());
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
    long long used = 0;
    m_impl->ts->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &used);
    return std::uint64_t(std::max(0LL, used));
}

}  // namespace glint::render::detail
