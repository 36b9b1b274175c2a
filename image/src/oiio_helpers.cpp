#include "oiio_helpers.h"

#include <algorithm>
#include <cctype>
#include <system_error>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::detail {

std::string firstLine(const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? std::string("unknown OpenImageIO error") : line;
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

}  // namespace glint::detail

namespace glint {

void checkImageFile(const std::filesystem::path& path) {
    // libpng prints its own line for a damaged file: catch the damage first.
    // A truncated JPEG decodes without an error: catch that too.
    // OpenEXR allocates what a header attribute claims before it finds the file short.
    if (detail::isPng(path)) detail::checkPngStructure(path);
    if (detail::isJpeg(path)) detail::checkJpegStructure(path);
    if (detail::isExr(path)) detail::checkExrHeaders(path);
}

}  // namespace glint

namespace glint::detail {

OIIO::ImageInput::unique_ptr openImage(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status))
        throw Error(ErrorKind::Io, "file does not exist", file, "open");
    if (std::filesystem::is_directory(status))
        throw Error(ErrorKind::Io, "is a directory, expected an image file", file, "open");
    if (!std::filesystem::is_regular_file(status))
        throw Error(ErrorKind::Io,
                    "is not a regular file (a device or a pipe), expected an image file", file,
                    "open");

    checkImageFile(path);
    auto in = OIIO::ImageInput::open(file);
    if (!in) {
        // Consume the global error so OpenImageIO does not print it at exit.
        const std::string why = firstLine(OIIO::geterror());
        throw Error(ErrorKind::Format, "not an image OpenImageIO can read (" + why + ")", file,
                    "open");
    }
    return in;
}

namespace {
/// Creates and opens an output for `tmp`; errors name `shown`.
OIIO::ImageOutput::unique_ptr openOutput(const std::filesystem::path& tmp, const std::string& file,
                                         const OIIO::ImageSpec& spec) {
    auto out = OIIO::ImageOutput::create(tmp.string());
    if (!out)
        throw Error(
            ErrorKind::Io,
            "no OpenImageIO writer for this file type (" + firstLine(OIIO::geterror()) + ")", file,
            "write");
    if (!out->open(tmp.string(), spec))
        throw Error(ErrorKind::Io, "cannot create file (" + firstLine(out->geterror()) + ")", file,
                    "write");
    return out;
}

void closeOutput(OIIO::ImageOutput& out, const std::string& file) {
    if (!out.close())
        throw Error(ErrorKind::Io, "cannot finish file (" + firstLine(out.geterror()) + ")", file,
                    "write");
}
}  // namespace

void writeOiioStrips(const std::filesystem::path& tmp, const std::filesystem::path& shown,
                     const OIIO::ImageSpec& spec, int stripRows,
                     const std::function<void(int y0, int y1, float* strip)>& fill) {
    const std::string file = shown.string();
    auto out = openOutput(tmp, file, spec);
    std::vector<float> strip(std::size_t(stripRows) * spec.width * spec.nchannels);
    for (int y0 = 0; y0 < spec.height; y0 += stripRows) {
        const int y1 = std::min(spec.height, y0 + stripRows);
        fill(y0, y1, strip.data());
        if (!out->write_scanlines(y0, y1, 0, OIIO::TypeFloat, strip.data())) {
            const std::string why = firstLine(out->geterror());
            out->close();
            throw Error(ErrorKind::Io, "cannot write pixels (" + why + ")", file,
                        "row " + std::to_string(y0));
        }
    }
    closeOutput(*out, file);
}

void writeOiio(const std::filesystem::path& tmp, const std::filesystem::path& shown,
               const OIIO::ImageSpec& spec, OIIO::TypeDesc format, const void* data) {
    const std::string file = shown.string();
    auto out = openOutput(tmp, file, spec);
    if (!out->write_image(format, data)) {
        const std::string why = firstLine(out->geterror());
        out->close();
        throw Error(ErrorKind::Io, "cannot write pixels (" + why + ")", file, "write");
    }
    closeOutput(*out, file);
}

}  // namespace glint::detail
