// Reading and writing images: layered OpenEXR (with other renderers' channel names), PNG, JPEG,
// any format OpenImageIO reads (loaded at the first such file: docs/image.md). Every writer writes
// a temporary file and renames it into place.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint {

/// Reads a layered EXR into FrameBuffers. Glint's own channel names are read directly; the alias
/// table maps Blender/Cycles, pbrt-v4 (per-sample Variance divided by spp) and Mitsuba names.
/// Throws glint::Error(Io) for a missing/unreadable file, (Format) for a truncated file or one
/// without R,G,B.
FrameBuffers readExr(const std::filesystem::path& path);

/// Lossless EXR compression. None is fastest (docs/image.md); Zip makes smooth layers smaller.
enum class ExrCompression { None, Zip };

/// Options of writeExr.
struct ExrWriteOptions {
    ExrCompression compression = ExrCompression::None;
};

/// Writes one-part float32 EXR with the channel names and glint:* attributes of docs/image.md.
void writeExr(const FrameBuffers& frame, const std::filesystem::path& path,
              const ExrWriteOptions& options = {});

/// Reads an EXR's first part, a PNG, a JPEG, or any image OpenImageIO can read, as float (all
/// channels; an EXR's in the order image tools show them; alpha straight, as stored). If
/// `linearize` and the file's colour is sRGB-encoded (a JPEG; a PNG unless it declares gamma 1.0;
/// another format declaring sRGB, or 8-bit and declaring nothing: BMP, TGA), values are converted
/// to linear.
Image readImage(const std::filesystem::path& path, bool linearize = true);
/// Checks an image file's structure before a reader allocates for it or prints its own
/// messages: PNG chunks, a JPEG's end marker, the sizes an OpenEXR header's attributes claim.
/// readImage makes the same checks on what it reads (an EXR's headers; a PNG's or JPEG's bytes,
/// read once); a caller that opens files through OpenImageIO itself (the renderer's texture
/// store) calls this first. Throws glint::Error(Format) naming the byte.
void checkImageFile(const std::filesystem::path& path);
/// Whether an image file stores its pixels in tiles that a reader can fetch one at a time (a
/// tiled OpenEXR), from its header: false for PNG, JPEG and scanline OpenEXR files; empty for
/// the other formats, which only OpenImageIO can tell (a TIFF or .tx file may be tiled). Throws
/// glint::Error as readImage does for a file it cannot open.
std::optional<bool> storedInTiles(const std::filesystem::path& path);

/// readImage of an encoded PNG or JPEG held in memory (a glTF asset's embedded image); errors
/// name `name`.
Image readImage(std::span<const unsigned char> bytes, const std::string& name,
                bool linearize = true);

/// Writes a plain float image: float EXR when the extension is .exr, else 8-bit (PNG through
/// libpng, other formats through OpenImageIO) with colour channels sRGB-encoded and clamped (alpha,
/// the 2nd of 2 or 4th of 4 channels, linear).
void writeImage(const Image& image, const std::filesystem::path& path);

/// The largest exposure, in stops either way, that display values and metrics accept: 2^64
/// keeps every finite radiance finite after scaling.
inline constexpr float kMaxExposure = 64.0f;

/// How a linear image is turned into display values.
struct DisplayOptions {
    float exposure = 0.0f;  ///< stops: values are multiplied by 2^exposure
    bool srgb = true;       ///< sRGB-encode after clamping to [0, 1]
    /// When >= 0, show this one channel in false colour (viridis-like ramp) over [lo, hi].
    int falseColorChannel = -1;
    float falseColorLo = 0.0f;
    float falseColorHi = 1.0f;
};

/// Display values in [0, 1] (3 channels; a 1-channel image is shown as grey). NaN/Inf map to
/// magenta so they are visible.
Image toDisplay(const Image& linear, const DisplayOptions& options = {});

/// sRGB transfer function (linear [0,1] → encoded) and its inverse.
float srgbEncode(float linear);
float srgbDecode(float encoded);

/// Whether a file's colour values are sRGB-encoded, from the colour space its header declares
/// (OpenImageIO's "oiio:ColorSpace") and whether it stores 8-bit integers: "sRGB", or nothing
/// declared in an 8-bit file (BMP, TGA, TIFF: 8-bit colour is sRGB, as Blender and pbrt-v4
/// read it).
bool srgbEncodedFile(const std::string& declaredColorSpace, bool eightBit);

/// Writes an 8-bit RGB PNG of toDisplay(linear, options).
void writePng(const Image& linear, const std::filesystem::path& path,
              const DisplayOptions& options = {});

/// Runs `write(tmpPath)` then renames tmpPath onto `path`; removes tmpPath on failure.
/// tmpPath is temporaryPathFor(path).
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path&)>& write);

/// The temporary name writeAtomically uses for `path` in this process: a hidden sibling that
/// keeps the extension, ".NAME.tmp-PID.EXT". Known in advance, so that a program interrupted by
/// a signal can remove it (one writer per target and process at a time).
std::filesystem::path temporaryPathFor(const std::filesystem::path& path);

}  // namespace glint
