// Tests of glint/image/metrics.h: hand-computed values, scikit-image reference values, crops,
// error maps, non-finite pixels and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>

#include "glint/image/error.h"
#include "glint/image/image.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

using namespace glint;

namespace {

constexpr double kC1 = 0.01 * 0.01;  // (K1 L)^2, Wang et al. 2004
constexpr double kC2 = 0.03 * 0.03;  // (K2 L)^2

Image filled(int w, int h, int c, const std::function<double(int, int, int)>& f) {
    Image im(w, h, c);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int ch = 0; ch < c; ++ch) im(x, y, ch) = float(f(x, y, ch));
    return im;
}

MetricOptions linearOptions() {
    MetricOptions o;
    o.linear = true;
    return o;
}

/// SSIM of two constant images a, b (all local variances 0): Wang et al. 2004, eq. 13 with
/// sigma_x = sigma_y = sigma_xy = 0 gives (2ab + C1) / (a^2 + b^2 + C1) * C2 / C2.
double constantSsim(double a, double b) {
    return (2 * a * b + kC1) / (a * a + b * b + kC1);
}

/// Expects `f` to throw glint::Error of `kind` whose message contains every one of `parts`.
void expectError(const std::function<void()>& f, ErrorKind kind,
                 std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no glint::Error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), kind) << e.what();
        for (const std::string& part : parts)
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
                << "'" << e.what() << "' lacks '" << part << "'";
    }
}

}  // namespace

TEST(Metrics, IdenticalImages) {
    const Image a =
        filled(17, 14, 3, [](int x, int y, int c) { return 0.1 * ((x + 2 * y + c) % 7); });
    EXPECT_EQ(mse(a, a).value, 0.0);
    EXPECT_EQ(relMse(a, a).value, 0.0);
    const MetricResult p = psnr(a, a);
    EXPECT_TRUE(std::isinf(p.value) && p.value > 0) << p.value;
    EXPECT_DOUBLE_EQ(ssim(a, a).value, 1.0);
    EXPECT_DOUBLE_EQ(ssim(a, a, linearOptions()).value, 1.0);
    EXPECT_EQ(ssim(a, a).pixels, 17u * 14u);
    EXPECT_EQ(ssim(a, a).nonFinitePixels, 0u);
}

TEST(Metrics, ConstantOffset) {
    // Every channel differs by 0.25 (exact in float): MSE 0.0625, PSNR -10 log10(0.0625),
    // relMSE 0.0625 / (0.5^2 + 0.01).
    const Image ref(12, 12, 3, 0.5f);
    const Image img(12, 12, 3, 0.75f);
    EXPECT_DOUBLE_EQ(mse(img, ref).value, 0.0625);
    EXPECT_NEAR(psnr(img, ref).value, 12.041199826559248, 1e-12);
    EXPECT_NEAR(relMse(img, ref).value, 0.0625 / 0.26, 1e-15);
    EXPECT_EQ(mse(img, ref).pixels, 144u);
    // relMSE is not symmetric: the denominator uses the reference.
    EXPECT_NEAR(relMse(ref, img).value, 0.0625 / (0.5625 + 0.01), 1e-15);
}

TEST(Metrics, SsimOfConstantImagesMatchesTheFormula) {
    const Image ref(13, 11, 2, 0.5f);
    const Image img(13, 11, 2, 0.75f);
    // Linear values: (2 * 0.75 * 0.5 + C1) / (0.75^2 + 0.5^2 + C1) = 0.7501 / 0.8126.
    EXPECT_NEAR(ssim(img, ref, linearOptions()).value, 0.7501 / 0.8126, 1e-12);
    EXPECT_NEAR(constantSsim(0.75, 0.5), 0.7501 / 0.8126, 1e-15);
    // Display values (default): the same formula on sRGB-encoded values.
    EXPECT_NEAR(ssim(img, ref).value, constantSsim(srgbEncode(0.75f), srgbEncode(0.5f)), 1e-12);
    // Exposure +1 stop clamps both to 1, so they become identical.
    MetricOptions bright;
    bright.exposure = 1.0f;
    EXPECT_NEAR(ssim(img, ref, bright).value, 1.0, 1e-12);
    // Exposure -2 stops: 0.1875 vs 0.125 before encoding.
    MetricOptions dark;
    dark.exposure = -2.0f;
    EXPECT_NEAR(ssim(img, ref, dark).value, constantSsim(srgbEncode(0.1875f), srgbEncode(0.125f)),
                1e-12);
}

