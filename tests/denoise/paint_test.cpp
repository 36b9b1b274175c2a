// Painting primitives: the soft brush, the magic wand, Poisson-diffusion blending (checked
// against the discrete Laplace equation and against Eigen's direct sparse solver).
#include <gtest/gtest.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {
namespace {

TEST(Brush, WeightsAtTheCentreInnerAndOuterRadius) {
    const Brush b{40.0, 0.5};  // outer radius 20, inner radius 10
    EXPECT_EQ(brushWeight(0.0, b), 1.0f);
    EXPECT_EQ(brushWeight(10.0, b), 1.0f);
    EXPECT_FLOAT_EQ(brushWeight(15.0, b), 0.5f);
    EXPECT_FLOAT_EQ(brushWeight(12.5, b), 0.75f);
    EXPECT_EQ(brushWeight(20.0, b), 0.0f);
    EXPECT_EQ(brushWeight(25.0, b), 0.0f);
    // Softness 0: a cone; softness 1: a hard disc.
    EXPECT_FLOAT_EQ(brushWeight(10.0, Brush{40.0, 0.0}), 0.5f);
    EXPECT_EQ(brushWeight(19.9, Brush{40.0, 1.0}), 1.0f);
    EXPECT_EQ(brushWeight(20.0, Brush{40.0, 1.0}), 0.0f);
}

TEST(Brush, RectangleHoldsExactlyThePixelsItCanTouch) {
    const Brush b{10.0, 0.5};
    const Rect r = dabRect(20.0, 30.0, b, 100, 100);
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 100; ++x) {
            const double d = std::hypot(x + 0.5 - 20.0, y + 0.5 - 30.0);
            if (brushWeight(d, b) > 0.0f) {
                EXPECT_TRUE(r.contains(x, y)) << x << "," << y;
            }
        }
    EXPECT_LE(r.width(), 11);
    EXPECT_EQ(dabRect(-50.0, -50.0, b, 100, 100).empty(), true);
    const Rect edge = dabRect(1.0, 1.0, b, 100, 100);
    EXPECT_EQ(edge.x0, 0);
    EXPECT_EQ(edge.y0, 0);
    EXPECT_THROW(validate(Brush{0.0, 0.5}), Error);
    EXPECT_THROW(validate(Brush{10.0, 1.5}), Error);
    EXPECT_THROW(validate(Brush{std::nan(""), 0.5}), Error);
}

// A frame with two planes meeting at x = 20: the normal flips there; colour, albedo and depth
// are the same on both sides (and the colour is noisy).
FrameBuffers twoPlanes(int w = 40, int h = 24) {
    FrameBuffers f(w, h);
    Image& n = f.ensure(Layer::Normal);
    Image& a = f.ensure(Layer::Albedo);
    Image& d = f.ensure(Layer::Depth);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c)
                f.color()(x, y, c) = 0.5f + 0.02f * float((x * 7 + y * 3 + c) % 5);
            n(x, y, 0) = x < 20 ? 0.0f : 1.0f;
            n(x, y, 2) = x < 20 ? 1.0f : 0.0f;
            for (int c = 0; c < 3; ++c) a(x, y, c) = 0.6f;
            d(x, y, 0) = 10.0f;
        }
    return f;
}

TEST(MagicWand, StopsAtANormalEdge) {
    const FrameBuffers f = twoPlanes();
    Image seeds(40, 24, 1, 0.0f);
    seeds(5, 5, 0) = 1.0f;
    const Image mask = magicWand(f, seeds);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 40; ++x)
            EXPECT_EQ(mask(x, y, 0), x < 20 ? 1.0f : 0.0f) << x << "," << y;
    // Without the normal test it floods everything.
    WandOptions noNormal;
    noNormal.normal = -1.0;
    const Image all = magicWand(f, seeds, noNormal);
    for (float v : all.data()) EXPECT_EQ(v, 1.0f);
}

