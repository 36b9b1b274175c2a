// PNG and JPEG read through libpng and libjpeg-turbo, and PNG written through libpng, without the
// OpenImageIO module (image/src/direct_formats.h): every variant of the formats gives the floats
// OpenImageIO gives (alpha straight, as stored), the colour space decisions of docs/image.md, and
// what only the module reads still reads through it.
#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>
// jpeglib.h needs <cstdio> before it.
#include <jpeglib.h>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

class DirectFormats : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("glint_direct_formats_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path path(const std::string& name) const { return m_dir / name; }
    fs::path m_dir;
};

/// One PNG written by libpng itself, in every shape the format has.
struct PngCase {
    std::string name;
    int colorType = PNG_COLOR_TYPE_RGB;
    int depth = 8;
    bool interlaced = false;
    bool transparency = false;  ///< a tRNS chunk (a palette's alphas, a grey or RGB key)
    bool srgb = false;          ///< an sRGB chunk
    double gamma = 0.0;         ///< a gAMA chunk when > 0
};

constexpr int kWidth = 7, kHeight = 5;

/// Writes `c` with samples that vary per pixel and channel; returns its path.
fs::path writePng(const fs::path& file, const PngCase& c) {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, kWidth, kHeight, c.depth, c.colorType,
                 c.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    int samples = 1;  // per pixel
    if (c.colorType == PNG_COLOR_TYPE_RGB) samples = 3;
    if (c.colorType == PNG_COLOR_TYPE_RGB_ALPHA) samples = 4;
    if (c.colorType == PNG_COLOR_TYPE_GRAY_ALPHA) samples = 2;
    const int levels = 1 << c.depth;
    std::vector<png_color> palette;
    std::vector<png_byte> alphas;
    if (c.colorType == PNG_COLOR_TYPE_PALETTE) {
        for (int i = 0; i < levels; ++i) {
            palette.push_back({png_byte(i * 37), png_byte(255 - i * 11), png_byte(i * 5 + 3)});
            alphas.push_back(png_byte(255 - i * 13));
        }
        png_set_PLTE(png, info, palette.data(), int(palette.size()));
        if (c.transparency) png_set_tRNS(png, info, alphas.data(), int(alphas.size()), nullptr);
    } else if (c.transparency) {
        png_color_16 key{};
        key.gray = png_uint_16(1);
        key.red = png_uint_16(1), key.green = png_uint_16(2), key.blue = png_uint_16(3);
        png_set_tRNS(png, info, nullptr, 0, &key);
    }
    if (c.srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    if (c.gamma > 0.0) png_set_gAMA(png, info, c.gamma);
    png_write_info(png, info);
    if (c.depth == 16) png_set_swap(png);
    // Values of `depth` bits, packed as libpng packs sub-byte depths (first pixel high).
    const std::size_t rowBytes = png_get_rowbytes(png, info);
    std::vector<png_byte> rows(rowBytes * kHeight);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            for (int s = 0; s < samples; ++s) {
                const int i = (y * kWidth + x) * samples + s;
                const int value = (i * 2654435761u >> 7) % levels;  // spread over the range
                png_byte* row = rows.data() + rowBytes * std::size_t(y);
                if (c.depth == 16) {
                    reinterpret_cast<png_uint_16*>(row)[x * samples + s] = png_uint_16(value);
                } else if (c.depth == 8) {
                    row[x * samples + s] = png_byte(value);
                } else {
                    const int bit = (x * samples + s) * c.depth;
                    row[bit / 8] |= png_byte(value << (8 - c.depth - bit % 8));
                }
            }
    if (c.transparency && c.colorType == PNG_COLOR_TYPE_GRAY) rows[0] = 0;  // some key pixels
    std::vector<png_bytep> pointers;
    for (int y = 0; y < kHeight; ++y) pointers.push_back(rows.data() + rowBytes * std::size_t(y));
    png_write_image(png, pointers.data());
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return file;
}

/// The file as OpenImageIO reads it, as float, alpha straight.
Image readByOpenImageIo(const fs::path& file) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(file.string(), &config);
    if (!in) return {};
    const OIIO::ImageSpec& spec = in->spec();
    Image image(spec.width, spec.height, spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, image.data().data());
    return image;
}

void expectBitEqual(const Image& a, const Image& b, const std::string& what) {
    ASSERT_EQ(a.width(), b.width()) << what;
    ASSERT_EQ(a.height(), b.height()) << what;
    ASSERT_EQ(a.channels(), b.channels()) << what;
    for (std::size_t i = 0; i < a.data().size(); ++i)
        ASSERT_EQ(a.data()[i], b.data()[i]) << what << ", value " << i;
}

