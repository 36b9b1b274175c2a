// The module of the renderer's texture cache (texture_cache.h): OpenImageIO's TextureSystem and
// its ImageCache behind TextureCache, built as libglint_textures.so and loaded by the first
// texture file a scene opens. It links OpenImageIO and nothing of Glint's libraries.
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <mutex>

#include "scene/texture_cache.h"

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

/// TextureSystems no cache uses, for the next cache to take. OIIO 2.4's TextureSystem::destroy
/// deletes its object through a type of the wrong size (AddressSanitizer's
/// new-delete-type-mismatch, inside libOpenImageIO), so a cache gives its TextureSystem back
/// here, emptied, instead of destroying it: a process holds as many as it ever had scenes with
/// texture files alive at once. Held through a pointer that is never freed, so that they stay
/// reachable (not leaks) to the end.
struct TextureSystemPool {
    std::mutex mutex;
    std::vector<OIIO::TextureSystem*> idle;
};
TextureSystemPool& pool() {
    static auto* const instance = new TextureSystemPool;
    return *instance;
}

class OiioTextureCache final : public TextureCache {
  public:
    OiioTextureCache() {
        // A private TextureSystem with a private ImageCache (shared = false): no other scene's
        // tiles in it. One an earlier cache gave back (emptied) is taken first.
        {
            TextureSystemPool& idle = pool();
            const std::lock_guard lock(idle.mutex);
            if (!idle.idle.empty()) {
                m_ts = idle.idle.back();
                idle.idle.pop_back();
            }
        }
        if (!m_ts) m_ts = OIIO::TextureSystem::create(false);
        // Untiled files (PNG, JPEG, scanline EXR) are cached in 64² tiles and get MIP levels
        // made on first need, so that they too are filtered by footprint.
        m_ts->attribute("autotile", 64);
        m_ts->attribute("automip", 1);
        // Only the calling renderer reports errors; OIIO's own log lines would repeat them.
        m_ts->attribute("max_errors_per_file", 1);
    }

    ~OiioTextureCache() override {
        // Its tiles and open files go now; the object goes back to the pool (see pool()).
        m_ts->invalidate_all(true);
        TextureSystemPool& idle = pool();
        const std::lock_guard lock(idle.mutex);
        idle.idle.push_back(m_ts);
    }

    void setMaxMemoryMb(float megabytes) override { m_ts->attribute("max_memory_MB", megabytes); }

    std::string open(const std::string& file, CachedFile& out) override {
        OIIO::TextureSystem::Perthread* thread = m_ts->get_perthread_info();
        OIIO::TextureSystem::TextureHandle* handle =
            m_ts->get_texture_handle(OIIO::ustring(file), thread);
        const OIIO::ImageSpec* spec = handle ? m_ts->imagespec(handle, thread) : nullptr;
        if (!spec || !m_ts->good(handle)) return "cannot be read: " + error();
        if (spec->width < 1 || spec->height < 1 || spec->nchannels < 1 || spec->depth != 1 ||
            spec->deep)
            return "is not a flat 2D image with pixels";
        out.handle = handle;
        out.width = spec->width;
        out.height = spec->height;
        out.channels = spec->nchannels;
        out.fingerprint = spec->get_string_attribute("oiio:SHA-1");
        // The file's own layout, from its header (the TextureSystem shows its cache's tiles and
        // MIP levels for every file).
        if (auto in = OIIO::ImageInput::open(file)) {
            const OIIO::ImageSpec& header = in->spec();
            out.tiled = header.tile_width > 0;
            out.colorSpace = header.get_string_attribute("oiio:ColorSpace");
            out.eightBit = header.format == OIIO::TypeDesc::UINT8;
            out.mipmapped = in->seek_subimage(0, 1);
        }
        // Where each MIP level's texels lie in the cache's tiles.
        OIIO::ImageCache& cache = *m_ts->imagecache();
        const OIIO::ustring name(file);
        out.imageHandle = cache.get_image_handle(name);
        while (const OIIO::ImageSpec* level = cache.imagespec(name, 0, int(out.levels.size()))) {
            CachedLevel tiles;
            tiles.x = level->x;
            tiles.y = level->y;
            tiles.width = level->width;
            tiles.height = level->height;
            tiles.tileWidth = level->tile_width > 0 ? level->tile_width : level->width;
            tiles.tileHeight = level->tile_height > 0 ? level->tile_height : level->height;
            out.levels.push_back(tiles);
        }
        (void)cache.geterror();  // asking one level past the last is not a failure
        return {};
    }

