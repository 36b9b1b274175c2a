// The streamed selection's spill store (auto/strip_spill.h): rows written strip by strip read
// back as the same floats over any rows, a dropped image's slot reused, no file left in the
// directory, and a store that cannot work holding nothing (so that its user filters again).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "auto/strip_spill.h"

namespace glint::denoise::detail {
namespace {

// A 5×10 image of 3 channels whose values name the key, the row and the place.
Image rowsOf(std::int64_t key, int y0, int y1) {
    Image rows(5, y1 - y0, 3);
    for (int y = y0; y < y1; ++y)
        for (int x = 0; x < 5; ++x)
            for (int c = 0; c < 3; ++c)
                rows(x, y - y0, c) =
                    float(key) * 1000.0f + float(y) + 0.1f * float(x) + 0.01f * float(c) + 1e-7f;
    return rows;
}

std::filesystem::path freshDirectory(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(StripSpill, ReadsBackTheRowsWrittenAsTheSameFloats) {
    const auto dir = freshDirectory("glint-strip-spill-test");
    StripSpill spill;
    ASSERT_TRUE(spill.open(dir.string(), 5, 10, 3, 2, false)) << spill.warning();
    EXPECT_TRUE(spill.on());
    // The file is unlinked at once: nothing is left in the directory.
    EXPECT_TRUE(std::filesystem::is_empty(dir));
    for (std::int64_t key : {7, 2})
        for (int y0 : {0, 4, 8}) spill.write(key, y0, rowsOf(key, y0, std::min(10, y0 + 4)));
    EXPECT_EQ(spill.bytesWritten(), 2u * 10 * 5 * 3 * sizeof(float));
    Image out;
    // Rows across the strips' boundaries, as the stacking reads them.
    ASSERT_TRUE(spill.read(7, 3, 9, out));
    EXPECT_TRUE(out.data().size() == rowsOf(7, 3, 9).data().size());
    for (std::size_t i = 0; i < out.data().size(); ++i)
        ASSERT_EQ(out.data()[i], rowsOf(7, 3, 9).data()[i]) << i;
    // A key it does not hold, or rows it does not hold, are not read.
    spill.write(9, 0, rowsOf(9, 0, 4));
    EXPECT_TRUE(spill.has(9, 0, 4));
    EXPECT_FALSE(spill.has(9, 3, 5));
    EXPECT_FALSE(spill.read(9, 3, 5, out));
    EXPECT_FALSE(spill.read(4, 0, 1, out));
    // A dropped key is gone; its slot holds the next key's rows.
    spill.drop(7);
    EXPECT_FALSE(spill.has(7, 0, 10));
    spill.write(11, 0, rowsOf(11, 0, 10));
    ASSERT_TRUE(spill.read(11, 0, 10, out));
    EXPECT_EQ(out(4, 9, 2), rowsOf(11, 0, 10)(4, 9, 2));
    ASSERT_TRUE(spill.read(2, 0, 10, out));
    EXPECT_EQ(out(1, 5, 0), rowsOf(2, 0, 10)(1, 5, 0));
    EXPECT_TRUE(spill.warning().empty());
    std::filesystem::remove_all(dir);
}

TEST(StripSpill, AStoreThatCannotWorkHoldsNothingAndSaysWhy) {
    // Not opened.
    StripSpill closed;
    closed.write(1, 0, rowsOf(1, 0, 2));
    EXPECT_FALSE(closed.has(1, 0, 2));
    // A directory that does not exist.
    StripSpill missing;
    EXPECT_FALSE(missing.open("/nonexistent/glint-spill", 5, 10, 3, 1, false));
    EXPECT_NE(missing.warning().find("/nonexistent/glint-spill"), std::string::npos)
        << missing.warning();
    missing.write(1, 0, rowsOf(1, 0, 2));
    EXPECT_FALSE(missing.has(1, 0, 2));
    // More than the disk holds (64 PiB).
    StripSpill huge;
    const auto dir = std::filesystem::temp_directory_path();
    EXPECT_FALSE(huge.open(dir.string(), 1 << 16, 1 << 16, 4, std::size_t(1) << 20, true));
    EXPECT_NE(huge.warning().find("MiB free"), std::string::npos) << huge.warning();
    EXPECT_FALSE(huge.failed());
}

}  // namespace
}  // namespace glint::denoise::detail
