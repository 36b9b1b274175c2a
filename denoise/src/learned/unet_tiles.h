// Tiles of the U-Net filter: output rectangles covering a region, each with the input window
// (its overlap) the network reads for it.
#pragma once

#include <cstdint>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::learned {

/// One tile: the network runs on `in` (padded with zeros to a multiple of 16) and keeps `out`.
struct UNetTile {
    Rect in;
    Rect out;
};

/// Tiles covering `roi` of a `frame`-sized image. Input windows start on the 16-pixel grid of the
/// frame and reach at least `overlap` pixels past their output (clipped to the frame), so that a
/// tile's output equals a single pass over the frame. One tile when the window around the whole
/// roi holds at most `maxTilePixels` (after padding); else square tiles of the largest aligned
/// side that fits (at least 2 × overlap + 16).
std::vector<UNetTile> planUNetTiles(const Rect& frame, const Rect& roi, int overlap,
                                    std::int64_t maxTilePixels);

/// `v` rounded up to a multiple of 16.
inline int alignUp16(int v) {
    return (v + 15) / 16 * 16;
}

}  // namespace glint::denoise::learned