TEST(Metrics, DisplayModeIsSsimOfEncodedValues) {
    // Values in [0, 3] so that the clamp matters; exposure -1 stop.
    const Image ref =
        filled(20, 16, 3, [](int x, int y, int c) { return 0.1 * ((x * 3 + y * 5 + c) % 31); });
    const Image img =
        filled(20, 16, 3, [](int x, int y, int c) { return 0.1 * ((x * 7 + y * 2 + c) % 29); });
    MetricOptions options;
    options.exposure = -1.0f;
    auto encode = [](const Image& im) {
        Image out = im;
        for (float& v : out.data()) v = srgbEncode(std::clamp(v * 0.5f, 0.0f, 1.0f));
        return out;
    };
    EXPECT_NEAR(ssim(img, ref, options).value,
                ssim(encode(img), encode(ref), linearOptions()).value, 1e-12);
    // MSE-type metrics ignore the display options: always linear values.
    EXPECT_EQ(mse(img, ref, options).value, mse(img, ref).value);
}

// Values computed once with scikit-image 0.19.3 (Debian bookworm python3-skimage) by
//   /usr/bin/python3 lab/bench/ssim_skimage.py --test-values
// i.e. structural_similarity(a, b, gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=1, channel_axis=2[, full=True]) on float64 copies of
// these float32 images (same integer formulas there). Glint agreed to about 1e-15 when they were
// pasted; the map is stored as float, hence 1e-6 for it. The mean skips the 5-pixel border, so
// only the map values check the mirrored extension ("c b a | a b c").
struct SkimageValues {
    double ssim;     ///< the mean SSIM
    double mapMean;  ///< mean of the full map (mean over channels), border included
    double map00;    ///< map at pixel (0, 0)
    double mapEdge;  ///< map at pixel (width - 1, 2)
};

void expectSkimageAgreement(const Image& a, const Image& b, const SkimageValues& expected) {
    const MetricOptions lin = linearOptions();
    EXPECT_NEAR(ssim(a, b, lin).value, expected.ssim, 1e-9);
    const Image map = ssimMap(a, b, lin);
    double sum = 0;
    for (float v : map.data()) sum += v;
    EXPECT_NEAR(sum / double(map.pixelCount()), expected.mapMean, 1e-6);
    EXPECT_NEAR(map(0, 0, 0), expected.map00, 1e-6);
    EXPECT_NEAR(map(a.width() - 1, 2, 0), expected.mapEdge, 1e-6);
}

TEST(Metrics, SsimAgreesWithScikitImage) {
    expectSkimageAgreement(
        filled(16, 13, 3,
               [](int x, int y, int c) { return ((7 * x + 13 * y + 5 * c) % 17) / 16.0; }),
        filled(16, 13, 3,
               [](int x, int y, int c) { return ((3 * x + 11 * y + 7 * c) % 19) / 18.0; }),
        {0.1684991195670463, -0.054675343906655863, -0.11447021758575682, -0.24409137622684526});

    auto ramp = [](int x, int y) { return (x + 2 * y) / 40.0; };
    expectSkimageAgreement(
        filled(12, 20, 1, [&](int x, int y, int) { return ramp(x, y); }),
        filled(12, 20, 1,
               [&](int x, int y, int) { return ramp(x, y) + ((x * y + 3) % 5 - 2) / 50.0; }),
        {0.95628805972226905, 0.94828595336156785, 0.90413141544701137, 0.93781734075571344});

    // The smallest accepted size: only the centre pixel is averaged.
    expectSkimageAgreement(
        filled(11, 11, 2, [](int x, int y, int c) { return ((x * x + 3 * y + c) % 11) / 10.0; }),
        filled(11, 11, 2,
               [](int x, int y, int c) { return ((y * y + 2 * x + 4 * c) % 13) / 12.0; }),
        {0.0026170582909328943, 0.04766391971253691, 0.56966180018387824, 0.078841015920532442});
}

