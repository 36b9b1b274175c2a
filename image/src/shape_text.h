// Private to glint_image: how an error message writes an image's shape and a number.
#pragma once

#include <cstdio>
#include <string>

#include "glint/image/image.h"

namespace glint::detail {

/// "WxHxC": width x height x channels (e.g. "640x480x3").
inline std::string shapeText(const Image& im) {
    return std::to_string(im.width()) + "x" + std::to_string(im.height()) + "x" +
           std::to_string(im.channels());
}

/// A number as %g writes it ("1e-07", "2.5", "nan"): std::to_string's fixed six decimals would
/// write 1e-07 as "0.000000".
inline std::string numberText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

}  // namespace glint::detail
