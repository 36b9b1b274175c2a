// Finding and loading the module of the image formats other than OpenEXR (other_formats.h).
#include "other_formats.h"

#include <algorithm>
#include <mutex>

#include "glint/image/error.h"
#include "glint/image/internal/modules.h"
#include "glint/image/io.h"

namespace glint::detail {

namespace {

namespace fs = std::filesystem;

struct Loaded {
    const OtherFormats* formats = nullptr;
    std::string failure;  ///< why it could not be loaded (empty when it was)
};

Loaded load() {
    const ModuleEntry module =
        loadModule("libglint_image_formats.so", "GLINT_IMAGE_FORMATS_MODULE", kOtherFormatsEntry);
    if (!module.entry) return {nullptr, module.failure};
    using Entry = const OtherFormats* (*)();
    return {reinterpret_cast<Entry>(module.entry)(), {}};
}

}  // namespace

const OtherFormats& otherFormats(const std::string& file, const std::string& where) {
    static std::once_flag once;
    static Loaded loaded;
    std::call_once(once, [] { loaded = load(); });
    if (!loaded.formats)
        throw Error(ErrorKind::Io,
                    "cannot read or write formats other than OpenEXR: " + loaded.failure, file,
                    where);
    return *loaded.formats;
}

void writeOtherFormat8(const fs::path& tmp, const fs::path& shown, int width, int height,
                       const std::vector<std::string>& names, int alpha,
                       const std::string& colorSpace, const unsigned char* data) {
    const std::string file = shown.string();
    const ModuleError error =
        otherFormats(file, "write")
            .write8(tmp.string(), file, width, height, names, alpha, colorSpace, data);
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