/// Direct (non-separable) evaluation of the definition in docs/metrics.md for one channel at
/// pixel (px, py): 11x11 Gaussian window, sigma 1.5, mirrored "c b a | a b c" extension.
double directSsim(const Image& a, const Image& b, int c, int px, int py) {
    auto mirror = [](int i, int n) { return i < 0 ? -1 - i : (i >= n ? 2 * n - 1 - i : i); };
    double g[11], norm = 0;
    for (int k = -5; k <= 5; ++k) norm += g[k + 5] = std::exp(-k * k / 4.5);
    double ux = 0, uy = 0, uxx = 0, uyy = 0, uxy = 0;
    for (int dy = -5; dy <= 5; ++dy)
        for (int dx = -5; dx <= 5; ++dx) {
            const double w = g[dx + 5] * g[dy + 5] / (norm * norm);
            const int x = mirror(px + dx, a.width());
            const int y = mirror(py + dy, a.height());
            const double u = a(x, y, c), v = b(x, y, c);
            ux += w * u;
            uy += w * v;
            uxx += w * u * u;
            uyy += w * v * v;
            uxy += w * u * v;
        }
    const double vx = uxx - ux * ux, vy = uyy - uy * uy, vxy = uxy - ux * uy;
    return (2 * ux * uy + kC1) * (2 * vxy + kC2) / ((ux * ux + uy * uy + kC1) * (vx + vy + kC2));
}

TEST(Metrics, SsimMatchesDirectDefinition) {
    // Tall enough that the kernel splits the rows into several parallel bands.
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const Image a = filled(23, 90, 2, [&](int, int, int) { return u(rng); });
    const Image b =
        filled(23, 90, 2, [&](int x, int y, int c) { return 0.5 * a(x, y, c) + 0.5 * u(rng); });
    const Image map = ssimMap(a, b, linearOptions());
    double sum = 0;
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < 23; ++x) {
            const double d = 0.5 * (directSsim(a, b, 0, x, y) + directSsim(a, b, 1, x, y));
            EXPECT_NEAR(map(x, y, 0), d, 1e-6) << "pixel " << x << "," << y;
            if (x >= 5 && x < 23 - 5 && y >= 5 && y < 90 - 5) sum += d;
        }
    EXPECT_NEAR(ssim(a, b, linearOptions()).value, sum / (13 * 80), 1e-12);
}

TEST(Metrics, GaussianNoise) {
    // Reference 0.5 everywhere, image = reference + N(0, s^2), s = 0.01, 256x256x3, seed 1.
    constexpr int n = 256;
    constexpr double s = 0.01;
    const Image ref(n, n, 3, 0.5f);
    std::mt19937 rng(1);
    std::normal_distribution<double> noise(0.0, s);
    const Image img = filled(n, n, 3, [&](int, int, int) { return 0.5 + noise(rng); });

    // MSE estimates s^2 from N = 196608 squares: sd = s^2 sqrt(2 / N) = 0.32% of s^2; allow 5 sd.
    const double N = double(n) * n * 3;
    const double mseTol = 5 * s * s * std::sqrt(2 / N);
    EXPECT_NEAR(mse(img, ref).value, s * s, mseTol);
    EXPECT_NEAR(relMse(img, ref).value, s * s / 0.26, mseTol / 0.26);
    // PSNR = -10 log10(MSE): d PSNR = 10 / ln 10 * d MSE / MSE.
    EXPECT_NEAR(psnr(img, ref).value, 40.0, 10 / std::log(10.0) * mseTol / (s * s));

    // SSIM: the reference has no local variance, so per pixel SSIM = l * C2 / (V + C2) where
    // V = x^T A x is the window's weighted variance of the noise, A = diag(w) - w w^T for the
    // 121 2D Gaussian weights w: E[V] = s^2 tr A, Var[V] = 2 s^4 tr A^2 (Gaussian quadratic
    // form). Second-order expansion: E[C2 / (V + C2)] = f(m) + C2 Var[V] / (m + C2)^3
    // with m = E[V]; l = 1 - E[(mu_x - 0.5)^2] / 0.5 differs from 1 by < 1e-5.
    // The map is correlated over the window, so the mean over 246^2 x 3 pixels is noisier than
    // independent pixels would be: over seeds 1..20 the difference from `expected` had standard
    // deviation 2.3e-4 and mean -1.2e-4 (the higher-order terms); allow 1.5e-3 (> 6 sd). The
    // scikit-image test above is the precise check; this one checks the statistics.
    double w1[11], sum = 0;
    for (int k = -5; k <= 5; ++k) sum += w1[k + 5] = std::exp(-k * k / (2 * 1.5 * 1.5));
    double sumW2 = 0, sumW3 = 0;
    for (double a : w1)
        for (double b : w1) {
            const double w = a * b / (sum * sum);
            sumW2 += w * w;
            sumW3 += w * w * w;
        }
    const double trA = 1 - sumW2;
    const double trA2 = sumW2 - 2 * sumW3 + sumW2 * sumW2;
    const double m = s * s * trA;
    const double varV = 2 * s * s * s * s * trA2;
    const double expected = kC2 / (m + kC2) + kC2 * varV / std::pow(m + kC2, 3);
    EXPECT_NEAR(ssim(img, ref, linearOptions()).value, expected, 1.5e-3);
}

