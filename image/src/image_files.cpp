#include "image_files.h"

#include <algorithm>
#include <cctype>
#include <system_error>

#include "direct_formats.h"
#include "exr_layout.h"
#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::detail {

std::string firstLine(const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));
    return line.empty() ? std::string("no reason given") : line;
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

void checkRegularFile(const std::filesystem::path& path) {
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

std::optional<bool> storedInTiles(const std::filesystem::path& path) {
    detail::checkRegularFile(path);
    if (detail::isExr(path)) {
        checkImageFile(path);
        return detail::ExrInput(path).layout().parts.front().tileWidth > 0;
    }
    if (detail::directFormatOf(detail::fileHead(path, 16))) return false;
    return std::nullopt;
}

}  // namespace glint