TEST(MagicWand, StopsAtADepthEdgeAndNeverCrossesNaN) {
    FrameBuffers f = twoPlanes();
    f.layer(Layer::Normal).fill(0.0f);
    for (int y = 0; y < 24; ++y)
        for (int x = 30; x < 40; ++x) f.layer(Layer::Depth)(x, y, 0) = 20.0f;  // a step
    for (int y = 0; y < 24; ++y) f.color()(10, y, 0) = std::nanf("");          // a NaN column
    Image seeds(40, 24, 1, 0.0f);
    seeds(15, 3, 0) = 1.0f;
    const Image mask = magicWand(f, seeds);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 40; ++x)
            EXPECT_EQ(mask(x, y, 0), x > 10 && x < 30 ? 1.0f : 0.0f) << x << "," << y;
    EXPECT_THROW(magicWand(f, Image(3, 3, 1)), Error);
}

TEST(MagicWand, DoesNotLeakThroughADiagonalFeatureEdge) {
    // A one-pixel diagonal line (x = y) of another albedo: a 4-connected fill from above it
    // cannot step across, where an 8-connected one would slip between two line pixels.
    const int n = 32;
    FrameBuffers f = twoPlanes(n, n);
    f.layer(Layer::Normal).fill(0.0f);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) f.layer(Layer::Albedo)(i, i, c) = 0.1f;
    Image seeds(n, n, 1, 0.0f);
    seeds(n - 1, 0, 0) = 1.0f;
    WandOptions o;
    o.color = -1.0;  // albedo alone decides
    const Image mask = magicWand(f, seeds, o);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) EXPECT_EQ(mask(x, y, 0), x > y ? 1.0f : 0.0f) << x << "," << y;
    // With the albedo test off as well nothing bounds it.
    o.albedo = -1.0;
    const Image unbounded = magicWand(f, seeds, o);
    for (float v : unbounded.data()) EXPECT_EQ(v, 1.0f);
}

// The discrete Laplace equation at a free pixel: deg·u − Σ neighbours.
double laplaceResidual(const Image& u, int x, int y) {
    const int w = u.width(), h = u.height();
    double s = 0.0;
    int deg = 0;
    const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
    for (int k = 0; k < 4; ++k) {
        if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
        s += u(nx[k], ny[k], 0);
        ++deg;
    }
    return deg * double(u(x, y, 0)) - s;
}

// Scribbles: a disc of 1s, a line of 0s, a few scattered 1s.
void scribble(int w, int h, Image& values, Image& fixed) {
    values = Image(w, h, 1, 0.0f);
    fixed = Image(w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (std::hypot(x - 0.3 * w, y - 0.4 * h) < 0.08 * w)
                values(x, y, 0) = 1.0f, fixed(x, y, 0) = 1.0f;
            if (x == w - 5) fixed(x, y, 0) = 1.0f;
            if ((x * 31 + y * 17) % 211 == 0) values(x, y, 0) = 1.0f, fixed(x, y, 0) = 1.0f;
        }
}

TEST(Diffusion, SatisfiesTheLaplaceEquationAndKeepsTheScribbles) {
    Image values, fixed;
    scribble(96, 70, values, fixed);
    DiffusionOptions o;
    o.tolerance = 1e-8;
    const Image u = diffuseWeights(values, fixed, o);
    double worst = 0.0;
    for (int y = 0; y < 70; ++y)
        for (int x = 0; x < 96; ++x) {
            if (fixed(x, y, 0) > 0.0f) {
                EXPECT_EQ(u(x, y, 0), values(x, y, 0));  // exactly kept
                continue;
            }
            EXPECT_GE(u(x, y, 0), 0.0f);
            EXPECT_LE(u(x, y, 0), 1.0f);
            worst = std::max(worst, std::fabs(laplaceResidual(u, x, y)));
        }
    // Stated tolerance: float storage of the result limits the residual to ~1e-6.
    EXPECT_LT(worst, 1e-5);
}