TEST(Metrics, CropEqualsMetricOfCroppedImages) {
    const Image ref =
        filled(40, 30, 3, [](int x, int y, int c) { return 0.02 * ((x + y * 3 + c) % 40); });
    const Image img =
        filled(40, 30, 3, [](int x, int y, int c) { return 0.02 * ((x * 5 + y + c) % 45); });
    const Rect rect{5, 31, 3, 20};
    MetricOptions options;
    options.crop = rect;
    const Image ci = img.crop(rect);
    const Image cr = ref.crop(rect);
    EXPECT_EQ(mse(img, ref, options).value, mse(ci, cr).value);
    EXPECT_EQ(relMse(img, ref, options).value, relMse(ci, cr).value);
    EXPECT_EQ(psnr(img, ref, options).value, psnr(ci, cr).value);
    EXPECT_EQ(ssim(img, ref, options).value, ssim(ci, cr).value);
    EXPECT_EQ(mse(img, ref, options).pixels, std::size_t(26 * 17));
    EXPECT_NE(ssim(img, ref, options).value, ssim(img, ref).value);
    const Image map = ssimMap(img, ref, options);
    EXPECT_EQ(map.width(), 26);
    EXPECT_EQ(map.height(), 17);

    // An error outside the crop does not count.
    Image spot = ref;
    spot(0, 0, 1) = 5.0f;
    MetricOptions inside;
    inside.crop = Rect{1, 40, 1, 30};
    EXPECT_EQ(mse(spot, ref, inside).value, 0.0);
    EXPECT_NEAR(mse(spot, ref).value, (5.0 - ref(0, 0, 1)) * (5.0 - ref(0, 0, 1)) / (40 * 30 * 3),
                1e-12);
}

