#include "exr_layout.h"

#include <algorithm>
#include <numeric>
#include <set>

#include "glint/image/error.h"
#include "oiio_helpers.h"

namespace glint::detail {

namespace {

std::string partName(const OIIO::ImageSpec& spec, int subimage) {
    const std::string name = spec.get_string_attribute("oiio:subimagename");
    return "part " + std::to_string(subimage) + (name.empty() ? "" : " ('" + name + "')");
}

}  // namespace

int ExrLayout::stripRows() const {
    int rows = 32;
    for (const ExrPart& p : parts)
        if (p.tileHeight > 0) rows = std::lcm(rows, p.tileHeight);
    // Tile heights are small powers of two in practice (16, 32, 64): the strip stays small.
    return rows;
}

ExrLayout readExrLayout(OIIO::ImageInput& in, const std::string& file) {
    ExrLayout layout;
    layout.spec = in.spec(0, 0);
    std::set<std::string> used;
    for (int s = 0; in.seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec spec = in.spec(s, 0);
        if (spec.deep)
            throw Error(ErrorKind::Format,
                        "deep EXR data is not supported (expected flat pixels, one value per "
                        "channel)",
                        file, partName(spec, s));
        if (spec.x != layout.spec.x || spec.y != layout.spec.y || spec.z != layout.spec.z ||
            spec.width != layout.spec.width || spec.height != layout.spec.height ||
            spec.depth != layout.spec.depth)
            throw Error(
                ErrorKind::Format,
                "data window " + std::to_string(spec.width) + "x" + std::to_string(spec.height) +
                    " at (" + std::to_string(spec.x) + ", " + std::to_string(spec.y) +
                    "); expected part 0's " + std::to_string(layout.spec.width) + "x" +
                    std::to_string(layout.spec.height) + " at (" + std::to_string(layout.spec.x) +
                    ", " + std::to_string(layout.spec.y) + ")",
                file, partName(spec, s));
        ExrPart part{s, layout.channels(), spec.nchannels,
                     spec.tile_width > 0 ? spec.tile_height : 0};
        const std::string prefix = spec.get_string_attribute("oiio:subimagename");
        for (const std::string& name : spec.channelnames) {
            std::string full = name;
            // A bare name ("R", "X") in a later part takes its part's name as its layer, as
            // writers that name each part after its layer expect.
            if (s > 0 && !prefix.empty() && name.find('.') == std::string::npos)
                full = prefix + "." + name;
            if (!used.insert(full).second)
                throw Error(ErrorKind::Format,
                            "channel '" + full +
                                "' is also in an earlier part; expected each "
                                "channel once",
                            file, partName(spec, s));
            layout.channelNames.push_back(full);
        }
        layout.parts.push_back(part);
    }
    return layout;
}

void readExrRows(OIIO::ImageInput& in, const ExrLayout& layout, int y0, int y1, float* strip,
                 const std::string& file) {
    const OIIO::ImageSpec& spec = layout.spec;
    const int w = spec.width, n = layout.channels();
    const bool onePart = layout.parts.size() == 1;
    std::vector<float> part;
    for (const ExrPart& p : layout.parts) {
        // One part reads straight into the strip; several read each part, then interleave.
        float* dst = strip;
        if (!onePart) {
            part.resize(std::size_t(y1 - y0) * w * p.channels);
            dst = part.data();
        }
        const bool ok =
            p.tileHeight > 0
                ? in.read_tiles(p.subimage, 0, spec.x, spec.x + w, spec.y + y0, spec.y + y1, spec.z,
                                spec.z + 1, 0, p.channels, OIIO::TypeFloat, dst)
                : in.read_scanlines(p.subimage, 0, spec.y + y0, spec.y + y1, spec.z, 0, p.channels,
                                    OIIO::TypeFloat, dst);
        if (!ok)
            throw Error(ErrorKind::Format,
                        "truncated or corrupt pixel data (" + firstLine(in.geterror()) + ")", file,
                        "rows " + std::to_string(y0) + "-" + std::to_string(y1 - 1) +
                            (onePart ? "" : " of part " + std::to_string(p.subimage)));
        if (onePart) return;
        const std::size_t pixels = std::size_t(y1 - y0) * w;
        for (std::size_t i = 0; i < pixels; ++i)
            std::copy_n(part.data() + i * p.channels, p.channels, strip + i * n + p.firstChannel);
    }
}

}  // namespace glint::detail