TEST(Diffusion, AgreesWithEigensDirectSparseSolve) {
    // Odd sides (vector tails, odd coarsening) and enough pixels for the parallel loops and
    // four levels: 211×163 → 106×82 → 53×41 → 27×21 → 14×11.
    const int w = 211, h = 163;
    Image values, fixed;
    scribble(w, h, values, fixed);
    // The same equations for Eigen: one unknown per free pixel.
    std::vector<int> index(std::size_t(w * h), -1);
    int n = 0;
    for (int i = 0; i < w * h; ++i)
        if (fixed.data()[std::size_t(i)] == 0.0f) index[std::size_t(i)] = n++;
    std::vector<Eigen::Triplet<double>> t;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int i = index[std::size_t(y * w + x)];
            if (i < 0) continue;
            const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
            int deg = 0;
            for (int k = 0; k < 4; ++k) {
                if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h) continue;
                ++deg;
                const int j = index[std::size_t(ny[k] * w + nx[k])];
                if (j >= 0)
                    t.emplace_back(i, j, -1.0);
                else
                    b[i] += values(nx[k], ny[k], 0);
            }
            t.emplace_back(i, i, double(deg));
        }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
    ASSERT_EQ(solver.info(), Eigen::Success);
    const Eigen::VectorXd direct = solver.solve(b);
    DiffusionOptions o;
    o.tolerance = 1e-9;
    const Image u = diffuseWeights(values, fixed, o);
    double worst = 0.0;
    for (int p = 0; p < w * h; ++p)
        if (index[std::size_t(p)] >= 0)
            worst = std::max(worst,
                             std::fabs(u.data()[std::size_t(p)] - direct[index[std::size_t(p)]]));
    EXPECT_LT(worst, 1e-6);  // float output of a 1e-9 relative residual
}

TEST(Diffusion, LinearBetweenTwoFixedColumnsWithZeroFluxBorders) {
    // Left column 0, right column 1, free top and bottom borders (zero flux): the harmonic
    // function is x / (w − 1), on a grid that coarsens (200×120) and on a single row.
    for (const auto& [w, h] : {std::pair{200, 120}, std::pair{50, 1}}) {
        Image values(w, h, 1, 0.0f), fixed(w, h, 1, 0.0f);
        for (int y = 0; y < h; ++y) {
            fixed(0, y, 0) = fixed(w - 1, y, 0) = 1.0f;
            values(w - 1, y, 0) = 1.0f;
        }
        DiffusionOptions o;
        o.tolerance = 1e-9;
        const Image u = diffuseWeights(values, fixed, o);
        double worst = 0.0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                worst = std::max(worst, std::fabs(u(x, y, 0) - double(x) / double(w - 1)));
        EXPECT_LT(worst, 1e-6) << w << "x" << h;
    }
}

TEST(Diffusion, SameResultForAnyThreadCount) {
    // Rows are independent and sums are added in row order: no thread count changes a bit.
    Image values, fixed;
    scribble(256, 160, values, fixed);
    Image one, many;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = diffuseWeights(values, fixed);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 3);
        many = diffuseWeights(values, fixed);
    }
    ASSERT_TRUE(one.sameShape(many));
    EXPECT_EQ(std::memcmp(one.data().data(), many.data().data(), one.data().size_bytes()), 0);
}

TEST(Diffusion, EdgeCasesAndBadInput) {
    // All zeros fixed: the solution is 0; everything fixed: unchanged.
    Image values(16, 16, 1, 0.7f), fixed(16, 16, 1, 0.0f);
    fixed(3, 3, 0) = 1.0f;
    values(3, 3, 0) = 0.0f;
    const Image zeros = diffuseWeights(values, fixed);
    for (float v : zeros.data()) EXPECT_EQ(v, 0.0f);
    // One fixed value 1: constant 1 everywhere (zero-flux borders).
    values(3, 3, 0) = 1.0f;
    const Image ones = diffuseWeights(values, fixed);
    for (float v : ones.data()) EXPECT_NEAR(v, 1.0f, 1e-5);
    EXPECT_THROW(diffuseWeights(values, Image(16, 16, 1, 0.0f)), Error);  // nothing fixed
    EXPECT_THROW(diffuseWeights(values, Image(8, 8, 1, 1.0f)), Error);    // sizes differ
    // A stop from the progress callback.
    Image v2, f2;
    scribble(64, 64, v2, f2);
    EXPECT_THROW(diffuseWeights(v2, f2, {}, [](double) { return false; }), Error);
}

}  // namespace
}  // namespace glint::denoise