TEST_F(DirectFormats, EveryKindOfPngReadsAsOpenImageIoReadsIt) {
    std::vector<PngCase> cases;
    for (int depth : {1, 2, 4, 8, 16}) {
        cases.push_back({"grey" + std::to_string(depth), PNG_COLOR_TYPE_GRAY, depth});
        if (depth <= 8)
            cases.push_back({"palette" + std::to_string(depth), PNG_COLOR_TYPE_PALETTE, depth});
    }
    for (int depth : {8, 16}) {
        const std::string d = std::to_string(depth);
        cases.push_back({"greyAlpha" + d, PNG_COLOR_TYPE_GRAY_ALPHA, depth});
        cases.push_back({"rgb" + d, PNG_COLOR_TYPE_RGB, depth});
        cases.push_back({"rgba" + d, PNG_COLOR_TYPE_RGB_ALPHA, depth});
        cases.push_back({"rgbKey" + d, PNG_COLOR_TYPE_RGB, depth, false, true});
        cases.push_back({"greyKey" + d, PNG_COLOR_TYPE_GRAY, depth, false, true});
        cases.push_back({"rgbaInterlaced" + d, PNG_COLOR_TYPE_RGB_ALPHA, depth, true});
    }
    cases.push_back({"paletteAlpha", PNG_COLOR_TYPE_PALETTE, 8, false, true});
    cases.push_back({"paletteAlphaInterlaced", PNG_COLOR_TYPE_PALETTE, 4, true, true});
    for (const PngCase& c : cases) {
        const fs::path file = writePng(path(c.name + ".png"), c);
        const Image theirs = readByOpenImageIo(file);
        ASSERT_FALSE(theirs.empty()) << c.name;
        expectBitEqual(readImage(file, false), theirs, c.name);
        // The same bytes held in memory (a glTF asset's embedded image).
        std::ifstream in(file, std::ios::binary);
        const std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), {}};
        expectBitEqual(readImage(bytes, c.name, false), theirs, c.name + " in memory");
    }
}

// A PNG's colour is sRGB unless it declares gamma 1.0, whatever else it declares (what Blender
// assumes). OpenImageIO calls a gAMA of 1/2.2 "Gamma2.2", which Glint read as linear before.
TEST_F(DirectFormats, APngIsSrgbUnlessItDeclaresGammaOne) {
    struct Case {
        PngCase png;
        bool srgb;
    };
    const Case cases[] = {
        {{"plain", PNG_COLOR_TYPE_RGB, 8}, true},
        {{"srgbChunk", PNG_COLOR_TYPE_RGB, 8, false, false, true}, true},
        {{"gamma22", PNG_COLOR_TYPE_RGB, 8, false, false, false, 1.0 / 2.2}, true},
        {{"gamma1", PNG_COLOR_TYPE_RGB, 8, false, false, false, 1.0}, false},
        {{"gamma1deep", PNG_COLOR_TYPE_RGB, 16, false, false, false, 1.0}, false},
        {{"plainDeep", PNG_COLOR_TYPE_RGB, 16}, true},
        {{"greyAlpha", PNG_COLOR_TYPE_GRAY_ALPHA, 8}, true},
    };
    for (const Case& c : cases) {
        const fs::path file = writePng(path(c.png.name + ".png"), c.png);
        const Image raw = readImage(file, false), linear = readImage(file, true);
        const int alpha = raw.channels() == 2 || raw.channels() == 4 ? raw.channels() - 1 : -1;
        for (std::size_t i = 0; i < raw.data().size(); ++i) {
            const bool colour = int(i % std::size_t(raw.channels())) != alpha;
            const float expected = c.srgb && colour ? srgbDecode(raw.data()[i]) : raw.data()[i];
            ASSERT_EQ(linear.data()[i], expected) << c.png.name << ", value " << i;
        }
    }
}

