// Tests of glint/image/box_mean.h: the window's mean on every channel, cut at the border; a
// non-finite value reaching only its windows; radius 0 and bad radii.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "glint/image/box_mean.h"
#include "glint/image/error.h"

using namespace glint;

namespace box_mean_test {

Image randomImage(int w, int h, int channels, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> value(-2.0f, 5.0f);
    Image image(w, h, channels);
    for (float& v : image.data()) v = value(rng);
    return image;
}

}  // namespace box_mean_test

using namespace box_mean_test;

TEST(BoxMean, EachPixelIsItsWindowsMeanOnEveryChannelWithTheWindowCutAtTheBorder) {
    const Image image = randomImage(13, 9, 3, 7);
    for (int r : {1, 2, 5, 20}) {
        const Image mean = boxMean(image, r);
        ASSERT_EQ(mean.width(), 13);
        ASSERT_EQ(mean.height(), 9);
        ASSERT_EQ(mean.channels(), 3);
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 13; ++x)
                for (int c = 0; c < 3; ++c) {
                    // The window's pixels counted one by one over the whole frame.
                    double sum = 0.0;
                    int n = 0;
                    for (int sy = 0; sy < 9; ++sy)
                        for (int sx = 0; sx < 13; ++sx)
                            if (std::abs(sx - x) <= r && std::abs(sy - y) <= r) {
                                sum += image(sx, sy, c);
                                ++n;
                            }
                    EXPECT_NEAR(mean(x, y, c), sum / n, 1e-5)
                        << "r " << r << " pixel " << x << "," << y << " channel " << c;
                }
    }
}

TEST(BoxMean, AConstantImageStaysConstantUpToTheCorners) {
    const Image flat(10, 6, 2, 0.3f);
    const Image mean = boxMean(flat, 3);
    for (float v : mean.data()) EXPECT_FLOAT_EQ(v, 0.3f);
}

TEST(BoxMean, ANonFiniteValueReachesOnlyTheWindowsThatHoldIt) {
    Image image = randomImage(12, 12, 1, 3);
    image(2, 2, 0) = std::numeric_limits<float>::infinity();
    image(9, 9, 0) = std::numeric_limits<float>::quiet_NaN();
    const Image mean = boxMean(image, 1);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x) {
            const bool nearInf = std::abs(x - 2) <= 1 && std::abs(y - 2) <= 1;
            const bool nearNan = std::abs(x - 9) <= 1 && std::abs(y - 9) <= 1;
            if (nearInf)
                EXPECT_TRUE(std::isinf(mean(x, y, 0))) << x << "," << y;
            else if (nearNan)
                EXPECT_TRUE(std::isnan(mean(x, y, 0))) << x << "," << y;
            else
                EXPECT_TRUE(std::isfinite(mean(x, y, 0))) << x << "," << y;
        }
}

TEST(BoxMean, RadiusZeroIsTheImageAndANegativeRadiusIsAnError) {
    const Image image = randomImage(5, 4, 3, 11);
    const Image same = boxMean(image, 0);
    EXPECT_TRUE(std::equal(same.data().begin(), same.data().end(), image.data().begin(),
                           image.data().end()));
    try {
        boxMean(image, -1);
        FAIL() << "a negative radius was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("radius -1"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(boxMean(Image(), 2).empty());
}
