// Private to image/: the formats other than OpenEXR that Glint reads, and writes, through their
// own reference libraries instead of the OpenImageIO module (other_formats.h): PNG by libpng
// (png_format.cpp), JPEG by libjpeg-turbo (jpeg_format.cpp). They are what a scene's texture
// files, a glTF asset's embedded images and a display PNG are, so rendering a textured asset or
// writing a PNG loads none of the some 260 libraries OpenImageIO brings. A format is one file and
// one line of the list in other_formats.cpp; a variant its reader leaves (a CMYK JPEG) and every
// other format go to the module.
#pragma once

#include <filesystem>
#include <span>
#include <string>

#include "other_formats.h"

namespace glint::detail {

/// One format read and written without the module.
struct DirectFormat {
    /// The format's name in messages ("png").
    const char* name;
    /// The extension of its files (".png"): what the module is told when it reads a variant the
    /// format leaves to it from memory, and what the format writes when `write8` is set.
    const char* extension;
    /// Whether `head`, the first bytes of a file (at least 16 when the file has them), are this
    /// format's signature.
    bool (*recognises)(std::span<const unsigned char> head);
    /// Walks the structure of a whole file's `bytes` before its library sees them (a truncated
    /// or damaged file, which the library would report without a place, print on stderr, or
    /// decode in part) and throws glint::Error(Format) naming `file` and the byte of the first
    /// damage.
    void (*checkStructure)(std::span<const unsigned char> bytes, const std::string& file);
    /// Decodes `bytes`, which `checkStructure` accepted: what it is into `out` (its colour space
    /// "sRGB" or "Linear" as the file declares it; `out.pixels` stays empty), its samples as float
    /// into `pixels`, alpha straight (as stored). False when the image is a variant it leaves to
    /// the module. Throws glint::Error(Format) naming `file` for damaged data; `check` throws for a
    /// refused size before anything is allocated for it.
    bool (*read)(std::span<const unsigned char> bytes, const std::string& file,
                 const SizeCheck& check, DecodedImage& out, Image& pixels);
    /// Writes `data`, 8-bit samples of `channels` (1 to 4; alpha the last of 2 or 4) interleaved,
    /// to `tmp`, declaring `colorSpace` ("sRGB" or "Linear"); throws glint::Error(Io) naming
    /// `shown`. Null when the module writes the format.
    void (*write8)(const std::filesystem::path& tmp, const std::string& shown, int width,
                   int height, int channels, const std::string& colorSpace,
                   const unsigned char* data);
};

extern const DirectFormat kPngFormat;
extern const DirectFormat kJpegFormat;

/// The direct format whose signature `head` carries, or null (other_formats.cpp).
const DirectFormat* directFormatOf(std::span<const unsigned char> head);
/// The direct format of the file at `path` by its first bytes, or null.
const DirectFormat* directFormatOf(const std::filesystem::path& path);

}  // namespace glint::detail
