// Images held in memory (a glTF asset's embedded PNG or JPEG), read as files of the same format
// are (other_formats.h), with the same structural checks and linearisation.
#include "direct_formats.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "other_formats.h"

namespace glint {

Image readImage(std::span<const unsigned char> bytes, const std::string& name, bool linearize) {
    // The format comes from the bytes (an embedded image has no extension to go by).
    const detail::DirectFormat* format = detail::directFormatOf(bytes);
    if (!format)
        throw Error(ErrorKind::Format,
                    "embedded image is in none of the formats glTF allows (PNG, JPEG)", name,
                    "byte 0");
    return detail::readOtherFormat(
        name, bytes, format->extension, linearize, [&](int width, int height, int channels) {
            if (channels > 4)
                throw Error(ErrorKind::Format, "expected a 2D image of 1 to 4 channels", name,
                            "header");
            // A header may claim any size: the same bound as for files (65536 per side, 2^28
            // pixels, and no more samples than about 2048 per byte).
            const long long pixels = (long long)width * height;
            if (width > 65536 || height > 65536 || pixels > (1LL << 28) ||
                pixels * channels / 2048 > (long long)bytes.size())
                throw Error(ErrorKind::Format,
                            "header claims " + std::to_string(width) + "x" +
                                std::to_string(height) + " pixels, more than " +
                                std::to_string(bytes.size()) + " bytes can hold",
                            name, "header");
        });
}

}  // namespace glint
