#include "image_files.h"

#include <algorithm>
#include <cctype>
#include <fstream>
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

std::vector<unsigned char> fileHead(const std::filesystem::path& path, std::size_t limit) {
    std::ifstream in(path, std::ios::binary);
    std::vector<unsigned char> bytes(limit);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(limit));
    bytes.resize(std::size_t(std::max<std::streamsize>(in.gcount(), 0)));
    return bytes;
}

std::vector<unsigned char> fileBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw Error(ErrorKind::Io, "cannot open file for reading", path.string(), "open");
    const std::streamoff size = in.tellg();
    std::vector<unsigned char> bytes(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
    if (in.gcount() != std::streamsize(bytes.size()))
        throw Error(ErrorKind::Io, "cannot read the whole file", path.string(),
                    "byte " + std::to_string(in.gcount()));
    return bytes;
}

}  // namespace glint::detail

namespace glint {

void checkImageFile(const std::filesystem::path& path) {
    // OpenEXR allocates what a header attribute claims before it finds the file short; the
    // formats read directly check their own structure (direct_formats.h).
    if (detail::isExr(path))
        detail::checkExrHeaders(path);
    else if (const detail::DirectFormat* format = detail::directFormatOf(path))
        format->checkStructure(detail::fileBytes(path), path.string());
}

std::optional<bool> storedInTiles(const std::filesystem::path& path) {
    detail::checkRegularFile(path);
    if (detail::isExr(path)) {
        checkImageFile(path);
        return detail::ExrInput(path).layout().parts.front().tileWidth > 0;
    }
    if (detail::directFormatOf(path)) return false;
    return std::nullopt;
}

}  // namespace glint
