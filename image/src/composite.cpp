#include "glint/image/composite.h"

#include <algorithm>
#include <string>

#include "glint/image/error.h"

namespace glint {

namespace {

std::string shape(const Image& im) {
    return std::to_string(im.width()) + "x" + std::to_string(im.height()) + "x" +
           std::to_string(im.channels());
}

void checkBlendShapes(const Image& a, const Image& b, const Image& weight, const char* what) {
    if (!a.sameShape(b))
        throw Error(ErrorKind::InvalidArgument, std::string(what) + ": images differ in shape (" +
                                                    shape(a) + " and " + shape(b) + ")");
    if (weight.width() != a.width() || weight.height() != a.height() ||
        (weight.channels() != 1 && weight.channels() != a.channels()))
        throw Error(ErrorKind::InvalidArgument,
                    std::string(what) + ": weight map is " + shape(weight) + ", expected " +
                        std::to_string(a.width()) + "x" + std::to_string(a.height()) + "x1 or x" +
                        std::to_string(a.channels()));
}

// One pixel of the blend; w exactly 0 or 1 selects an input unchanged.
inline float mixValue(float a, float b, float w) {
    w = std::clamp(w, 0.0f, 1.0f);
    if (w == 0.0f) return a;
    if (w == 1.0f) return b;
    return a * (1.0f - w) + b * w;
}

void blendRows(Image& out, const Image& a, const Image& b, const Image& weight, const Rect& rect) {
    const int ch = a.channels();
    const bool perChannel = weight.channels() == ch && ch != 1;
    for (int y = rect.y0; y < rect.y1; ++y) {
        const float* pa = a.row(y);
        const float* pb = b.row(y);
        const float* pw = weight.row(y);
        float* po = out.row(y);
        for (int x = rect.x0; x < rect.x1; ++x)
            for (int c = 0; c < ch; ++c) {
                const std::size_t i = std::size_t(x) * ch + c;
                const float w = perChannel ? pw[i] : pw[x];
                po[i] = mixValue(pa[i], pb[i], w);
            }
    }
}

}  // namespace

void paste(Image& dst, const Image& src, int x0, int y0) {
    if (src.channels() != dst.channels())
        throw Error(ErrorKind::InvalidArgument,
                    "paste: the image has " + std::to_string(src.channels()) +
                        " channels, the target " + std::to_string(dst.channels()));
    const Rect where{x0, x0 + src.width(), y0, y0 + src.height()};
    if (intersect(where, dst.bounds()) != where)
        throw Error(ErrorKind::InvalidArgument,
                    "paste: a " + std::to_string(src.width()) + "x" + std::to_string(src.height()) +
                        " image at (" + std::to_string(x0) + ", " + std::to_string(y0) +
                        ") does not fit in " + std::to_string(dst.width()) + "x" +
                        std::to_string(dst.height()));
    for (int y = 0; y < src.height(); ++y)
        std::copy_n(src.row(y), std::size_t(src.width()) * src.channels(),
                    dst.row(y0 + y) + std::size_t(x0) * dst.channels());
}

FrameBuffers withColorPasted(const FrameBuffers& frame, const Image& src, int x0, int y0) {
    FrameBuffers out = frame.sharedCopy();
    Image color = frame.color();
    paste(color, src, x0, y0);
    out.set(Layer::Color, std::move(color));
    return out;
}

Image blend(const Image& a, const Image& b, const Image& weight) {
    checkBlendShapes(a, b, weight, "blend");
    Image out(a.width(), a.height(), a.channels());
    blendRows(out, a, b, weight, a.bounds());
    return out;
}

void blendInPlace(Image& dst, const Image& src, const Image& weight, const Rect& rect) {
    checkBlendShapes(dst, src, weight, "blend");
    const Rect r = intersect(rect, dst.bounds());
    if (r.empty()) return;
    blendRows(dst, dst, src, weight, r);
}

}  // namespace glint
