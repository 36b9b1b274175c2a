// Glint's filter over a tiled texture's MIP levels. The levels of at most kResidentTextureSize
// texels a side are read once into memory (half-float RGBA); finer ones are read texel by texel
// from the TextureStore's tile cache (OpenImageIO's ImageCache). A lookup is filtered over its
// footprint: trilinear between the two levels the filter width falls between, at up to 8 taps
// along the footprint's long axis, as OIIO's anisotropic filter does, at a third of its cost;
// a render's lookups read one of the two levels, picked at random by its weight (docs/assets.md,
// "Textures").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "scene/texture_store.h"
#include "vecmath.h"

namespace glint::render::detail {

/// The side of the finest MIP level a file texture keeps in memory, at most: 512² half RGBA
/// with its coarser levels is 2.8 MB.
inline constexpr int kResidentTextureSize = 512;

/// One texture file's MIP levels: the sizes of all, the texels of the resident ones.
class TextureLevels {
  public:
    /// The levels of `file` in `store`, reading the resident ones. Empty when the store cannot
    /// read them (the failure is recorded in the store: throwIfFailed()).
    static TextureLevels read(const TextureStore& store, int file);

    bool empty() const { return m_levels.empty(); }
    /// Bytes of texels held in memory.
    std::size_t residentBytes() const;

    /// True when a lookup over `footprint` reads only resident levels (no tile): its filter
    /// width spans a texel of the finest resident level or more.
    bool resident(const TexFootprint& footprint) const;
    /// The value at (s, t) (OIIO's orientation: t runs down from the top; any floats, wrapped by
    /// wrapS and wrapT, non-finite ones taken as 0) filtered over
    /// `footprint` (zero: bilinear at the finest level), with texels of the levels not resident
    /// read from `store` (file `file`, the one read()). Values as the file stores them (not
    /// decoded from sRGB, not clamped); 0 where a tile cannot be read (recorded in the store).
    Vec4 lookup(const TextureStore& store, int file, float s, float t,
                const TexFootprint& footprint, TextureWrap wrapS, TextureWrap wrapT) const;
    /// lookup()'s filter at one of the two MIP levels it blends, the coarser when `u` (in
    /// [0, 1)) is below its weight, so that the mean over uniform u is lookup()'s value
    /// (stochastic trilinear filtering: Pharr et al. 2024, "Filtering After Shading with
    /// Stochastic Texture Filtering"). Half the bilinear lookups of lookup(), and tiles read only
    /// as often as their level's weight.
    Vec4 lookupOneLevel(const TextureStore& store, int file, float s, float t,
                        const TexFootprint& footprint, TextureWrap wrapS, TextureWrap wrapT,
                        float u) const;
    /// The mean over the whole texture: the coarsest level's mean.
    Vec4 mean() const;

  private:
    struct Level {
        int width = 0, height = 0;
        std::vector<std::uint16_t> texels;  ///< half RGBA, rows from the top; empty: in tiles
    };
    /// The taps of a footprint's filter and the two levels each blends.
    struct Filter {
        Vec2 major;          ///< the taps lie along it, spaced by major / taps
        int taps = 1;        ///< lookups spaced along `major`
        int fine = 0;        ///< the finer level of each tap
        int coarse = 0;      ///< the coarser one (fine when there is no blend)
        float blend = 0.0f;  ///< the coarser level's weight
    };
    /// The filter of `footprint`: its taps and the two levels it blends.
    Filter filterFor(const TexFootprint& footprint) const;
    /// The mean of the filter's taps at one level; tiles read are left in `pin`.
    Vec4 taps(const TextureStore& store, int file, const Filter& f, int level, float s, float t,
              TextureWrap wrapS, TextureWrap wrapT, TilePin& pin) const;
    Vec4 bilinear(const TextureStore& store, int file, int level, float s, float t,
                  TextureWrap wrapS, TextureWrap wrapT, TilePin& pin) const;

    std::vector<Level> m_levels;  ///< finest first
    int m_firstResident = 0;      ///< the finest level held in memory
};

}  // namespace glint::render::detail
