// The files the external filter exchanges with a program: three-channel float images as
// OpenEXR (R, G, B) or PFM (Portable Float Map, "PF", little-endian, rows bottom to top).
// Private to the external filter.
#pragma once

#include <filesystem>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// File formats an external program reads and writes.
enum class ExchangeFormat { Exr, Pfm };

/// Writes a 3-channel image as `format`.
void writeExchangeImage(const Image& image, const std::filesystem::path& path,
                        ExchangeFormat format);

/// Reads a 3-channel image written by a program. Throws glint::Error naming the file: Io when
/// it is missing, Format when it is not a 3-channel image of that format (a short PFM, say).
Image readExchangeImage(const std::filesystem::path& path, ExchangeFormat format);

}  // namespace glint::denoise::detail
