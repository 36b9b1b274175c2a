// Private to the renderer: the tile cache behind a scene's TextureStore (texture_store.h) —
// OpenImageIO's TextureSystem with its ImageCache, in a module of its own
// (oiio_texture_cache.cpp, the shared object libglint_textures.so, found as
// glint/image/internal/modules.h says; the environment variable GLINT_TEXTURES_MODULE names it).
// The first texture file a scene opens loads it, so that rendering a scene without texture files
// never loads OpenImageIO's some 260 libraries (docs/research/start-and-writing.md). Nothing here
// is an OpenImageIO type: handles are opaque, errors are text.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace glint::render::detail {

/// How texture coordinates outside [0, 1] wrap (glTF sampler wrapS/wrapT).
enum class TextureWrap { Repeat, Clamp, Mirror };

/// How a cached tile stores its texels. Integer formats read as 0 … 1; Other: convert each with
/// TextureCache::otherTexel.
enum class TexelFormat { Half, Float, UInt8, UInt16, Other };

/// Where a MIP level's texels lie in the cache's tiles.
struct CachedLevel {
    int x = 0, y = 0;                   ///< the level's pixel origin (data window)
    int width = 0, height = 0;          ///< the level's size
    int tileWidth = 1, tileHeight = 1;  ///< the cache's tile size for the level
};

/// What TextureCache::open learns of a file.
struct CachedFile {
    void* handle = nullptr;       ///< the file in the texture system (filtered lookups, texels)
    void* imageHandle = nullptr;  ///< the file in the image cache (tiles)
    int width = 0, height = 0, channels = 0;
    bool tiled = false;               ///< stored in tiles, else in scanlines
    bool mipmapped = false;           ///< has MIP levels of its own
    std::string colorSpace;           ///< as the file declares it ("sRGB", "Linear"), or empty
    bool eightBit = false;            ///< its samples are 8-bit
    std::string fingerprint;          ///< the SHA-1 of its pixels that maketx writes, or empty
    std::vector<CachedLevel> levels;  ///< finest first: the file's own, or those the cache makes
};

/// A tile held by the cache until TextureCache::release.
struct CachedTile {
    void* tile = nullptr;
    const void* pixels = nullptr;
    TexelFormat format = TexelFormat::Float;
    int otherFormat = 0;  ///< the cache's own code for TexelFormat::Other
};

/// One scene's tile cache. Lookups may come from any thread; open() and setMaxMemoryMb() from one.
class TextureCache {
  public:
    virtual ~TextureCache() = default;

    /// The most memory its tiles may hold; beyond it they are evicted.
    virtual void setMaxMemoryMb(float megabytes) = 0;
    /// Opens `file` (its header only). Empty, or what is wrong with it, to follow the file's
    /// name: "cannot be read: REASON", "is not a flat 2D image with pixels".
    virtual std::string open(const std::string& file, CachedFile& out) = 0;
    /// The calling thread's state in the cache, for tile().
    virtual void* perThread() = 0;
    /// Holds the tile of MIP level `level` of the file holding the pixel (x, y) (in the level's
    /// data window). False, the reason in error(), when it cannot be read.
    virtual bool tile(void* imageHandle, void* perThread, int level, int x, int y,
                      CachedTile& out) = 0;
    virtual void release(void* tile) = 0;
    /// Texel value `i` of pixels in the format TexelFormat::Other code `otherFormat` gives.
    virtual float otherTexel(const void* pixels, int otherFormat, std::size_t i) const = 0;
    /// The first `channels` channels of the texels [x0, x1) × [y0, y1) of MIP level `level`, as
    /// float into `out`. False, the reason in error(), when they cannot be read.
    virtual bool texels(void* handle, int level, int x0, int x1, int y0, int y1, int channels,
                        float* out) = 0;
    /// The cache's own anisotropic MIP filter with bilinear taps: the first `channels` channels
    /// at (s, t), origin top-left, over the footprint (dsdx, dtdx), (dsdy, dtdy), into `out`
    /// (left as they are where the file has no channel). False, the reason in error(), when the
    /// file cannot be read there.
    virtual bool filter(void* handle, float s, float t, float dsdx, float dtdx, float dsdy,
                        float dtdy, TextureWrap wrapS, TextureWrap wrapT, int channels,
                        float* out) = 0;
    /// The first line of the last error met, and forgets it ("unknown error" when none).
    virtual std::string error() = 0;
    /// Bytes of tiles held now.
    virtual std::uint64_t bytesUsed() const = 0;
};

/// The module's entry point, an extern "C" function returning a new TextureCache (deleted by its
/// owner); the version in the name changes with the interface.
inline constexpr const char* kTextureCacheEntry = "glint_texture_cache_1";

}  // namespace glint::render::detail
