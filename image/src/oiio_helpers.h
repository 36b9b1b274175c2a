// Private to image/: opening and writing files through OpenImageIO with glint::Error reporting.
#pragma once

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <functional>
#include <span>
#include <string>

namespace glint::detail {

/// Opens `path` for reading. Throws glint::Error(Io) when the file is missing or unreadable and
/// (Format) when OpenImageIO does not recognise it as an image.
OIIO::ImageInput::unique_ptr openImage(const std::filesystem::path& path);

/// Writes `data` (laid out as `spec` says, of type `format`) to `tmp` in the format its extension
/// names; errors name `shown`, the file the user asked for. Throws glint::Error(Io).
void writeOiio(const std::filesystem::path& tmp, const std::filesystem::path& shown,
               const OIIO::ImageSpec& spec, OIIO::TypeDesc format, const void* data);

/// Writes a float image of `spec` to `tmp` in strips of `stripRows` rows: `fill(y0, y1, strip)`
/// fills rows [y0, y1) of all channels, interleaved, into `strip`. Errors name `shown`.
void writeOiioStrips(const std::filesystem::path& tmp, const std::filesystem::path& shown,
                     const OIIO::ImageSpec& spec, int stripRows,
                     const std::function<void(int y0, int y1, float* strip)>& fill);

/// True when the file (or the bytes) starts with the PNG signature.
bool isPng(const std::filesystem::path& path);
bool isPng(std::span<const unsigned char> bytes);
/// Walks a PNG's chunks (lengths, CRCs, IHDR first, IDAT present, IEND reached) and throws
/// glint::Error(Format) naming the byte of the first damage (png_check.cpp).
void checkPngStructure(const std::filesystem::path& path);
/// The same for an image held in memory; errors name `file`.
void checkPngStructure(std::span<const unsigned char> bytes, const std::string& file);

/// True when the file (or the bytes) starts with the JPEG start-of-image marker.
bool isJpeg(const std::filesystem::path& path);
bool isJpeg(std::span<const unsigned char> bytes);
/// Throws glint::Error(Format) for a JPEG without its end-of-image marker (truncated).
void checkJpegStructure(const std::filesystem::path& path);
/// The same for an image held in memory; errors name `file`.
void checkJpegStructure(std::span<const unsigned char> bytes, const std::string& file);

/// True when the file starts with the OpenEXR magic number.
bool isExr(const std::filesystem::path& path);
/// Walks an OpenEXR file's headers (every part's) and throws glint::Error(Format) naming the
/// attribute and byte of one whose size runs past the end of the file (exr_check.cpp).
void checkExrHeaders(const std::filesystem::path& path);

/// Lower-case extension with the dot (".exr"), or "".
std::string lowerExtension(const std::filesystem::path& path);

/// First line of an OpenImageIO error message (they can span lines).
std::string firstLine(const std::string& message);

}  // namespace glint::detail
