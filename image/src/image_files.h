// Private to image/: what Glint checks of an image file before a library reads it — that it is a
// regular file, its format's signature, the structure of EXR files (that of PNG and JPEG files
// is their readers', direct_formats.h) — and small helpers of the image readers and writers.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace glint::detail {

/// Throws glint::Error(Io) naming `path` when it does not exist, is a directory, or is not a
/// regular file (a device or a pipe).
void checkRegularFile(const std::filesystem::path& path);

/// The first `limit` bytes of the file (fewer when it is shorter or cannot be read).
std::vector<unsigned char> fileHead(const std::filesystem::path& path, std::size_t limit);
/// The whole file's bytes. Throws glint::Error(Io) naming `path` when it cannot be read.
std::vector<unsigned char> fileBytes(const std::filesystem::path& path);

/// True when the file starts with the OpenEXR magic number.
bool isExr(const std::filesystem::path& path);
/// Walks an OpenEXR file's headers (every part's) and throws glint::Error(Format) naming the
/// attribute and byte of one whose size runs past the end of the file (exr_check.cpp).
void checkExrHeaders(const std::filesystem::path& path);

/// Lower-case extension with the dot (".exr"), or "".
std::string lowerExtension(const std::filesystem::path& path);

/// The first line of a library's error message (they can span lines).
std::string firstLine(const std::string& message);

}  // namespace glint::detail