// A PNG's colour is not multiplied by its alpha (glTF: "not premultiplied"), and neither is a
// TIFF's that says so: before, OpenImageIO multiplied both, in their encoded values.
TEST_F(DirectFormats, AlphaIsStraightAsStored) {
    // A colour of 0.8, 0.6, 0.4 at half coverage, and one of no coverage at all.
    Image im(2, 1, 4);
    const float pixels[8] = {0.8f, 0.6f, 0.4f, 0.5f, 0.2f, 0.9f, 0.5f, 0.0f};
    std::copy(pixels, pixels + 8, im.data().begin());
    writeImage(im, path("a.png"));  // libpng
    // A TIFF of straight alpha, through OpenImageIO's module.
    OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeUInt8);
    spec.alpha_channel = 3;
    spec.attribute("oiio:UnassociatedAlpha", 1);
    auto out = OIIO::ImageOutput::create(path("a.tif").string());
    ASSERT_TRUE(out && out->open(path("a.tif").string(), spec));
    std::vector<float> encoded(pixels, pixels + 8);
    for (int i : {0, 1, 2, 4, 5, 6}) encoded[std::size_t(i)] = srgbEncode(pixels[i]);
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, encoded.data()));
    out->close();
    for (const char* name : {"a.png", "a.tif"}) {
        const Image back = readImage(path(name));
        ASSERT_EQ(back.channels(), 4) << name;
        for (int i = 0; i < 8; ++i)
            EXPECT_NEAR(srgbEncode(back.data()[std::size_t(i)]), srgbEncode(pixels[i]),
                        i % 4 == 3 ? 1.0f : 0.5f / 255.0f + 1e-5f)
                << name << ", value " << i;
        EXPECT_NEAR(back.data()[3], 128.0f / 255.0f, 1e-6f) << name;  // alpha stays linear
    }
    // A TIFF Glint writes says its alpha is straight, so that other readers keep it so too.
    writeImage(im, path("b.tif"));
    auto in = OIIO::ImageInput::open(path("b.tif").string());
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_int_attribute("tiff:UnassociatedAlpha"), 1);  // ExtraSamples
    EXPECT_NEAR(readImage(path("b.tif")).data()[4], pixels[4], 0.5f / 255.0f);
}

TEST_F(DirectFormats, PngsWrittenAreReadByOpenImageIoAsWritten) {
    for (int channels = 1; channels <= 4; ++channels) {
        Image im(5, 4, channels);
        for (std::size_t i = 0; i < im.data().size(); ++i) im.data()[i] = float(i % 17) / 16.0f;
        const fs::path file = path("w" + std::to_string(channels) + ".png");
        writeImage(im, file);
        const Image theirs = readByOpenImageIo(file);
        expectBitEqual(readImage(file, false), theirs, file.string());
        auto in = OIIO::ImageInput::open(file.string());
        ASSERT_TRUE(in);
        EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "sRGB");
        EXPECT_EQ(in->spec().alpha_channel, channels == 2 || channels == 4 ? channels - 1 : -1);
    }
    // A display PNG not sRGB-encoded declares gamma 1.0 and reads back linear.
    Image grey(2, 2, 3, 0.25f);
    writePng(grey, path("linear.png"), {.srgb = false});
    EXPECT_NEAR(readImage(path("linear.png")).data()[0], 64.0f / 255.0f, 1e-6f);
}

/// Writes a JPEG of `components` (1 grey, 3 RGB, 4 CMYK) through libjpeg; returns its path.
fs::path writeJpeg(const fs::path& file, int components) {
    jpeg_compress_struct jpeg{};
    jpeg_error_mgr errors{};
    jpeg.err = jpeg_std_error(&errors);
    jpeg_create_compress(&jpeg);
    std::FILE* f = std::fopen(file.c_str(), "wb");
    jpeg_stdio_dest(&jpeg, f);
    jpeg.image_width = 19;
    jpeg.image_height = 13;
    jpeg.input_components = components;
    jpeg.in_color_space = components == 1 ? JCS_GRAYSCALE : components == 3 ? JCS_RGB : JCS_CMYK;
    jpeg_set_defaults(&jpeg);
    jpeg_set_quality(&jpeg, 90, TRUE);
    jpeg_start_compress(&jpeg, TRUE);
    std::vector<JSAMPLE> row(19 * std::size_t(components));
    while (jpeg.next_scanline < jpeg.image_height) {
        for (std::size_t i = 0; i < row.size(); ++i)
            row[i] = JSAMPLE((i * 29 + jpeg.next_scanline * 53) % 256);
        JSAMPROW rows[1] = {row.data()};
        jpeg_write_scanlines(&jpeg, rows, 1);
    }
    jpeg_finish_compress(&jpeg);
    jpeg_destroy_compress(&jpeg);
    std::fclose(f);
    return file;
}

TEST_F(DirectFormats, JpegsReadAsOpenImageIoReadsThem) {
    for (int components : {1, 3}) {
        const fs::path file =
            writeJpeg(path("c" + std::to_string(components) + ".jpg"), components);
        const Image theirs = readByOpenImageIo(file);
        expectBitEqual(readImage(file, false), theirs, file.string());
        // JPEG colour is sRGB.
        EXPECT_EQ(readImage(file, true).data()[5], srgbDecode(theirs.data()[5]));
    }
    // A CMYK JPEG is left to the module, which converts it to RGB as OpenImageIO does.
    const fs::path cmyk = writeJpeg(path("cmyk.jpg"), 4);
    expectBitEqual(readImage(cmyk, false), readByOpenImageIo(cmyk), "cmyk.jpg");
}

