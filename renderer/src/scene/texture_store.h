// The texture files of one scene, read through a tile cache (texture_cache.h: OpenImageIO's
// TextureSystem, in a module the first texture file loads): tiled and MIP-mapped files (.tx,
// tiled EXR) as they are, tile by tile on demand; untiled ones (PNG, JPEG, scanline EXR) with MIP
// levels made on first need. A cache of a set size holds the tiles in use, so textures larger
// than it still render. The store gives a file's MIP levels whole and texels of them from the
// tiles, which TextureLevels filters; the cache's own filter (lookup()) is the reference it is
// tested against. Each Scene owns its own store and cache, so scenes do not share or evict each
// other's tiles.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "scene/texture_cache.h"
#include "vecmath.h"

namespace glint::render::detail {

/// A lookup's footprint: the change of the texture coordinates (s, t) for one step of the ray
/// in x and in y (a pixel, scaled). Zero axes: no filtering beyond bilinear.
struct TexFootprint {
    Vec2 dx, dy;
};

/// What a texture file holds, from its header.
struct TextureFileInfo {
    int width = 0, height = 0, channels = 0;
    bool tiled = false;       ///< stored in tiles (read tile by tile), else in scanlines
    bool mipmapped = false;   ///< has MIP levels of its own
    bool srgb = false;        ///< colour values stored sRGB-encoded (8-bit PNG, JPEG)
    std::string fingerprint;  ///< the SHA-1 of the pixels that maketx writes, or empty
};

/// A filtered texture value as the renderer uses it: non-finite values 0, the rest clamped to
/// [0, kMaxRadiance]; the colour channels decoded from sRGB when `decodeSrgb` (after filtering,
/// as Cycles does for 8-bit sRGB images).
Vec4 usableTextureValue(Vec4 v, bool decodeSrgb);

/// The tile a lookup last read from the cache, held (pinned) between its texelQuad() calls so
/// that taps falling in one tile fetch it once; TextureStore::release() it when the lookup ends.
struct TilePin {
    void* tile = nullptr;                     ///< the cache's tile, or null
    void* thread = nullptr;                   ///< the cache's state of the calling thread
    const void* pixels = nullptr;             ///< the tile's texels
    TexelFormat format = TexelFormat::Float;  ///< how they are stored
    int otherFormat = 0;                      ///< the cache's code of TexelFormat::Other
    int file = -1, level = -1, x = 0, y = 0;  ///< the tile: file, MIP level, pixel origin
};
/// One scene's texture files and their tile cache (a cache of its own).
class TextureStore {
  public:
    /// The default tile cache size in MB (Settings::textureCacheMb).
    static constexpr int kDefaultCacheMb = 1024;

    explicit TextureStore(int cacheMb = kDefaultCacheMb);
    ~TextureStore();
    TextureStore(const TextureStore&) = delete;
    TextureStore& operator=(const TextureStore&) = delete;

    /// Sets the tile cache size in MB (tiles beyond it are evicted; lookups give the same values
    /// whatever the size).
    void setCacheMb(int megabytes);
    int cacheMb() const { return m_cacheMb; }

    /// Opens `file` (reading its header only) and returns its index for lookup(); the same file
    /// twice gives the same index. Throws glint::Error(Format) with the cache's reason when the
    /// file is not an image it reads, and glint::Error(Io) when the cache's module cannot be
    /// loaded (the first file loads it); `sceneFile` and `where` name the place that asked.
    int open(const std::filesystem::path& file, const std::filesystem::path& sceneFile,
             const std::string& where);
    /// A hash of the file's content for sceneContentHash: of its fingerprint when it has one,
    /// else of its bytes (read in pieces, so a large texture costs time, not memory).
    std::uint64_t contentHash(int file) const;
    const TextureFileInfo& info(int file) const { return m_files[std::size_t(file)].info; }
    const std::filesystem::path& path(int file) const { return m_files[std::size_t(file)].path; }

    /// The cache's own filter (OpenImageIO's anisotropic MIP filter), the reference Glint's
    /// (TextureLevels) is tested against: the RGBA value of `file` at (s, t) (origin at the
    /// image's top-left, texel centres at half-integers / size, as OIIO has them) filtered over
    /// `footprint`, wrapped by `wrapS` /
    /// `wrapT`: grey replicated, alpha 1 where the file has none, non-finite values 0 and the rest
    /// clamped to [0, kMaxRadiance]. `decodeSrgb` decodes the colour channels from sRGB after
    /// filtering. A file that fails to read gives 0 and is recorded (failure()).
    Vec4 lookup(int file, float s, float t, const TexFootprint& footprint, TextureWrap wrapS,
                TextureWrap wrapT, bool decodeSrgb) const;

    /// The sizes (width, height) of the file's MIP levels, finest first: the file's own, or for a
    /// file without them those the TextureSystem makes.
    std::vector<std::pair<int, int>> levelSizes(int file) const;
    /// The texels (x0, y0), (x1, y0), (x0, y1) and (x1, y1) of MIP level `level` of `file`
    /// (indices within the level), read from the tile cache into `out` as the file stores them:
    /// grey replicated, alpha 1 where the file has none. False, the texels 0 and the failure
    /// recorded, when a tile cannot be read. The tile read stays pinned in `pin` for the next
    /// call; release(pin) when done.
    bool texelQuad(int file, int level, int x0, int x1, int y0, int y1, Vec4 out[4],
                   TilePin& pin) const;
    /// Lets go of the tile `pin` holds (if any).
    void release(TilePin& pin) const;
    /// Reads MIP level `level` of `file` whole into `rgba` (RGBA floats, rows from the top; grey
    /// replicated, alpha 1 where the file has none). False, and the failure recorded, when the
    /// file cannot be read there.
    bool readLevel(int file, int level, std::vector<float>& rgba) const;
    /// Counts `bytes` of texels held in memory outside the tile cache (TextureLevels) against
    /// the cache size: the tile cache gets what is left of it, and never less than a quarter.
    void addResidentBytes(std::size_t bytes);
    /// The tile cache's size in MB: cacheMb() less the resident bytes, at least a quarter of it.
    float tileCacheMb() const;

    /// Forgets a recorded read failure (before a render).
    void clearFailure() const;
    /// Throws glint::Error(Io) naming the file and the cache's reason when a lookup since the last
    /// clearFailure() could not read its texture (a damaged or truncated tile).
    void throwIfFailed() const;
    /// Bytes of tiles the cache holds now.
    std::uint64_t cacheBytesUsed() const;

  private:
    struct File {
        std::filesystem::path path;
        TextureFileInfo info;
        void* handle = nullptr;       ///< the file in the cache's texture system
        void* imageHandle = nullptr;  ///< the file in the cache's image cache
        std::vector<CachedLevel> levels;
    };
    void recordFailure(int file) const;

    std::unique_ptr<TextureCache> m_cache;  ///< made by the first open()
    std::vector<File> m_files;
    int m_cacheMb = kDefaultCacheMb;
    std::size_t m_residentBytes = 0;
    mutable std::atomic<bool> m_failed{false};
    mutable std::mutex m_failureMutex;
    mutable std::string m_failure;
    mutable int m_failedFile = -1;
};

}  // namespace glint::render::detail
