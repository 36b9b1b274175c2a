// Textures and environment images: read through glint::readImage, linearised, checked.
#include <cmath>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "scene/loader.h"

namespace glint::render::detail {

Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where) {
    if (source.width() < 1 || source.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", sceneFile.string(), where);
    Image out(source.width(), source.height(), 3);
    for (int y = 0; y < source.height(); ++y)
        for (int x = 0; x < source.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = source(x, y, source.channels() >= 3 ? c : 0) * scale;
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")" +
                                    (scale != 1.0f ? " after scaling by " + std::to_string(scale)
                                                   : std::string()),
                                sceneFile.string(), where);
                out(x, y, c) = v;
            }
    return out;
}

Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where) {
    std::error_code ec;  // odd paths (too long...) are reported, not thrown
    if (!std::filesystem::exists(image, ec))
        throw Error(ErrorKind::Io, what + " file '" + image.string() + "' not found",
                    sceneFile.string(), where);
    if (!std::filesystem::is_regular_file(image, ec))
        throw Error(ErrorKind::Io, what + " '" + image.string() + "' is not a file",
                    sceneFile.string(), where);
    const Image raw = readImage(image, true);
    try {
        return scaledRgb(raw, scale, what, sceneFile, where);
    } catch (const Error& e) {
        // Name the image itself as the file.
        throw Error(e.kind(), e.message(), image.string(), where);
    }
}

Image textureRgba(const Image& raw, const std::string& what, const std::filesystem::path& file,
                  const std::string& where) {
    if (raw.width() < 1 || raw.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", file.string(), where);
    const int n = raw.channels();
    // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
    const int rgb[3] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0};
    const int alpha = n == 2 ? 1 : (n >= 4 ? 3 : -1);
    Image out(raw.width(), raw.height(), 4);
    for (int y = 0; y < raw.height(); ++y)
        for (int x = 0; x < raw.width(); ++x) {
            for (int c = 0; c < 4; ++c) {
                const float v = c < 3 ? raw(x, y, rgb[c]) : (alpha >= 0 ? raw(x, y, alpha) : 1.0f);
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")",
                                file.string(), where);
                out(x, y, c) = v;
            }
        }
    return out;
}

}  // namespace glint::render::detail
