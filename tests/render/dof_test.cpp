// Depth of field: the blur of an out-of-focus edge matches the thin-lens circle of confusion.
//
// Thin lens (PBR 6.2.3) with lens radius A focused at depth z_f: a point at depth z is seen
// through lens point l at image-plane (tangent) position s + l (1/z − 1/z_f), so it spreads
// over a disc of radius A |1/z − 1/z_f| in tangent units. On a film of height H pixels and
// vertical field of view fovY, one tangent unit is H / (2 tan(fovY/2)) pixels, hence
//   CoC diameter [pixels] = 2A · |z − z_f| / (z · z_f) · H / (2 tan(fovY/2))
// (= aperture 2A × |z − z_f| / z × focal scale H / (2 tan(fovY/2) z_f)).
// A straight edge is therefore blurred into the marginal CDF of a uniform disc of radius
// R = CoC/2: F(u) = 1/2 + (u √(1−u²) + asin u)/π with u = offset / R (lens samples are uniform
// on the disc: concentric mapping), and a box pixel filter averages F over each pixel.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

constexpr int kWidth = 64, kHeight = 32;
constexpr double kLensRadius = 1.0, kFocus = 2.0;

/// Marginal CDF of x over the uniform unit disc.
double discCdf(double u) {
    if (u <= -1.0) return 0.0;
    if (u >= 1.0) return 1.0;
    return 0.5 + (u * std::sqrt(1.0 - u * u) + std::asin(u)) / std::numbers::pi;
}

/// Analytic edge profile of pixel column x: F((px − centre)/R) averaged over px ∈ [x, x+1].
double expectedProfile(int x, double radius) {
    const int n = 2000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double px = x + (i + 0.5) / n - 0.5 * kWidth;
        sum += radius > 0.0 ? discCdf(px / radius) : (px > 0.0 ? 1.0 : 0.0);
    }
    return sum / n;
}

/// 10–90 % width of a rising profile sampled at pixel centres, by linear interpolation.
double width1090(const std::vector<double>& profile) {
    auto crossing = [&](double level) {
        for (std::size_t x = 1; x < profile.size(); ++x)
            if (profile[x - 1] < level && profile[x] >= level)
                return double(x - 1) + (level - profile[x - 1]) / (profile[x] - profile[x - 1]);
        return -1.0;
    };
    return crossing(0.9) - crossing(0.1);
}

struct EdgeRender {
    std::vector<double> profile;   ///< row-averaged albedo per column
    std::vector<double> variance;  ///< variance of that average
};

/// Renders a white half-plane X ≥ 0 at depth z (edge through the image centre) through a thin
/// lens of radius kLensRadius focused at kFocus, fovY = 90°, and averages the albedo over rows.
EdgeRender renderEdge(double z, int spp) {
    test::TempDir dir("dof");
    const std::string d = std::to_string(-z), big = std::to_string(4.0 * z);
    dir.write("half.obj", "v 0 -" + big + " " + d + "\nv " + big + " -" + big + " " + d + "\nv " +
                              big + " " + big + " " + d + "\nv 0 " + big + " " + d +
                              "\nf 1 2 3 4\n");
    Renderer renderer(loadScene(dir.write("scene.json", R"({
      "camera": {"position": [0, 0, 0], "lookAt": [0, 0, -1], "fovY": 90,
                 "lensRadius": )" + std::to_string(kLensRadius) +
                                                            R"(, "focusDistance": )" +
                                                            std::to_string(kFocus) + R"(},
      "film": {"width": 64, "height": 32},
      "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
      "shapes": [{"obj": "half.obj", "material": "white"}],
      "render": {"maxDepth": 1}
    })")));
    Settings s = renderer.scene().settings();
    s.spp = spp;
    const FrameBuffers f = renderer.render(s).frame;
    EdgeRender out;
    for (int x = 0; x < kWidth; ++x) {
        double sum = 0.0, var = 0.0;
        for (int y = 0; y < kHeight; ++y) {
            sum += f.layer(Layer::Albedo)(x, y, 0);
            var += f.layer(Layer::AlbedoVariance)(x, y, 0);
        }
        out.profile.push_back(sum / kHeight);
        out.variance.push_back(var / (double(kHeight) * kHeight));
    }
    return out;
}

/// CoC diameter in pixels (see the file comment).
double cocPixels(double z) {
    const double pixelsPerTangent = kHeight / (2.0 * std::tan(0.25 * std::numbers::pi));
    return 2.0 * kLensRadius * std::abs(z - kFocus) / (z * kFocus) * pixelsPerTangent;
}

TEST(DepthOfField, OutOfFocusEdgeMatchesCircleOfConfusion) {
    // Behind the focus plane (z = 4: CoC 8 px) and in front of it (z = 1.5: CoC ≈ 5.3 px).
    for (double z : {4.0, 1.5}) {
        const double radius = 0.5 * cocPixels(z);
        const EdgeRender r = renderEdge(z, 64);
        std::vector<double> expected;
        for (int x = 0; x < kWidth; ++x) {
            expected.push_back(expectedProfile(x, radius));
            // 5 standard errors of the row average (film variance of the mean; stratification
            // makes the true error smaller) plus 1e-3 for the float film and lens mapping.
            EXPECT_NEAR(r.profile[std::size_t(x)], expected.back(),
                        5.0 * std::sqrt(r.variance[std::size_t(x)]) + 1e-3)
                << "z " << z << " column " << x;
        }
        // The 10–90 % width of the rendered edge matches that of the analytic profile to a
        // quarter pixel, and both are near the disc's own 10–90 % width 2 u₉₀ R (u₉₀ ≈ 0.69, the
        // root of F(u) = 0.9), widened by at most the one-pixel box filter.
        const double measured = width1090(r.profile), analytic = width1090(expected);
        EXPECT_NEAR(measured, analytic, 0.25) << "z " << z;
        double lo = 0.0, hi = 1.0;
        for (int i = 0; i < 60; ++i) (discCdf(0.5 * (lo + hi)) < 0.9 ? lo : hi) = 0.5 * (lo + hi);
        const double disc = 2.0 * lo * radius;
        EXPECT_GT(measured, disc - 0.25) << "z " << z;
        EXPECT_LT(measured, disc + 1.0) << "z " << z;
    }
}

TEST(DepthOfField, InFocusEdgeStaysSharp) {
    // At the focus distance the CoC is 0: only the pixel containing the edge is partial.
    const EdgeRender r = renderEdge(kFocus, 16);
    for (int x = 0; x < kWidth; ++x)
        EXPECT_NEAR(r.profile[std::size_t(x)], expectedProfile(x, 0.0), 1e-3) << "column " << x;
}

}  // namespace
}  // namespace glint::render
