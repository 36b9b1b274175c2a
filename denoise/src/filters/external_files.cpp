// EXR and PFM files for the external filter (external_files.h). PFM after Paul Debevec's
// Portable Float Map: "PF\n<width> <height>\n<scale>\n", then width × height RGB float triples,
// rows from the bottom up, little-endian when the scale is negative.
#include "filters/external_files.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::denoise::detail {

namespace fs = std::filesystem;

namespace {

void writePfm(const Image& image, const fs::path& path) {
    std::ofstream out(path, std::ios::binary);
    out << "PF\n" << image.width() << " " << image.height() << "\n-1.0\n";
    std::vector<float> row(std::size_t(image.width()) * 3);
    for (int y = image.height() - 1; y >= 0; --y) {
        std::memcpy(row.data(), image.row(y), row.size() * sizeof(float));
        if constexpr (std::endian::native == std::endian::big)
            for (float& v : row)
                v = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<std::uint32_t>(v)));
        out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * 4));
    }
    if (!out.flush()) throw Error(ErrorKind::Io, "cannot write the file", path.string());
}

Image readPfm(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ErrorKind::Io, "cannot read the file", path.string());
    // Header: magic, width, height, scale, each followed by whitespace (one byte after the scale).
    std::string magic;
    long long width = 0, height = 0;
    double scale = 0.0;
    in >> magic >> width >> height >> scale;
    if (!in || in.get() == EOF)
        throw Error(ErrorKind::Format, "not a PFM file (expected 'PF', width, height, scale)",
                    path.string(), "header");
    if (magic != "PF")
        throw Error(ErrorKind::Format,
                    "'" + magic + "' is not 'PF' (a 3-channel PFM; 'Pf' is 1-channel)",
                    path.string(), "header");
    if (width < 1 || height < 1 || width > (1 << 20) || height > (1 << 20) || scale == 0.0)
        throw Error(ErrorKind::Format,
                    "size " + std::to_string(width) + "x" + std::to_string(height) +
                        " or scale 0 is not a valid PFM header",
                    path.string(), "header");
    const std::streamoff start = in.tellg();
    in.seekg(0, std::ios::end);
    const std::streamoff bytes = std::streamoff(width) * height * 3 * 4;
    if (in.tellg() - start != bytes)
        throw Error(ErrorKind::Format,
                    "holds " + std::to_string(in.tellg() - start) + " bytes of pixels, a " +
                        std::to_string(width) + "x" + std::to_string(height) + " PFM needs " +
                        std::to_string(bytes),
                    path.string(), "pixels");
    in.seekg(start);
    Image image(int(width), int(height), 3);
    const bool swap = (scale < 0.0) != (std::endian::native == std::endian::little);
    for (int y = int(height) - 1; y >= 0; --y) {
        float* row = image.row(y);
        in.read(reinterpret_cast<char*>(row), std::streamsize(width * 3 * 4));
        if (swap)
            for (long long i = 0; i < width * 3; ++i)
                row[i] =
                    std::bit_cast<float>(__builtin_bswap32(std::bit_cast<std::uint32_t>(row[i])));
    }
    if (!in) throw Error(ErrorKind::Io, "cannot read the pixels", path.string());
    return image;
}

}  // namespace

void writeExchangeImage(const Image& image, const fs::path& path, ExchangeFormat format) {
    GLINT_CHECK(image.channels() == 3);
    if (format == ExchangeFormat::Pfm) return writePfm(image, path);
    FrameBuffers frame(image.width(), image.height());
    frame.set(Layer::Color, image);
    writeExr(frame, path);
}

Image readExchangeImage(const fs::path& path, ExchangeFormat format) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
        throw Error(ErrorKind::Io, "the program wrote no output file", path.string());
    if (format == ExchangeFormat::Pfm) return readPfm(path);
    return readExr(path).color();
}

}  // namespace glint::denoise::detail
