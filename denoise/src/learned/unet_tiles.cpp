// Tile planning of the U-Net filter, after OIDN's UNetFilter tiling: a tile's output pixels are
// at least the receptive-field half-width (the overlap) away from the tile's cut edges, and tiles
// start on the 2^4 = 16 pixel grid so that the four 2×2 pools see the same pixel groups as in one
// pass over the frame.
#include "learned/unet_tiles.h"

#include <algorithm>
#include <cmath>

namespace glint::denoise::learned {

namespace {

int alignDown16(int v) {
    return v >= 0 ? v / 16 * 16 : -((-v + 15) / 16 * 16);
}

// Output spans along one axis: [lo, hi) cut at the grid origin `start` every `stride` pixels.
struct Span {
    int in0, in1, out0, out1;
};

std::vector<Span> spans(int size, int lo, int hi, int overlap, int stride) {
    std::vector<Span> s;
    for (int o = alignDown16(lo); o < hi; o += stride) {
        const int out0 = std::max(o, lo), out1 = std::min(o + stride, hi);
        s.push_back(
            {std::max(alignDown16(out0 - overlap), 0), std::min(out1 + overlap, size), out0, out1});
    }
    return s;
}

}  // namespace

std::vector<UNetTile> planUNetTiles(const Rect& frame, const Rect& roi, int overlap,
                                    std::int64_t maxTilePixels) {
    const int w = frame.width(), h = frame.height();
    // One pass over the roi and its surroundings when it fits.
    const int wx0 = std::max(alignDown16(roi.x0 - overlap), 0), wx1 = std::min(roi.x1 + overlap, w);
    const int wy0 = std::max(alignDown16(roi.y0 - overlap), 0), wy1 = std::min(roi.y1 + overlap, h);
    if (std::int64_t(alignUp16(wx1 - wx0)) * alignUp16(wy1 - wy0) <= maxTilePixels)
        return {{Rect{wx0, wx1, wy0, wy1}, roi}};
    // Square tiles of side `side` whose outputs advance by side − 2 × overlap.
    const int side = std::max(alignDown16(int(std::sqrt(double(maxTilePixels)))), 2 * overlap + 16);
    const int stride = side - 2 * overlap;
    std::vector<UNetTile> tiles;
    for (const Span& y : spans(h, roi.y0, roi.y1, overlap, stride))
        for (const Span& x : spans(w, roi.x0, roi.x1, overlap, stride))
            tiles.push_back(
                {Rect{x.in0, x.in1, y.in0, y.in1}, Rect{x.out0, x.out1, y.out0, y.out1}});
    return tiles;
}

}  // namespace glint::denoise::learned
