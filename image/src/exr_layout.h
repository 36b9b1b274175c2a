// Private to image/: the pixel layout of a layered EXR over all the shapes OpenEXR files take —
// scanline or tiled, one part or several (OpenImageIO shows each part as a subimage), with or
// without mip levels (level 0 is the full-resolution image) — and reading rows of every channel
// from it (docs/image.md, "The layered EXR").
#pragma once

#include <OpenImageIO/imageio.h>

#include <string>
#include <vector>

namespace glint::detail {

/// One part of the file: its subimage, where its channels start in ExrLayout::channelNames, and
/// its tile height (0 for scanlines).
struct ExrPart {
    int subimage = 0;
    int firstChannel = 0;
    int channels = 0;
    int tileHeight = 0;
};

/// Every channel of every part of a flat EXR of one data window.
struct ExrLayout {
    OIIO::ImageSpec spec;  ///< part 0, level 0: the data window and the attributes
    std::vector<std::string> channelNames;
    std::vector<ExrPart> parts;

    int width() const { return spec.width; }
    int height() const { return spec.height; }
    int channels() const { return int(channelNames.size()); }
    /// Rows per strip for readExrRows: a multiple of every part's tile height, about 32.
    int stripRows() const;
};

/// The layout of the open file `in`. A bare channel name ("X") of a part after the first is
/// named "PART.X" (PART: the part's name), so that each part can name its layer. Throws
/// glint::Error(Format) naming `file` and the part for a deep part, a part whose data window
/// differs from part 0's, or a channel name two parts still share.
ExrLayout readExrLayout(OIIO::ImageInput& in, const std::string& file);

/// Reads rows [y0, y1) (relative to the data window) of every channel of `layout` as float
/// into `strip`, interleaved in channelNames order (width × channels values per row). y0 is a
/// multiple of layout.stripRows(), y1 that or the last row. Throws glint::Error(Format) naming
/// `file` and the rows for truncated or corrupt data.
void readExrRows(OIIO::ImageInput& in, const ExrLayout& layout, int y0, int y1, float* strip,
                 const std::string& file);

}  // namespace glint::detail
