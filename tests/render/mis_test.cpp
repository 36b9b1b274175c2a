// MIS consistency on a small Veach-style glossy-plates scene: four glossy strips of increasing
// roughness reflect four spherical lights of increasing size and equal power.
// - Agreement in expectation: for every pair of estimators (power, balance, none+bsdf,
//   none+light) the difference of image means, divided by the standard error estimated from the
//   variance-of-the-mean buffers, must satisfy |z| < 5 (two-sided p ≈ 6e-7 under normality),
//   per channel.
// - Efficiency: at equal spp the estimated MSE of the image (sum over pixels of the variance of
//   the mean) of power and balance is below that of either single strategy.
#include <gtest/gtest.h>

#include <map>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

struct Estimate {
    double mean[3] = {};
    double varianceOfMean[3] = {};
    double mse = 0.0;  // Σ over pixels and channels of the variance of the mean
};

Estimate summarise(const FrameBuffers& f) {
    Estimate e;
    const Image& c = f.color();
    const Image& v = f.layer(Layer::Variance);
    const double n = double(c.pixelCount());
    for (int y = 0; y < c.height(); ++y)
        for (int x = 0; x < c.width(); ++x)
            for (int k = 0; k < 3; ++k) {
                e.mean[k] += c(x, y, k) / n;
                e.varianceOfMean[k] += v(x, y, k) / (n * n);
                e.mse += v(x, y, k);
            }
    return e;
}

std::string glossyScene() {
    std::string lights;
    const float radii[4] = {0.1f, 0.25f, 0.5f, 1.0f};
    std::string materials;
    std::string shapes;
    for (int i = 0; i < 4; ++i) {
        const float r = radii[i];
        const float le = 1.0f / (r * r);  // equal power
        materials += ",\"light" + std::to_string(i) +
                     "\": {\"type\": \"diffuse\", \"albedo\": [0,0,0], " + "\"emission\": [" +
                     std::to_string(le) + ", " + std::to_string(le * 0.8f) + ", " +
                     std::to_string(le * 0.6f) + "]}";
        shapes += ",{\"obj\": \"sphere.obj\", \"material\": \"light" + std::to_string(i) +
                  "\", \"transform\": {\"scale\": " + std::to_string(r) + ", \"translate\": [" +
                  std::to_string(-3.0f + 2.0f * i) + ", 3, -6]}}";
    }
    const float roughness[4] = {0.15f, 0.3f, 0.5f, 0.8f};
    for (int i = 0; i < 4; ++i) {
        materials +=
            ",\"plate" + std::to_string(i) +
            "\": {\"type\": \"conductor\", \"roughness\": " + std::to_string(roughness[i]) +
            ", \"specular\": [0.9, 0.9, 0.9]}";
        shapes += ",{\"obj\": \"quad.obj\", \"material\": \"plate" + std::to_string(i) +
                  "\", \"transform\": {\"scale\": [4, 1, 0.45], \"rotate\": [" +
                  std::to_string(-4.0f + 3.0f * i) + ", [1, 0, 0]], \"translate\": [0, " +
                  std::to_string(-0.3f * i) + ", " + std::to_string(-1.5f + 1.0f * i) + "]}}";
    }
    return R"({
      "camera": {"position": [0, 3, 6], "lookAt": [0, -0.4, -0.3], "fovY": 38},
      "film": {"width": 48, "height": 32},
      "materials": {"dummy": {"type": "diffuse"})" +
           materials + R"(},
      "shapes": [)" +
           shapes.substr(1) +
           R"(],
      "render": {"spp": 64, "maxDepth": 4, "seed": 17}
    })";
}

TEST(Mis, EstimatorsAgreeAndMisWins) {
    test::TempDir dir("glossy");
    dir.write("sphere.obj", test::sphereObj(1.0f, 8, 16));
    dir.write("quad.obj", test::quadObj());
    Renderer renderer(parseScene(glossyScene(), dir.path() / "scene.json"));
    std::map<std::string, Estimate> estimates;
    for (const test::MisMode& m : test::kMisModes) {
        Settings s = renderer.scene().settings();
        s.mis = m.mis;
        s.strategy = m.strategy;
        estimates[m.name] = summarise(renderer.render(s).frame);
    }
    for (auto a = estimates.begin(); a != estimates.end(); ++a)
        for (auto b = std::next(a); b != estimates.end(); ++b)
            for (int k = 0; k < 3; ++k) {
                const double se =
                    std::sqrt(a->second.varianceOfMean[k] + b->second.varianceOfMean[k]);
                const double z = (a->second.mean[k] - b->second.mean[k]) / se;
                EXPECT_LT(std::abs(z), 5.0)
                    << a->first << " vs " << b->first << " channel " << k << ": "
                    << a->second.mean[k] << " vs " << b->second.mean[k] << " (se " << se << ")";
            }
    EXPECT_GT(estimates["power"].mean[0], 0.01) << "the plates reflect the lights";
    for (const char* mis : {"power", "balance"})
        for (const char* single : {"bsdf", "light"})
            EXPECT_LT(estimates[mis].mse, estimates[single].mse) << mis << " vs " << single;
}

}  // namespace
}  // namespace glint::render