TEST_F(DirectFormats, OnlyATiledExrIsStoredInTiles) {
    Image im(8, 8, 3, 0.5f);
    writeImage(im, path("a.png"));
    writeImage(im, path("a.jpg"));
    writeImage(im, path("scanlines.exr"));
    writeImage(im, path("a.tif"));
    OIIO::ImageSpec spec(32, 32, 3, OIIO::TypeHalf);
    spec.tile_width = spec.tile_height = 16;
    auto out = OIIO::ImageOutput::create(path("tiles.exr").string());
    ASSERT_TRUE(out && out->open(path("tiles.exr").string(), spec));
    const std::vector<float> pixels(32 * 32 * 3, 0.5f);
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, pixels.data()));
    out->close();

    EXPECT_EQ(storedInTiles(path("a.png")), false);
    EXPECT_EQ(storedInTiles(path("a.jpg")), false);
    EXPECT_EQ(storedInTiles(path("scanlines.exr")), false);
    EXPECT_EQ(storedInTiles(path("tiles.exr")), true);
    EXPECT_EQ(storedInTiles(path("a.tif")), std::nullopt);  // only OpenImageIO can tell
    EXPECT_THROW(storedInTiles(path("missing.png")), Error);
}

TEST_F(DirectFormats, DamagedDataNamesTheFileAndFormat) {
    // Valid chunks (their CRCs right) around a deflate stream that is not one.
    const fs::path good = writePng(path("good.png"), {"good", PNG_COLOR_TYPE_RGB, 8});
    std::ifstream in(good, std::ios::binary);
    std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), {}};
    // IHDR is 8 + 25 bytes; the IDAT chunk's data starts 8 bytes after its header.
    std::size_t idat = 8;
    while (std::string(reinterpret_cast<const char*>(&bytes[idat + 4]), 4) != "IDAT")
        idat += 12 + (std::size_t(bytes[idat]) << 24 | std::size_t(bytes[idat + 1]) << 16 |
                      std::size_t(bytes[idat + 2]) << 8 | bytes[idat + 3]);
    const std::size_t length = std::size_t(bytes[idat + 2]) << 8 | bytes[idat + 3];
    for (std::size_t i = 2; i < length; ++i) bytes[idat + 8 + i] ^= 0x5a;
    // Its CRC again, so that only libpng's inflate can see the damage.
    std::uint32_t crc = 0xffffffffu;
    for (std::size_t i = idat + 4; i < idat + 8 + length; ++i) {
        crc ^= bytes[i];
        for (int k = 0; k < 8; ++k) crc = (crc & 1u) ? 0xedb88320u ^ (crc >> 1) : crc >> 1;
    }
    crc ^= 0xffffffffu;
    for (int k = 0; k < 4; ++k)
        bytes[idat + 8 + length + std::size_t(k)] = (crc >> (24 - 8 * k)) & 0xff;
    std::ofstream(path("bad.png"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    try {
        readImage(path("bad.png"));
        ADD_FAILURE() << "bad.png was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(e.file(), path("bad.png").string());
        EXPECT_EQ(e.where(), "pixels") << e.what();
        EXPECT_NE(std::string(e.what()).find("damaged PNG: "), std::string::npos) << e.what();
    }
}

TEST_F(DirectFormats, AJpegWhoseScanEndsEarlyIsAnError) {
    // A JPEG cut inside its scan, its end-of-image marker put back: the structure holds, and
    // libjpeg would pad the rest of the image with grey.
    const fs::path good = writeJpeg(path("good.jpg"), 3);
    std::ifstream in(good, std::ios::binary);
    std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), {}};
    std::size_t scan = 2;  // after the start-of-image marker, segment by segment to the scan's
    while (!(bytes[scan] == 0xff && bytes[scan + 1] == 0xda))
        scan += 2 + (std::size_t(bytes[scan + 2]) << 8 | bytes[scan + 3]);
    scan += 2 + (std::size_t(bytes[scan + 2]) << 8 | bytes[scan + 3]);
    ASSERT_GT(bytes.size(), scan + 8);
    bytes.resize(scan + (bytes.size() - 2 - scan) / 3);
    if (bytes.back() == 0xff) bytes.pop_back();  // not half a marker
    bytes.push_back(0xff);
    bytes.push_back(0xd9);
    std::ofstream(path("cut.jpg"), std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    for (int fromMemory : {0, 1}) {
        try {
            if (fromMemory)
                readImage(bytes, "cut.jpg");
            else
                readImage(path("cut.jpg"));
            ADD_FAILURE() << "cut.jpg was read";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format);
            EXPECT_EQ(e.file(), fromMemory ? "cut.jpg" : path("cut.jpg").string());
            EXPECT_EQ(e.where(), "pixels") << e.what();
            EXPECT_NE(std::string(e.what()).find("truncated JPEG (its data ends early)"),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace glint
