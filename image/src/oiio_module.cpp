// The module of the image formats other than OpenEXR (other_formats.h): OpenImageIO's readers
// and writers behind OtherFormats, built as libglint_image_formats.so and loaded on first use.
// It links OpenImageIO and nothing of Glint's libraries: its errors go back as ModuleError.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <memory>

#include "glint/image/error.h"
#include "other_formats.h"

namespace glint::detail {

namespace {

std::string firstLineOf(const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? std::string("no reason given") : line;
}

ModuleError failure(ErrorKind kind, std::string message, std::string where) {
    return {int(kind), std::move(message), std::move(where)};
}

ModuleError read(const std::string& file, std::span<const unsigned char> bytes,
                 const std::string& extension, const SizeCheck& check, DecodedImage& out) {
    std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    OIIO::ImageInput::unique_ptr in;
    // Alpha as the file stores it: OpenImageIO would multiply the colour of a file of straight
    // alpha by it (in its encoded values), where glTF, Blender and Glint's PNG reader keep it.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (bytes.empty()) {
        in = OIIO::ImageInput::open(file, &config);
    } else {
        proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(bytes.data(), bytes.size());
        in = OIIO::ImageInput::open("embedded" + extension, &config, proxy.get());
    }
    if (!in)
        // Consumes the global error so that OpenImageIO does not print it at exit.
        return failure(ErrorKind::Format,
                       "not an image OpenImageIO can read (" + firstLineOf(OIIO::geterror()) + ")",
                       "open");
    const OIIO::ImageSpec spec = in->spec();
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0)
        return failure(ErrorKind::Format, "expected a flat 2D image with pixels", "header");
    check(spec.width, spec.height, spec.nchannels);
    out.width = spec.width;
    out.height = spec.height;
    out.channels = spec.nchannels;
    out.alphaChannel = spec.alpha_channel;
    out.colorSpace = spec.get_string_attribute("oiio:ColorSpace");
    out.eightBit = spec.format == OIIO::TypeDesc::UINT8;
    out.pixels.resize(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, out.pixels.data()))
        return failure(ErrorKind::Format,
                       "truncated or corrupt pixel data (" + firstLineOf(in->geterror()) + ")",
                       "pixels");
    in->close();
    return {};
}

ModuleError write8(const std::string& tmp, int width, int height,
                   const std::vector<std::string>& names, int alpha, const std::string& colorSpace,
                   const unsigned char* data) {
    OIIO::ImageSpec spec(width, height, int(names.size()), OIIO::TypeUInt8);
    spec.channelnames = names;
    spec.alpha_channel = alpha;
    // Glint's values are straight (its readers keep a file's alpha as stored): a format that
    // can say so (TIFF's extra sample) is told, so that no reader multiplies them again.
    if (alpha >= 0) spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!colorSpace.empty()) spec.attribute("oiio:ColorSpace", colorSpace);
    auto out = OIIO::ImageOutput::create(tmp);
    if (!out)
        return failure(
            ErrorKind::Io,
            "no OpenImageIO writer for this file type (" + firstLineOf(OIIO::geterror()) + ")",
            "write");
    if (!out->open(tmp, spec))
        return failure(ErrorKind::Io, "cannot create file (" + firstLineOf(out->geterror()) + ")",
                       "write");
    if (!out->write_image(OIIO::TypeUInt8, data)) {
        const std::string why = firstLineOf(out->geterror());
        out->close();
        return failure(ErrorKind::Io, "cannot write pixels (" + why + ")", "write");
    }
    if (!out->close())
        return failure(ErrorKind::Io, "cannot finish file (" + firstLineOf(out->geterror()) + ")",
                       "write");
    return {};
}

const OtherFormats kFormats{&read, &write8};

}  // namespace

}  // namespace glint::detail

extern "C" __attribute__((visibility("default"))) const glint::detail::OtherFormats*
glint_other_formats_2() {
    return &glint::detail::kFormats;
}
