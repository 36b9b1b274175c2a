// Private to image/: the image formats other than OpenEXR. PNG and JPEG go through libpng and
// libjpeg-turbo (direct_formats.h); every other format (Radiance HDR, TIFF, BMP, TGA, …) and a
// CMYK JPEG through OpenImageIO in a module of their own (oiio_module.cpp, the shared object
// libglint_image_formats.so, found as glint/image/internal/modules.h says; the environment
// variable GLINT_IMAGE_FORMATS_MODULE names it), which the first such read or write loads. A
// command that reads and writes only EXRs, PNGs and JPEGs never loads OpenImageIO and the some
// 260 libraries it brings, which take about 0.4 s to load on a 2-core machine
// (docs/research/start-and-writing.md).
#pragma once

#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "glint/image/image.h"

namespace glint::detail {

/// What the module read: a float image, its channels interleaved, and what tells whether its
/// colour channels are sRGB-encoded.
struct DecodedImage {
    int width = 0, height = 0, channels = 0;
    int alphaChannel = -1;   ///< -1: none
    std::string colorSpace;  ///< as the file declares it ("sRGB", "Linear"), or empty
    bool eightBit = false;   ///< its samples are 8-bit
    std::vector<float> pixels;
};

/// An error the module met (the caller throws it as a glint::Error): its ErrorKind, message and
/// place. kind < 0: no error.
struct ModuleError {
    int kind = -1;
    std::string message, where;
};

/// Refuses a header's size before anything is allocated for it (throws glint::Error).
using SizeCheck = std::function<void(int width, int height, int channels)>;

/// The module's functions. The caller names the file in their errors.
struct OtherFormats {
    /// Reads the image in `file`, or in `bytes` when they are not empty (`extension`, ".png" or
    /// ".jpg", names their format), as float.
    ModuleError (*read)(const std::string& file, std::span<const unsigned char> bytes,
                        const std::string& extension, const SizeCheck& check, DecodedImage& out);
    /// Writes `data`, 8-bit samples of a width × height × channels image with the channel names
    /// `names`, alpha at `alpha` (-1: none), declared in `colorSpace`, to `tmp` in the format its
    /// extension names.
    ModuleError (*write8)(const std::string& tmp, int width, int height,
                          const std::vector<std::string>& names, int alpha,
                          const std::string& colorSpace, const unsigned char* data);
};

/// The module's entry point, an extern "C" function returning its OtherFormats; the version in
/// the name changes with the structure.
inline constexpr const char* kOtherFormatsEntry = "glint_other_formats_2";

/// The module, loaded on the first call. Throws glint::Error(Io) naming what was tried when it
/// cannot be found or loaded; `file` and `where` name what needed it.
const OtherFormats& otherFormats(const std::string& file, const std::string& where);

/// Writes 8-bit samples, in the format `tmp`'s extension names: a PNG of 1 to 4 channels (alpha
/// the last of 2 or 4) through libpng, anything else through the module (OtherFormats::write8);
/// throws glint::Error(Io) naming `shown`.
void writeOtherFormat8(const std::filesystem::path& tmp, const std::filesystem::path& shown,
                       int width, int height, const std::vector<std::string>& names, int alpha,
                       const std::string& colorSpace, const unsigned char* data);

/// Reads an image of another format than OpenEXR from `file` (or `bytes`, as in
/// OtherFormats::read): a PNG or JPEG, by its signature, through its library, anything else
/// through the module; alpha straight, as stored. Decodes sRGB colour channels to linear when
/// `linearize`.
Image readOtherFormat(const std::string& file, std::span<const unsigned char> bytes,
                      const std::string& extension, bool linearize, const SizeCheck& check);

}  // namespace glint::detail
