// PNG read and written through libpng, without the OpenImageIO module (direct_formats.h). Every
// PNG is read as 8- or 16-bit grey, grey + alpha, RGB or RGBA (palettes and transparency chunks
// expanded, interlacing undone); its colour is sRGB-encoded unless a gAMA chunk of 1.0 declares
// it linear (what Blender and Cycles assume of a PNG, whatever gamma it declares). libpng reports
// errors by longjmp: the functions that set its jump hold nothing that needs destroying. Before
// libpng sees a file its chunks are walked (lengths, CRCs, IHDR first, image data, IEND):
// libpng's own message for a truncated or damaged file names no byte.
#include <png.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "direct_formats.h"
#include "glint/image/error.h"
#include "image_files.h"

namespace glint::detail {

namespace {

// CRC-32 (ISO 3309, the PNG chunk checksum), table-driven.
std::uint32_t crc32(const unsigned char* data, std::size_t n, std::uint32_t crc = 0xffffffffu) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xedb88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ data[i]) & 0xffu] ^ (crc >> 8);
    return crc;
}

std::uint32_t bigEndian(const unsigned char* p) {
    return std::uint32_t(p[0]) << 24 | std::uint32_t(p[1]) << 16 | std::uint32_t(p[2]) << 8 |
           std::uint32_t(p[3]);
}

bool isPng(std::span<const unsigned char> bytes) {
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    return bytes.size() >= 8 && std::equal(bytes.begin(), bytes.begin() + 8, signature);
}

void checkPng(std::span<const unsigned char> bytes, const std::string& file) {
    auto fail = [&](std::size_t at, const std::string& what) {
        throw Error(ErrorKind::Format, "damaged PNG: " + what, file, "byte " + std::to_string(at));
    };
    std::size_t at = 8;
    bool sawHeader = false, sawData = false;
    while (true) {
        if (at + 12 > bytes.size()) fail(at, "truncated (the file ends inside a chunk header)");
        const std::uint32_t length = bigEndian(&bytes[at]);
        const std::string type(reinterpret_cast<const char*>(&bytes[at + 4]), 4);
        if (length > 0x7fffffffu || at + 12 + std::size_t(length) > bytes.size())
            fail(at, "truncated (chunk '" + type + "' of " + std::to_string(length) +
                         " bytes goes past the end of the file)");
        const std::uint32_t stored = bigEndian(&bytes[at + 8 + length]);
        if ((crc32(&bytes[at + 4], 4 + std::size_t(length)) ^ 0xffffffffu) != stored)
            fail(at, "chunk '" + type + "' fails its CRC");
        if (!sawHeader && type != "IHDR") fail(at, "the first chunk is not IHDR");
        // libpng prints its own lines for a zero width or height (PNG 1.2, 11.2.2: both >= 1).
        if (!sawHeader && length >= 8 &&
            (bigEndian(&bytes[at + 8]) == 0 || bigEndian(&bytes[at + 12]) == 0))
            fail(at, "IHDR says the image is " + std::to_string(bigEndian(&bytes[at + 8])) + "x" +
                         std::to_string(bigEndian(&bytes[at + 12])) +
                         " pixels; a PNG is at least 1x1");
        sawHeader = true;
        sawData = sawData || type == "IDAT";
        at += 12 + std::size_t(length);
        if (type == "IEND") break;
    }
    if (!sawData) fail(at, "no image data (IDAT)");
}

/// What libpng's callbacks read from and report to.
struct PngState {
    const unsigned char* data = nullptr;
    std::size_t size = 0, at = 0;
    const char* stage = "header";
    char message[256] = "";
};

void onError(png_structp png, png_const_charp message) {
    auto* state = static_cast<PngState*>(png_get_error_ptr(png));
    std::snprintf(state->message, sizeof state->message, "%s", message);
    png_longjmp(png, 1);
}

// libpng would print its warnings (an unknown chunk, a bad gAMA) on stderr; the image reads.
void onWarning(png_structp, png_const_charp) {}

void readFromMemory(png_structp png, png_bytep out, png_size_t count) {
    auto* state = static_cast<PngState*>(png_get_io_ptr(png));
    if (count > state->size - state->at) png_error(png, "the data ends early");
    std::memcpy(out, state->data + state->at, count);
    state->at += count;
}

