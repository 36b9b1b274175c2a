// Private to image/: a layered EXR read through OpenEXR over all the shapes its files take —
// scanline or tiled, one part or several, with or without mip levels (level 0 is the
// full-resolution image) — its layout and rows of every channel (docs/image.md, "The layered
// EXR"). OpenEXR alone, so that reading an EXR never loads the image library of other formats.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace glint::detail {

/// One attribute of the first part's header: its value as text (strings as they are, numbers in
/// decimal, vectors and boxes as their numbers separated by spaces, other types by their OpenEXR
/// type name in brackets) and as an integer when it is an int attribute.
struct ExrAttribute {
    std::string name;
    std::string text;
    std::optional<std::int64_t> integer;
};

/// One part of the file: where its channels start in ExrLayout::channelNames, how many, and its
/// tile size (0 for scanlines).
struct ExrPart {
    int index = 0;
    int firstChannel = 0;
    int channels = 0;
    int tileWidth = 0, tileHeight = 0;
};

/// Every channel of every part of a flat EXR of one data window. Each part's channels are in the
/// order image tools show them (per layer: R, G, B, then A; X, Y, Z in a layer that has X; the
/// rest by name), the order readImage returns them in.
struct ExrLayout {
    int x = 0, y = 0;           ///< the data window's origin
    int width = 0, height = 0;  ///< the data window's size
    std::vector<ExrAttribute> attributes;
    std::vector<std::string> channelNames;
    std::vector<ExrPart> parts;

    int channels() const { return int(channelNames.size()); }
    /// The attribute named `name`, or null.
    const ExrAttribute* find(std::string_view name) const;
};

/// Where ExrInput::read puts one channel: its index in ExrLayout::channelNames, the place of
/// its value in the data window's first pixel, and the strides between pixels and between rows
/// in bytes.
struct ExrTarget {
    int channel = 0;
    float* first = nullptr;
    std::size_t xStride = 0, yStride = 0;
};

/// An EXR file open for reading.
class ExrInput {
  public:
    /// Opens `path` and reads its layout. A bare channel name ("X") of a part after the first is
    /// named "PART.X" (PART: the part's name), so that each part can name its layer. Throws
    /// glint::Error(Io) when the file is missing or unreadable, (Format) naming the file and the
    /// part for a file that is not an EXR, a deep or subsampled part, a part whose data window
    /// differs from part 0's, or a channel name two parts still share.
    explicit ExrInput(const std::filesystem::path& path);
    ~ExrInput();
    ExrInput(const ExrInput&) = delete;
    ExrInput& operator=(const ExrInput&) = delete;

    const ExrLayout& layout() const { return m_layout; }

    /// Reads the channels `targets` name, as float, straight into them (float data bit for bit;
    /// a channel named at most once), the file's chunks decoded in parallel. Throws
    /// glint::Error(Format) naming the file and the rows of the first chunk, in file order, whose
    /// data is truncated or corrupt.
    void read(const std::vector<ExrTarget>& targets);

  private:
    struct Files;
    std::string m_file;
    std::unique_ptr<Files> m_files;
    ExrLayout m_layout;
};

}  // namespace glint::detail
