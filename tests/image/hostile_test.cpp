// Damaged image files and absurd display/metric options: one clean glint::Error each, never a
// library's own stderr line, a partly decoded image or a NaN result (docs/reliability.md).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "png_bytes.h"

namespace glint {
namespace {

namespace fs = std::filesystem;

class ImageHostile : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("glint_image_hostile_" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
        Image im(16, 12, 3);
        for (int y = 0; y < 12; ++y)
            for (int x = 0; x < 16; ++x)
                for (int c = 0; c < 3; ++c) im(x, y, c) = float((x + y + c) % 5) / 5.0f;
        writeImage(im, m_dir / "good.png");
        writeImage(im, m_dir / "good.jpg");
    }
    void TearDown() override { fs::remove_all(m_dir); }

    std::vector<char> bytes(const fs::path& p) {
        std::ifstream in(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    fs::path write(const std::string& name, const std::vector<char>& data) {
        std::ofstream(m_dir / name, std::ios::binary)
            .write(data.data(), std::streamsize(data.size()));
        return m_dir / name;
    }
    void expectFormatError(const fs::path& file, const std::string& mention) {
        try {
            readImage(file);
            ADD_FAILURE() << file << " was read";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
            EXPECT_EQ(e.file(), file.string());
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    }
    fs::path m_dir;
};

TEST_F(ImageHostile, DamagedPngIsCaughtBeforeLibpng) {
    std::vector<char> png = bytes(m_dir / "good.png");
    EXPECT_NO_THROW(readImage(m_dir / "good.png"));
    // Truncated inside the image data, and after the last chunk header.
    expectFormatError(write("cut.png", {png.begin(), png.begin() + long(png.size()) - 20}),
                      "truncated");
    expectFormatError(write("cut2.png", {png.begin(), png.begin() + 20}), "truncated");
    // One flipped byte in the pixel data: its chunk's CRC fails.
    std::vector<char> flipped = png;
    flipped[flipped.size() - 20] ^= 0x5a;
    expectFormatError(write("flip.png", flipped), "CRC");
}

TEST_F(ImageHostile, APngOfZeroWidthOrHeightIsOneErrorNotLibpngsLines) {
    // libpng printed two "libpng error" lines of its own for these.
    for (const auto& [w, h] : {std::pair{0u, 0u}, std::pair{0u, 5u}, std::pair{5u, 0u}}) {
        const std::string png = test::pngOfSize(w, h);
        const fs::path file = write("zero.png", {png.begin(), png.end()});
        expectFormatError(file, "a PNG is at least 1x1");
        try {
            readImage(std::span<const unsigned char>(
                          reinterpret_cast<const unsigned char*>(png.data()), png.size()),
                      "embedded.png");
            ADD_FAILURE() << "embedded bytes were read";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("at least 1x1"), std::string::npos) << e.what();
        }
    }
}

TEST_F(ImageHostile, TruncatedJpegIsRefusedNotDecodedGrey) {
    const std::vector<char> jpg = bytes(m_dir / "good.jpg");
    EXPECT_NO_THROW(readImage(m_dir / "good.jpg"));
    expectFormatError(write("cut.jpg", {jpg.begin(), jpg.begin() + long(jpg.size()) / 2}),
                      "truncated JPEG");
}

TEST_F(ImageHostile, AnExrHeaderAttributeLongerThanTheFileIsRefusedBeforeOpenExrAllocatesIt) {
    // fuzz_shard_merge's find: 1905 bytes whose string attribute 'capDate' claims 2 GB. OpenEXR
    // 3.1 allocated the 2 GB (seconds, and past libFuzzer's memory limit) before finding the
    // file short; the header walk refuses it naming the attribute.
    const fs::path file = fs::path(GLINT_SOURCE_DIR) /
                          "tests/data/fuzz-regressions/exr/header-attribute-claims-2gb.exr";
    expectFormatError(file, "'capDate' (string)");
    try {
        readExr(file);
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "header") << e.what();
        EXPECT_NE(std::string(e.what()).find("claims 2009202707 bytes"), std::string::npos)
            << e.what();
    }
    // A good EXR, single- and multi-part, passes the walk.
    Image im(4, 3, 3);
    writeImage(im, m_dir / "good.exr");
    EXPECT_NO_THROW(checkImageFile(m_dir / "good.exr"));
    EXPECT_NO_THROW(readImage(m_dir / "good.exr"));
    // Cut inside its header: a truncated header, not a read past the end.
    const std::vector<char> exr = bytes(m_dir / "good.exr");
    expectFormatError(write("cut.exr", {exr.begin(), exr.begin() + 40}), "header");
}

TEST_F(ImageHostile, ExposureBeyondSixtyFourStopsIsRefusedNotNaN) {
    const Image a(16, 16, 3, 0.0f), b(16, 16, 3, 0.5f);
    MetricOptions o;
    o.exposure = 128.0f;  // 2^128 overflows float: 0 × inf would be NaN
    EXPECT_THROW(ssim(a, b, o), Error);
    o.exposure = 64.0f;
    const double s = ssim(a, b, o).value;
    EXPECT_TRUE(std::isfinite(s));
    DisplayOptions d;
    d.exposure = -65.0f;
    EXPECT_THROW(toDisplay(a, d), Error);
}

TEST(TemporaryPath, IsAHiddenSiblingNamedByTheProcess) {
    const fs::path tmp = temporaryPathFor("/some/folder/render.exr");
    EXPECT_EQ(tmp.parent_path(), fs::path("/some/folder"));
    EXPECT_EQ(tmp.extension(), ".exr");
    EXPECT_EQ(tmp.filename().string(), ".render.tmp-" + std::to_string(::getpid()) + ".exr");
}

}  // namespace
}  // namespace glint