/// Reads the header and the samples of every row into `samples`; false after a libpng error.
bool decode(png_structp png, png_infop info, PngState& state, const SizeCheck& check,
            DecodedImage& out, std::unique_ptr<unsigned char[]>& samples,
            std::vector<png_bytep>& rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_info(png, info);
    png_uint_32 width = 0, height = 0;
    int depth = 0, type = 0;
    png_get_IHDR(png, info, &width, &height, &depth, &type, nullptr, nullptr, nullptr);
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (type == PNG_COLOR_TYPE_GRAY && depth < 8) png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(png);
    if (depth == 16) png_set_swap(png);  // the host's byte order
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    const int channels = png_get_channels(png, info);
    check(int(width), int(height), channels);

    out.width = int(width);
    out.height = int(height);
    out.channels = channels;
    out.alphaChannel = channels == 2 || channels == 4 ? channels - 1 : -1;
    out.eightBit = png_get_bit_depth(png, info) == 8;
    int intent = 0;
    double gamma = 0.0;
    const bool linear = !png_get_sRGB(png, info, &intent) && png_get_gAMA(png, info, &gamma) &&
                        std::fabs(gamma - 1.0) < 0.01;
    out.colorSpace = linear ? "Linear" : "sRGB";

    state.stage = "pixels";
    const std::size_t rowBytes = png_get_rowbytes(png, info);
    samples.reset(new unsigned char[rowBytes * height]);  // left uninitialised: libpng fills it
    rows.resize(height);
    for (png_uint_32 y = 0; y < height; ++y) rows[y] = samples.get() + rowBytes * y;
    png_read_image(png, rows.data());
    png_read_end(png, nullptr);
    return true;
}

bool readPng(std::span<const unsigned char> bytes, const std::string& file, const SizeCheck& check,
             DecodedImage& out, Image& pixels) {
    PngState state;
    state.data = bytes.data();
    state.size = bytes.size();
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, onError, onWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    struct Release {
        png_structp& png;
        png_infop& info;
        ~Release() {
            if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        }
    } release{png, info};
    if (!info) throw Error(ErrorKind::Io, "libpng cannot start (out of memory)", file, "open");
    png_set_read_fn(png, &state, readFromMemory);

    std::unique_ptr<unsigned char[]> samples;
    std::vector<png_bytep> rows;
    if (!decode(png, info, state, check, out, samples, rows))
        throw Error(ErrorKind::Format, std::string("damaged PNG: ") + state.message, file,
                    state.stage);
    // As OpenImageIO converts: a sample times the reciprocal of its largest value.
    pixels = Image(out.width, out.height, out.channels);
    const std::span<float> values = pixels.data();
    if (out.eightBit) {
        for (std::size_t i = 0; i < values.size(); ++i)
            values[i] = float(samples[i]) * (1.0f / 255.0f);
    } else {
        const auto* wide = reinterpret_cast<const std::uint16_t*>(samples.get());
        for (std::size_t i = 0; i < values.size(); ++i)
            values[i] = float(wide[i]) * (1.0f / 65535.0f);
    }
    return true;
}

/// Writes the header and every row to `file`; false after a libpng error.
bool encode(png_structp png, png_infop info, std::FILE* file, int width, int height, int channels,
            bool srgb, const unsigned char* data) {
    if (setjmp(png_jmpbuf(png))) return false;
    static const int kTypes[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                  PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    png_init_io(png, file);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8, kTypes[channels - 1],
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (srgb)
        png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    else
        png_set_gAMA(png, info, 1.0);
    png_write_info(png, info);
    const std::size_t rowBytes = std::size_t(width) * std::size_t(channels);
    for (int y = 0; y < height; ++y) png_write_row(png, data + rowBytes * std::size_t(y));
    png_write_end(png, info);
    return true;
}

void writePng8(const std::filesystem::path& tmp, const std::string& shown, int width, int height,
               int channels, const std::string& colorSpace, const unsigned char* data) {
    PngState state;
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (!file)
        throw Error(ErrorKind::Io, std::string("cannot create file (") + std::strerror(errno) + ")",
                    shown, "write");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, onError, onWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    struct Release {
        png_structp& png;
        png_infop& info;
        std::FILE*& file;
        ~Release() {
            if (png) png_destroy_write_struct(&png, info ? &info : nullptr);
            if (file) std::fclose(file);
        }
    } release{png, info, file};
    if (!info) throw Error(ErrorKind::Io, "libpng cannot start (out of memory)", shown, "write");
    if (!encode(png, info, file, width, height, channels, colorSpace == "sRGB", data))
        throw Error(ErrorKind::Io, std::string("cannot write pixels (") + state.message + ")",
                    shown, "write");
    std::FILE* const done = file;
    file = nullptr;
    if (std::fclose(done) != 0)
        throw Error(ErrorKind::Io, std::string("cannot finish file (") + std::strerror(errno) + ")",
                    shown, "write");
}

}  // namespace

const DirectFormat kPngFormat{"png", ".png", isPng, checkPng, readPng, writePng8};

}  // namespace glint::detail
