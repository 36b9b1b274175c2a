// Private to glint_image: how an error message names an image's shape.
#pragma once

#include <string>

#include "glint/image/image.h"

namespace glint::detail {

/// "WxHxC": width x height x channels (e.g. "640x480x3").
inline std::string shapeText(const Image& im) {
    return std::to_string(im.width()) + "x" + std::to_string(im.height()) + "x" +
           std::to_string(im.channels());
}

}  // namespace glint::detail