    void* perThread() override { return m_ts->imagecache()->get_perthread_info(); }

    bool tile(void* imageHandle, void* perThread, int level, int x, int y,
              CachedTile& out) override {
        OIIO::ImageCache& cache = *m_ts->imagecache();
        auto* tile =
            cache.get_tile(static_cast<OIIO::ImageCache::ImageHandle*>(imageHandle),
                           static_cast<OIIO::ImageCache::Perthread*>(perThread), 0, level, x, y, 0);
        if (!tile) return false;
        OIIO::TypeDesc format;
        out.tile = tile;
        out.pixels = cache.tile_pixels(tile, format);
        out.otherFormat = int(format.basetype);
        switch (format.basetype) {
            case OIIO::TypeDesc::HALF:
                out.format = TexelFormat::Half;
                break;
            case OIIO::TypeDesc::FLOAT:
                out.format = TexelFormat::Float;
                break;
            case OIIO::TypeDesc::UINT8:
                out.format = TexelFormat::UInt8;
                break;
            case OIIO::TypeDesc::UINT16:
                out.format = TexelFormat::UInt16;
                break;
            default:
                out.format = TexelFormat::Other;
        }
        return true;
    }

    void release(void* tile) override {
        m_ts->imagecache()->release_tile(static_cast<OIIO::ImageCache::Tile*>(tile));
    }

    float otherTexel(const void* pixels, int otherFormat, std::size_t i) const override {
        // OIIO's normalisation: integer formats to 0 … 1.
        const OIIO::TypeDesc format{OIIO::TypeDesc::BASETYPE(otherFormat)};
        float v = 0.0f;
        const char* bytes = static_cast<const char*>(pixels) + i * format.size();
        OIIO::convert_pixel_values(format, bytes, OIIO::TypeDesc::FLOAT, &v, 1);
        return v;
    }

    bool texels(void* handle, int level, int x0, int x1, int y0, int y1, int channels,
                float* out) override {
        OIIO::TextureOpt opt;
        return m_ts->get_texels(static_cast<OIIO::TextureSystem::TextureHandle*>(handle),
                                m_ts->get_perthread_info(), opt, level, x0, x1, y0, y1, 0, 1, 0,
                                channels, OIIO::TypeDesc::FLOAT, out);
    }

    bool filter(void* handle, float s, float t, float dsdx, float dtdx, float dsdy, float dtdy,
                TextureWrap wrapS, TextureWrap wrapT, int channels, float* out) override {
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
        return m_ts->texture(static_cast<OIIO::TextureSystem::TextureHandle*>(handle),
                             m_ts->get_perthread_info(), opt, s, t, dsdx, dtdx, dsdy, dtdy,
                             channels, out);
    }

    std::string error() override { return firstLine(m_ts->geterror()); }

    std::uint64_t bytesUsed() const override {
        long long used = 0;
        m_ts->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &used);
        return std::uint64_t(std::max(0LL, used));
    }

  private:
    OIIO::TextureSystem* m_ts = nullptr;
};

}  // namespace

}  // namespace glint::render::detail

extern "C" __attribute__((visibility("default"))) glint::render::detail::TextureCache*
glint_texture_cache_1() {
    return new glint::render::detail::OiioTextureCache;
}
