// glint::Image — a width × height × channels array of float, row-major, channels interleaved.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "glint/image/large_pages.h"

namespace glint {

/// A rectangle of pixels, half-open: x in [x0, x1), y in [y0, y1).
struct Rect {
    int x0 = 0, x1 = 0, y0 = 0, y1 = 0;

    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    bool operator==(const Rect&) const = default;
};

/// Intersection of two rectangles (empty if they do not overlap).
Rect intersect(const Rect& a, const Rect& b);

/// Float image with interleaved channels. Cheap to move, deep-copied on copy.
class Image {
  public:
    Image() = default;
    /// Allocates width × height × channels floats set to `fill`. Throws on negative sizes.
    Image(int width, int height, int channels, float fill = 0.0f);

    int width() const { return m_width; }
    int height() const { return m_height; }
    int channels() const { return m_channels; }
    bool empty() const { return m_data.empty(); }
    std::size_t pixelCount() const { return std::size_t(m_width) * std::size_t(m_height); }
    Rect bounds() const { return {0, m_width, 0, m_height}; }

    /// Pointer to the first channel of pixel (0, y); unchecked.
    float* row(int y) { return m_data.data() + std::size_t(y) * m_width * m_channels; }
    const float* row(int y) const { return m_data.data() + std::size_t(y) * m_width * m_channels; }

    /// Unchecked element access.
    float& operator()(int x, int y, int c) {
        return m_data[(std::size_t(y) * m_width + x) * m_channels + c];
    }
    float operator()(int x, int y, int c) const {
        return m_data[(std::size_t(y) * m_width + x) * m_channels + c];
    }

    /// Bounds-checked element access; throws glint::Error(InvalidArgument) outside the image.
    float& at(int x, int y, int c);
    float at(int x, int y, int c) const;

    std::span<float> data() { return m_data; }
    std::span<const float> data() const { return m_data; }

    /// Sets every element to `value`.
    void fill(float value);
    /// Copy of the pixels inside `rect` (which must lie inside the image).
    Image crop(const Rect& rect) const;
    /// Copy of channels [first, first + count).
    Image channelsSlice(int first, int count) const;
    /// Number of elements that are NaN or ±Inf.
    std::size_t countNonFinite() const;
    /// True when sizes and channel counts match.
    bool sameShape(const Image& other) const {
        return m_width == other.m_width && m_height == other.m_height &&
               m_channels == other.m_channels;
    }

  private:
    int m_width = 0;
    int m_height = 0;
    int m_channels = 0;
    std::vector<float, LargePageAllocator<float>> m_data;
};

}  // namespace glint
