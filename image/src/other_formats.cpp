// The image formats other than OpenEXR (other_formats.h): PNG and JPEG read (and PNG written)
// through their own libraries (direct_formats.h), every other format through the module,
// found and loaded at its first use.
#include "other_formats.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "direct_formats.h"
#include "glint/image/error.h"
#include "glint/image/internal/modules.h"
#include "glint/image/io.h"
#include "image_files.h"

namespace glint::detail {

namespace fs = std::filesystem;

namespace {

/// The formats read and written without the module, one line each (direct_formats.h).
const DirectFormat* const kDirectFormats[] = {
    &kPngFormat,
    &kJpegFormat,
};

}  // namespace

const DirectFormat* directFormatOf(std::span<const unsigned char> head) {
    for (const DirectFormat* format : kDirectFormats)
        if (format->recognises(head)) return format;
    return nullptr;
}

const DirectFormat* directFormatOf(const fs::path& path) {
    return directFormatOf(fileHead(path, 16));
}

const OtherFormats& otherFormats(const std::string& file, const std::string& where) {
    // Loaded once (a static's initialisation is thread-safe); a failure is kept and reported to
    // every caller.
    static const ModuleEntry module =
        loadModule("libglint_image_formats.so", "GLINT_IMAGE_FORMATS_MODULE", kOtherFormatsEntry);
    static const OtherFormats* const formats =
        module.entry ? reinterpret_cast<const OtherFormats* (*)()>(module.entry)() : nullptr;
    if (!formats)
        throw Error(ErrorKind::Io,
                    "cannot read or write formats other than OpenEXR: " + module.failure, file,
                    where);
    return *formats;
}

void writeOtherFormat8(const fs::path& tmp, const fs::path& shown, int width, int height,
                       const std::vector<std::string>& names, int alpha,
                       const std::string& colorSpace, const unsigned char* data) {
    const std::string file = shown.string();
    const int channels = int(names.size());
    const bool plain = channels >= 1 && channels <= 4 &&
                       alpha == (channels == 2 || channels == 4 ? channels - 1 : -1);
    for (const DirectFormat* format : kDirectFormats)
        if (plain && format->write8 && format->extension == lowerExtension(tmp))
            return format->write8(tmp, file, width, height, channels, colorSpace, data);
    const ModuleError error =
        otherFormats(file, "write")
            .write8(tmp.string(), width, height, names, alpha, colorSpace, data);
    if (error.kind >= 0) throw Error(ErrorKind(error.kind), error.message, file, error.where);
}

namespace {

/// srgbDecode of the 256 values an 8-bit sample is read as (i × 1/255, as every reader here and
/// OpenImageIO convert it), so that an 8-bit image is decoded by lookup, bit for bit the same.
const std::array<float, 256>& eightBitDecoded() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[std::size_t(i)] = srgbDecode(float(i) * (1.0f / 255.0f));
        return t;
    }();
    return table;
}

}  // namespace

Image readOtherFormat(const std::string& file, std::span<const unsigned char> bytes,
                      const std::string& extension, bool linearize, const SizeCheck& check) {
    DecodedImage decoded;
    Image image;
    bool read = false;
    // A file of a direct format is read once: its bytes are checked, then decoded. The module
    // reads a variant the format declines from the file or the caller's bytes.
    if (const DirectFormat* format =
            bytes.empty() ? directFormatOf(fs::path(file)) : directFormatOf(bytes)) {
        const std::vector<unsigned char> whole =
            bytes.empty() ? fileBytes(file) : std::vector<unsigned char>();
        const std::span<const unsigned char> data = bytes.empty() ? std::span(whole) : bytes;
        format->checkStructure(data, file);
        read = format->read(data, file, check, decoded, image);
    }
    if (!read) {
        decoded = {};
        const ModuleError error =
            otherFormats(file, "open").read(file, bytes, extension, check, decoded);
        if (error.kind >= 0) throw Error(ErrorKind(error.kind), error.message, file, error.where);
        image = Image(decoded.width, decoded.height, decoded.channels);
        std::copy(decoded.pixels.begin(), decoded.pixels.end(), image.data().begin());
    }
    if (linearize && srgbEncodedFile(decoded.colorSpace, decoded.eightBit)) {
        // Decode every colour channel; alpha stays linear.
        const std::array<float, 256>& table = eightBitDecoded();
        float* data = image.data().data();
        const int n = decoded.channels;
        for (std::size_t i = 0; i < image.pixelCount(); ++i)
            for (int c = 0; c < n; ++c) {
                if (c == decoded.alphaChannel) continue;
                float& v = data[i * std::size_t(n) + std::size_t(c)];
                const long k = std::lround(v * 255.0f);
                v = decoded.eightBit && k >= 0 && k <= 255 && float(k) * (1.0f / 255.0f) == v
                        ? table[std::size_t(k)]
                        : srgbDecode(v);
            }
    }
    return image;
}

}  // namespace glint::detail
