// Images held in memory (a glTF asset's embedded PNG or JPEG), read through OpenImageIO's
// memory proxy with the same structural checks and linearisation as files.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "oiio_helpers.h"

namespace glint {

Image readImage(std::span<const unsigned char> bytes, const std::string& name, bool linearize) {
    // The format comes from the bytes (an embedded image has no extension to go by).
    const char* extension = nullptr;
    if (detail::isPng(bytes)) {
        detail::checkPngStructure(bytes, name);
        extension = ".png";
    } else if (detail::isJpeg(bytes)) {
        detail::checkJpegStructure(bytes, name);
        extension = ".jpg";
    } else {
        throw Error(ErrorKind::Format, "embedded image is neither PNG nor JPEG", name, "byte 0");
    }
    OIIO::Filesystem::IOMemReader proxy(bytes.data(), bytes.size());
    auto in = OIIO::ImageInput::open(std::string("embedded") + extension, nullptr, &proxy);
    if (!in)
        throw Error(
            ErrorKind::Format,
            "not an image OpenImageIO can read (" + detail::firstLine(OIIO::geterror()) + ")", name,
            "open");
    const OIIO::ImageSpec spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0 ||
        spec.nchannels > 4)
        throw Error(ErrorKind::Format, "expected a 2D image of 1 to 4 channels", name, "header");
    // A header may claim any size: the same bound as for files (65536 per side, 2^28 pixels,
    // and no more samples than about 2048 per byte).
    const long long pixels = (long long)spec.width * spec.height;
    if (spec.width > 65536 || spec.height > 65536 || pixels > (1LL << 28) ||
        pixels * spec.nchannels / 2048 > (long long)bytes.size())
        throw Error(ErrorKind::Format,
                    "header claims " + std::to_string(spec.width) + "x" +
                        std::to_string(spec.height) + " pixels, more than " +
                        std::to_string(bytes.size()) + " bytes can hold",
                    name, "header");
    Image image(spec.width, spec.height, spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, image.data().data()))
        throw Error(ErrorKind::Format,
                    "truncated or corrupt pixel data (" + detail::firstLine(in->geterror()) + ")",
                    name, "pixels");
    in->close();
    const std::string space = spec.get_string_attribute("oiio:ColorSpace");
    if (linearize && OIIO::Strutil::iequals(space, "sRGB")) {
        float* data = image.data().data();
        for (std::size_t i = 0; i < image.pixelCount(); ++i)
            for (int c = 0; c < spec.nchannels; ++c)
                if (c != spec.alpha_channel)
                    data[i * spec.nchannels + c] = srgbDecode(data[i * spec.nchannels + c]);
    }
    return image;
}

}  // namespace glint
