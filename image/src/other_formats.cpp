// Finding and loading the module of the image formats other than OpenEXR (other_formats.h).
#include "other_formats.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <system_error>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::detail {

namespace {

namespace fs = std::filesystem;

constexpr const char* kModuleName = "libglint_image_formats.so";

struct Loaded {
    const OtherFormats* formats = nullptr;
    std::string failure;  ///< why it could not be loaded (empty when it was)
};

Loaded load() {
    std::string tried;
    for (const fs::path& candidate : otherFormatsCandidates()) {
        std::error_code ec;
        if (!fs::is_regular_file(candidate, ec)) {
            tried += (tried.empty() ? "" : ", ") + candidate.string();
            continue;
        }
        // RTLD_LOCAL: OpenImageIO's symbols stay the module's; the process may link it already
        // (the renderer's texture store), which the module then shares.
        void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* why = ::dlerror();
            return {nullptr, "cannot load " + candidate.string() + " (" +
                                 std::string(why ? why : "no reason given") + ")"};
        }
        using Entry = const OtherFormats* (*)();
        auto entry = reinterpret_cast<Entry>(::dlsym(handle, kOtherFormatsEntry));
        if (!entry)
            return {nullptr, candidate.string() + " has no " + kOtherFormatsEntry +
                                 " (a module of another Glint version)"};
        return {entry(), {}};
    }
    if (const char* env = std::getenv("GLINT_IMAGE_FORMATS_MODULE"); env && *env)
        return {nullptr, "GLINT_IMAGE_FORMATS_MODULE names " + tried +
                             ", which is not a file (expected the path of " + kModuleName + ")"};
    return {nullptr, "the module " + std::string(kModuleName) + " is in none of " + tried +
                         "; set GLINT_IMAGE_FORMATS_MODULE to its path"};
}

}  // namespace

std::vector<fs::path> otherFormatsCandidates() {
    std::vector<fs::path> out;
    // A module the user names is the only one tried: a wrong path is an error, not a fallback.
    if (const char* env = std::getenv("GLINT_IMAGE_FORMATS_MODULE"); env && *env)
        return {fs::path(env)};
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec)
        out.push_back(
            (exe.parent_path() / ".." / "lib" / "glint" / kModuleName).lexically_normal());
    out.push_back(fs::path(GLINT_IMAGE_FORMATS_BUILD_DIR) / kModuleName);
    out.push_back(fs::path(GLINT_IMAGE_FORMATS_INSTALL_DIR) / kModuleName);
    return out;
}

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
