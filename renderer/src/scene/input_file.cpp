#include "scene/input_file.h"

#include "glint/image/error.h"

namespace glint::render::detail {

InputKind inputKind(const std::filesystem::path& path) {
    std::error_code ec;  // odd paths (too long...) are reported as missing, not thrown
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(status)) return InputKind::Missing;
    if (std::filesystem::is_directory(status)) return InputKind::Folder;
    if (!std::filesystem::is_regular_file(status)) return InputKind::Special;
    return InputKind::Regular;
}

std::string notARegularFile(InputKind kind, const std::string& expected) {
    switch (kind) {
        case InputKind::Folder:
            return "is a folder, expected " + expected;
        case InputKind::Special:
            return "is not a regular file (a device or a pipe), expected " + expected;
        default:
            return {};
    }
}

void requireRegularFile(const std::filesystem::path& path, const std::string& what,
                        const std::string& expected, const std::string& file,
                        const std::string& where) {
    const InputKind kind = inputKind(path);
    if (kind == InputKind::Regular) return;
    if (kind == InputKind::Missing)
        throw Error(ErrorKind::Io, what + " file '" + path.string() + "' not found", file, where);
    throw Error(ErrorKind::Io, what + " '" + path.string() + "' " + notARegularFile(kind, expected),
                file, where);
}

}  // namespace glint::render::detail
