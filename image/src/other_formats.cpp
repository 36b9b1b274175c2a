// Finding and loading the module of the image formats other than OpenEXR (other_formats.h).
#include "other_formats.h"

#include <algorithm>

#include "glint/image/error.h"
#include "glint/image/internal/modules.h"
#include "glint/image/io.h"

namespace glint::detail {

namespace fs = std::filesystem;

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
    const ModuleError error =
        otherFormats(file, "write")
            .write8(tmp.string(), width, height, names, alpha, colorSpace, data);
    if (error.kind >= 0) throw Error(ErrorKind(error.kind), error.message, file, error.where);
}

Image readOtherFormat(const std::string& file, std::span<const unsigned char> bytes,
                      const std::string& extension, bool linearize, const SizeCheck& check) {
    DecodedImage decoded;
    const ModuleError error =
        otherFormats(file, "open").read(file, bytes, extension, check, decoded);
    if (error.kind >= 0) throw Error(ErrorKind(error.kind), error.message, file, error.where);
    Image image(decoded.width, decoded.height, decoded.channels);
    std::copy(decoded.pixels.begin(), decoded.pixels.end(), image.data().begin());
    if (linearize && srgbEncodedFile(decoded.colorSpace, decoded.eightBit)) {
        // Decode every colour channel; alpha stays linear.
        float* data = image.data().data();
        const int n = decoded.channels;
        for (std::size_t i = 0; i < image.pixelCount(); ++i)
            for (int c = 0; c < n; ++c)
                if (c != decoded.alphaChannel) data[i * n + c] = srgbDecode(data[i * n + c]);
    }
    return image;
}

}  // namespace glint::detail
