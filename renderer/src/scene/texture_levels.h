// A file texture's coarse MIP levels held in memory: the file's own levels of at most
// kResidentTextureSize texels a side, as half floats (RGBA). A lookup whose footprint spans a
// texel of them or more (far surfaces, the view of a large texture on a small film, every hit
// after a diffuse or glossy bounce) is filtered here, without a TextureSystem call; finer ones
// go to the TextureStore's tile cache (docs/assets.md, "Textures").
#pragma once

#include <cstddef>
#include <vector>

#include <Imath/half.h>

#include "scene/texture_store.h"
#include "vecmath.h"

namespace glint::render::detail {

/// The side of the finest MIP level a file texture keeps in memory, at most: 512² half RGBA
/// with its coarser levels is 2.8 MB.
inline constexpr int kResidentTextureSize = 512;

/// The resident MIP levels of one texture file, finest first.
class ResidentLevels {
  public:
    /// Reads from `store` the MIP levels of `file` of at most kResidentTextureSize texels a side
    /// (every level of a smaller file). Empty when the store cannot read them (the failure is
    /// recorded in the store: throwIfFailed()).
    static ResidentLevels read(const TextureStore& store, int file);

    bool empty() const { return m_levels.empty(); }
    /// Bytes of texels held.
    std::size_t bytes() const;

    /// True when a lookup over `footprint` (in OIIO's s, t) is filtered here: its filter width
    /// spans a texel of the finest resident level or more. A zero footprint never is.
    bool covers(const TexFootprint& footprint) const;
    /// The value at (s, t) (OIIO's orientation: t runs down from the top) filtered over
    /// `footprint`: trilinear between the two levels the filter width falls between, at up to
    /// 8 taps along the footprint's long axis (as OIIO's anisotropic filter). Values as the
    /// file stores them (not decoded from sRGB, not clamped).
    Vec4 lookup(float s, float t, const TexFootprint& footprint, TextureWrap wrapS,
                TextureWrap wrapT) const;
    /// The mean over the whole texture: the coarsest level's mean.
    Vec4 mean() const;

  private:
    struct Level {
        int width = 0, height = 0;
        std::vector<Imath::half> texels;  ///< RGBA, rows from the top
    };
    Vec4 bilinear(const Level& level, float s, float t, TextureWrap wrapS, TextureWrap wrapT) const;

    std::vector<Level> m_levels;
};

}  // namespace glint::render::detail
