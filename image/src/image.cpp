#include "glint/image/image.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "glint/image/error.h"
#include "shape_text.h"

namespace glint {

Rect intersect(const Rect& a, const Rect& b) {
    Rect r{std::max(a.x0, b.x0), std::min(a.x1, b.x1), std::max(a.y0, b.y0), std::min(a.y1, b.y1)};
    if (r.empty()) return {};
    return r;
}

Image::Image(int width, int height, int channels, float fill)
    : m_width(width), m_height(height), m_channels(channels) {
    if (width < 0 || height < 0 || channels < 0)
        throw Error(ErrorKind::InvalidArgument,
                    "image size must be non-negative, got " + std::to_string(width) + "x" +
                        std::to_string(height) + "x" + std::to_string(channels));
    m_data.assign(std::size_t(width) * height * channels, fill);
}

namespace {
[[noreturn]] void outOfRange(const Image& im, int x, int y, int c) {
    throw Error(ErrorKind::InvalidArgument,
                "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") channel " +
                    std::to_string(c) + " is outside the " + detail::shapeText(im) + " image");
}
}  // namespace

float& Image::at(int x, int y, int c) {
    if (x < 0 || y < 0 || c < 0 || x >= m_width || y >= m_height || c >= m_channels)
        outOfRange(*this, x, y, c);
    return (*this)(x, y, c);
}

float Image::at(int x, int y, int c) const {
    if (x < 0 || y < 0 || c < 0 || x >= m_width || y >= m_height || c >= m_channels)
        outOfRange(*this, x, y, c);
    return (*this)(x, y, c);
}

void Image::fill(float value) {
    std::fill(m_data.begin(), m_data.end(), value);
}

Image Image::crop(const Rect& rect) const {
    if (rect.empty() || intersect(rect, bounds()) != rect)
        throw Error(ErrorKind::InvalidArgument,
                    "crop [" + std::to_string(rect.x0) + "," + std::to_string(rect.x1) + ")x[" +
                        std::to_string(rect.y0) + "," + std::to_string(rect.y1) +
                        ") is empty or outside the " + std::to_string(m_width) + "x" +
                        std::to_string(m_height) + " image");
    Image out(rect.width(), rect.height(), m_channels);
    for (int y = rect.y0; y < rect.y1; ++y)
        std::copy_n(row(y) + std::size_t(rect.x0) * m_channels,
                    std::size_t(rect.width()) * m_channels, out.row(y - rect.y0));
    return out;
}

Image Image::channelsSlice(int first, int count) const {
    if (first < 0 || count <= 0 || first + count > m_channels)
        throw Error(ErrorKind::InvalidArgument, "channel slice [" + std::to_string(first) + ", " +
                                                    std::to_string(first + count) +
                                                    ") outside an image with " +
                                                    std::to_string(m_channels) + " channels");
    Image out(m_width, m_height, count);
    for (std::size_t i = 0; i < pixelCount(); ++i)
        for (int c = 0; c < count; ++c)
            out.m_data[i * count + c] = m_data[i * m_channels + first + c];
    return out;
}

std::size_t Image::countNonFinite() const {
    return std::size_t(
        std::count_if(m_data.begin(), m_data.end(), [](float v) { return !std::isfinite(v); }));
}

}  // namespace glint
