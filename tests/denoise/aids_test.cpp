// Visual aids: the bank's disagreement, a candidate's change, histogram-equalised depth.
#include <gtest/gtest.h>

#include <cmath>

#include "glint/denoise/aids.h"
#include "glint/image/error.h"

namespace glint::denoise {
namespace {

TEST(VisualAids, FilterVarianceIsZeroWhereResultsAgreeAndOneAtTheMost) {
    Image a(8, 4, 3, 0.5f), b(8, 4, 3, 0.5f), c(8, 4, 3, 0.5f);
    for (int c2 = 0; c2 < 3; ++c2) {
        b(2, 1, c2) = 0.7f;  // small disagreement
        b(6, 3, c2) = 0.9f;  // the largest
        c(6, 3, c2) = 0.1f;
    }
    c(0, 0, 0) = std::nanf("");  // left out, not propagated
    const Image map = filterVarianceMap({&a, &b, &c});
    EXPECT_EQ(map.channels(), 1);
    EXPECT_EQ(map(4, 2, 0), 0.0f);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_EQ(map(6, 3, 0), 1.0f);
    EXPECT_GT(map(2, 1, 0), 0.0f);
    EXPECT_LT(map(2, 1, 0), 1.0f);
    for (float v : map.data()) EXPECT_TRUE(v >= 0.0f && v <= 1.0f);
    const Image same = filterVarianceMap({&a, &a});
    for (float v : same.data()) EXPECT_EQ(v, 0.0f);
    EXPECT_THROW(filterVarianceMap({}), Error);
    Image small(2, 2, 3);
    EXPECT_THROW(filterVarianceMap({&a, &small}), Error);
}

TEST(VisualAids, ChangeMapIsNormalisedAbsoluteDifference) {
    Image comp(4, 4, 3, 0.2f), cand(4, 4, 3, 0.2f);
    for (int c = 0; c < 3; ++c) cand(1, 1, c) = 0.6f, cand(2, 2, c) = 0.4f;
    const Image map = changeMap(cand, comp);
    EXPECT_EQ(map(0, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(map(1, 1, 0), 1.0f);
    EXPECT_FLOAT_EQ(map(2, 2, 0), 0.5f);
    EXPECT_THROW(changeMap(cand, Image(2, 2, 3)), Error);
}

TEST(VisualAids, EqualisedDepthIsMonotoneInZeroOneAndNaNIsZero) {
    Image depth(5, 1, 1);
    depth(0, 0, 0) = 100.0f;
    depth(1, 0, 0) = 1.0f;
    depth(2, 0, 0) = 2.0f;
    depth(3, 0, 0) = std::nanf("");
    depth(4, 0, 0) = 1000.0f;
    const Image eq = equalizeHistogram(depth);
    EXPECT_FLOAT_EQ(eq(1, 0, 0), 0.25f);
    EXPECT_FLOAT_EQ(eq(2, 0, 0), 0.5f);
    EXPECT_FLOAT_EQ(eq(0, 0, 0), 0.75f);
    EXPECT_FLOAT_EQ(eq(4, 0, 0), 1.0f);
    EXPECT_EQ(eq(3, 0, 0), 0.0f);
    EXPECT_THROW(equalizeHistogram(Image(2, 2, 3)), Error);
}

}  // namespace
}  // namespace glint::denoise