TEST(Metrics, ErrorMaps) {
    Image ref(3, 2, 2, 1.0f);
    Image img(3, 2, 2, 1.0f);
    img(1, 0, 0) = 1.5f;  // |d| = 0.5 in one of two channels
    img(2, 1, 0) = 0.0f;  // |d| = 1 and ...
    img(2, 1, 1) = 3.0f;  // ... |d| = 2
    const Image abs = absErrorMap(img, ref);
    ASSERT_EQ(abs.channels(), 1);
    ASSERT_EQ(abs.width(), 3);
    ASSERT_EQ(abs.height(), 2);
    EXPECT_FLOAT_EQ(abs(0, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(abs(1, 0, 0), 0.25f);
    EXPECT_FLOAT_EQ(abs(2, 1, 0), 1.5f);
    // Relative map: mean over channels of (x - r)^2 / (r^2 + 0.01); r = 1.
    const Image rel = relErrorMap(img, ref);
    EXPECT_FLOAT_EQ(rel(1, 0, 0), float(0.25 / 1.01 / 2));
    EXPECT_FLOAT_EQ(rel(2, 1, 0), float((1.0 + 4.0) / 1.01 / 2));
    // Its mean is relMSE.
    double mean = 0;
    for (float v : rel.data()) mean += v;
    EXPECT_NEAR(mean / 6, relMse(img, ref).value, 1e-7);
    // Crop.
    MetricOptions options;
    options.crop = Rect{1, 3, 1, 2};
    const Image part = absErrorMap(img, ref, options);
    ASSERT_EQ(part.width(), 2);
    ASSERT_EQ(part.height(), 1);
    EXPECT_FLOAT_EQ(part(1, 0, 0), 1.5f);
}

TEST(Metrics, SsimMap) {
    const Image ref =
        filled(24, 18, 3, [](int x, int y, int c) { return 0.03 * ((x * 2 + y * 3 + c) % 30); });
    const Image img =
        filled(24, 18, 3, [](int x, int y, int c) { return 0.03 * ((x + y * 4 + 2 * c) % 31); });
    const Image map = ssimMap(img, ref, linearOptions());
    ASSERT_EQ(map.width(), 24);
    ASSERT_EQ(map.height(), 18);
    ASSERT_EQ(map.channels(), 1);
    // The SSIM value is the mean of the map over pixels at least 5 from every border.
    double sum = 0;
    for (int y = 5; y < 18 - 5; ++y)
        for (int x = 5; x < 24 - 5; ++x) sum += map(x, y, 0);
    EXPECT_NEAR(sum / (14 * 8), ssim(img, ref, linearOptions()).value, 1e-6);
    // Constant images: every pixel, border included, has the constant-image value.
    const Image c = ssimMap(Image(12, 11, 1, 0.75f), Image(12, 11, 1, 0.5f), linearOptions());
    for (float v : c.data()) EXPECT_NEAR(v, constantSsim(0.75, 0.5), 1e-6);
    const Image same = ssimMap(img, img);
    for (float v : same.data()) EXPECT_FLOAT_EQ(v, 1.0f);
}

TEST(Metrics, NonFinitePixels) {
    const Image ref =
        filled(16, 12, 3, [](int x, int y, int c) { return 0.05 * ((x + y + c) % 20); });
    Image img =
        filled(16, 12, 3, [](int x, int y, int c) { return 0.05 * ((x + 2 * y + c) % 20); });
    Image badRef = ref;
    img(3, 4, 1) = std::numeric_limits<float>::quiet_NaN();
    badRef(7, 8, 2) = std::numeric_limits<float>::infinity();
    badRef(3, 4, 0) = -std::numeric_limits<float>::infinity();  // same pixel as the NaN

    // MSE-type: the two pixels are counted and left out of the mean.
    const MetricResult m = mse(img, badRef);
    EXPECT_EQ(m.nonFinitePixels, 2u);
    EXPECT_EQ(m.pixels, 16u * 12u);
    double sum = 0;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 16; ++x) {
            if ((x == 3 && y == 4) || (x == 7 && y == 8)) continue;
            for (int c = 0; c < 3; ++c) sum += std::pow(double(img(x, y, c)) - ref(x, y, c), 2);
        }
    EXPECT_NEAR(m.value, sum / (190 * 3), 1e-12);
    EXPECT_TRUE(std::isfinite(psnr(img, badRef).value));
    EXPECT_EQ(relMse(img, badRef).nonFinitePixels, 2u);

    // SSIM: only the non-finite values are replaced by 0; finite channels are kept.
    Image zi = img;
    Image zr = badRef;
    zi(3, 4, 1) = 0.0f;
    zr(7, 8, 2) = 0.0f;
    zr(3, 4, 0) = 0.0f;
    const MetricResult s = ssim(img, badRef);
    EXPECT_EQ(s.nonFinitePixels, 2u);
    EXPECT_EQ(s.value, ssim(zi, zr).value);
    const Image map = ssimMap(img, badRef);
    for (float v : map.data()) EXPECT_TRUE(std::isfinite(v));

    // Maps mark those pixels NaN.
    const Image abs = absErrorMap(img, badRef);
    EXPECT_TRUE(std::isnan(abs(3, 4, 0)));
    EXPECT_TRUE(std::isnan(abs(7, 8, 0)));
    EXPECT_FALSE(std::isnan(abs(8, 8, 0)));
    EXPECT_TRUE(std::isnan(relErrorMap(img, badRef)(7, 8, 0)));

    // Nothing finite left: a Numeric error.
    const Image nan(4, 4, 1, std::numeric_limits<float>::quiet_NaN());
    expectError([&] { mse(nan, Image(4, 4, 1)); }, ErrorKind::Numeric, {"16 pixels", "NaN/Inf"});
}

TEST(Metrics, BadInput) {
    const Image a(16, 13, 3, 0.5f);
    const Image b(16, 12, 3, 0.5f);
    for (Metric metric : {Metric::Mse, Metric::RelMse, Metric::Psnr, Metric::Ssim})
        expectError([&] { computeMetric(metric, a, b); }, ErrorKind::InvalidArgument,
                    {"16x13x3", "16x12x3", metricName(metric)});
    expectError([&] { absErrorMap(a, Image(16, 13, 1)); }, ErrorKind::InvalidArgument, {"16x13x1"});
    expectError([&] { ssimMap(Image(), Image()); }, ErrorKind::InvalidArgument, {"empty"});

    MetricOptions outside;
    outside.crop = Rect{10, 17, 0, 13};
    expectError([&] { mse(a, a, outside); }, ErrorKind::InvalidArgument, {"10,17,0,13", "16x13"});
    expectError([&] { relErrorMap(a, a, outside); }, ErrorKind::InvalidArgument, {"crop"});
    MetricOptions empty;
    empty.crop = Rect{3, 3, 0, 5};
    expectError([&] { psnr(a, a, empty); }, ErrorKind::InvalidArgument, {"crop"});

    // SSIM needs its 11x11 window inside the image or crop (as scikit-image does).
    expectError([&] { ssim(Image(10, 40, 3), Image(10, 40, 3)); }, ErrorKind::InvalidArgument,
                {"11x11", "10x40"});
    MetricOptions small;
    small.crop = Rect{0, 16, 0, 10};
    expectError([&] { ssimMap(a, a, small); }, ErrorKind::InvalidArgument, {"11x11", "16x10"});
    MetricOptions badExposure;
    badExposure.exposure = std::numeric_limits<float>::infinity();
    expectError([&] { ssim(a, a, badExposure); }, ErrorKind::InvalidArgument, {"exposure"});
}

TEST(Metrics, TinyImagesAndTheEndsOfTheFloatRange) {
    // 1×1 and 1×N: the pixel metrics work, SSIM asks for its 11×11 window.
    for (auto [w, h] : {std::pair{1, 1}, std::pair{1, 40}, std::pair{40, 1}}) {
        const Image a(w, h, 3, 0.5f), b(w, h, 3, 0.6f);
        EXPECT_NEAR(mse(a, b).value, 0.01, 1e-7);
        EXPECT_TRUE(std::isfinite(psnr(a, b).value));
        EXPECT_TRUE(std::isfinite(relMse(a, b).value));
        EXPECT_THROW(ssim(a, b), Error);
    }
    // Accumulated in double: 1e30 values (squares 1e60, past float) and 1e-30 values (squares
    // below the smallest float) give the exact relative error: 1 % off is relMSE
    // 1e-4 / (1 + 0.01 / r²), r the reference (pbrt's 0.01 guards dark pixels).
    for (float scale : {1e-30f, 1.0f, 1e30f}) {
        const Image ref(32, 32, 3, 1.0f * scale), img(32, 32, 3, 1.01f * scale);
        const double r = relMse(img, ref).value;
        const double reference = double(1.0f * scale);
        EXPECT_NEAR(r, 1e-4 / (1.0 + 0.01 / (reference * reference)), 1e-8 + 1e-4 * r) << scale;
        EXPECT_TRUE(std::isfinite(mse(img, ref).value)) << scale;
        EXPECT_NEAR(ssim(img, img).value, 1.0, 1e-12) << scale;
    }
}

TEST(Metrics, Names) {
    for (Metric metric : {Metric::Mse, Metric::RelMse, Metric::Psnr, Metric::Ssim})
        EXPECT_EQ(parseMetric(metricName(metric)), metric);
    EXPECT_EQ(parseMetric("SSIM"), Metric::Ssim);
    EXPECT_STREQ(metricName(Metric::RelMse), "relmse");
    expectError([] { parseMetric("lpips"); }, ErrorKind::InvalidArgument, {"lpips", "flip-hdr"});
    const Image a(11, 11, 1, 0.25f);
    const Image b(11, 11, 1, 0.5f);
    EXPECT_EQ(computeMetric(Metric::Mse, a, b).value, 0.0625);
    EXPECT_EQ(computeMetric(Metric::Ssim, a, b).value, ssim(a, b).value);
}
