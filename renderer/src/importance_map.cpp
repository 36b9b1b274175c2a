#include "glint/render/importance_map.h"

#include <cmath>
#include <sstream>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::render {

Image readImportanceMap(const std::filesystem::path& path) {
    const Image image = readImage(path, false);
    if (image.channels() == 1) return image;
    if (image.channels() < 3)
        throw Error(ErrorKind::Format,
                    "an importance map has one channel, or three or more whose first three are "
                    "R, G, B (their luminance is the weight); this image has " +
                        std::to_string(image.channels()),
                    path.string());
    Image weights(image.width(), image.height(), 1);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            weights(x, y, 0) =
                0.2126f * image(x, y, 0) + 0.7152f * image(x, y, 1) + 0.0722f * image(x, y, 2);
    return weights;
}

void checkImportanceMap(const Image& weights, int width, int height, const std::string& file) {
    auto bad = [&](const std::string& what, const std::string& where = {}) {
        throw Error(ErrorKind::InvalidArgument, what, file, where);
    };
    if (weights.width() != width || weights.height() != height)
        bad("the importance map is " + std::to_string(weights.width()) + "x" +
            std::to_string(weights.height()) + ", the scene renders " + std::to_string(width) +
            "x" + std::to_string(height) + " (expected one weight a pixel)");
    if (weights.channels() != 1)
        bad("expected one channel of weights, got " + std::to_string(weights.channels()));
    bool anyPositive = false;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float w = weights(x, y, 0);
            if (!std::isfinite(w) || w < 0.0f) {
                std::ostringstream msg;
                msg << "importance weight " << w << "; expected a finite weight >= 0";
                bad(msg.str(), "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")");
            }
            anyPositive |= w > 0.0f;
        }
    if (!anyPositive)
        bad("every weight is 0: no pixel could take a sample after the start (expected some "
            "weight > 0)");
}

}  // namespace glint::render
