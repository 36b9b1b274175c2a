// Motion blur: analytic coverage of a translating quad, time-averaged feature variance, moving
// camera, Embree motion geometry matching the shading pose, static scenes paying nothing, and
// bad motion input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "embree/embree_scene.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "sampling/rng.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

// Film 32 × 8, pinhole at the origin looking down -z with fovY = 90°: H / (2 tan 45°) = 4 pixels
// per unit of X / d, so a point at lateral X and depth d lands at raster x = 16 + 4 X / d, and a
// quad at depth 10 maps X to x = 16 + 0.4 X (linear, so translation in X is a raster shift).
constexpr int kWidth = 32, kHeight = 8;
constexpr float kDepth = 10.0f;
float pixelOf(float x) {
    return 16.0f + 0.4f * x;
}

/// OBJ of the rectangle [x0, x1] × [-20, 20] at z = -kDepth, facing the camera (+z).
std::string rectObj(float x0, float x1) {
    const std::string z = std::to_string(-kDepth);
    return "v " + std::to_string(x0) + " -20 " + z + "\nv " + std::to_string(x1) + " -20 " + z +
           "\nv " + std::to_string(x1) + " 20 " + z + "\nv " + std::to_string(x0) + " 20 " + z +
           "\nf 1 2 3 4\n";
}

/// Fraction of pixel column [x, x+1] × shutter covered by the raster interval [a + τΔ, b + τΔ]:
/// the inner time integral is exact (interval length), the outer one a 4000-point midpoint rule
/// of a piecewise-linear integrand (error < 1e-6).
double expectedCoverage(int x, double a, double b, double delta) {
    const int n = 4000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double px = x + (i + 0.5) / n;
        // a + τΔ ≤ px ≤ b + τΔ  ⇔  τ ∈ [(px − b)/Δ, (px − a)/Δ] (Δ > 0).
        const double lo = std::max(0.0, (px - b) / delta), hi = std::min(1.0, (px - a) / delta);
        sum += std::max(0.0, hi - lo);
    }
    return sum / n;
}

/// A white moving quad X ∈ [-10, 2.5] translated by +25 in X over the shutter (raster [12, 17]
/// → [22, 27]) and a static white quad X ∈ [-40, -30] (raster [0, 4]); nothing else, no light.
/// `cameraMoves` instead keeps the quad still and moves the camera by -25 in X.
std::filesystem::path writeMotionScene(const test::TempDir& dir, bool cameraMoves) {
    dir.write("moving.obj", rectObj(-10.0f, 2.5f));
    dir.write("static.obj", rectObj(-40.0f, -30.0f));
    const std::string camera =
        cameraMoves ? R"("camera": {"position": [0, 0, 0], "lookAt": [0, 0, -1], "fovY": 90,
                        "shutter": [0, 1],
                        "motion": {"position": [-25, 0, 0], "lookAt": [-25, 0, -1]}},)"
                    : R"("camera": {"position": [0, 0, 0], "lookAt": [0, 0, -1], "fovY": 90,
                        "shutter": [0.25, 0.75]},)";
    const std::string motion = cameraMoves ? "" : R"(, "motion": {"translate": [25, 0, 0]})";
    return dir.write("scene.json", "{" + camera + R"(
      "film": {"width": 32, "height": 8},
      "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]}},
      "shapes": [{"obj": "moving.obj", "material": "white")" +
                                       motion + R"(},
                 {"obj": "static.obj", "material": "white"}],
      "render": {"spp": 256, "maxDepth": 1}
    })");
}

/// Checks the albedo of every pixel against the analytic coverage. Tolerance: 5 standard errors
/// of the mean from the film's own variance buffer (that buffer assumes independent samples;
/// the stratified pixel/time samples have lower error, so the bound is conservative; a 5σ miss
/// has probability < 1e-6 per pixel) plus 1e-4 for float accumulation.
void checkCoverage(const FrameBuffers& f) {
    const Image& albedo = f.layer(Layer::Albedo);
    const Image& var = f.layer(Layer::AlbedoVariance);
    const double a = pixelOf(-10.0f), b = pixelOf(2.5f), delta = 0.4 * 25.0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const double expected = x < 4 ? 1.0 : expectedCoverage(x, a, b, delta);
            const double sigma = std::sqrt(double(var(x, y, 0)));
            EXPECT_NEAR(albedo(x, y, 0), expected, 5.0 * sigma + 1e-4) << "pixel " << x << "," << y;
            if (expected > 0.0 && expected < 1.0) {
                EXPECT_GT(sigma, 0.0) << "pixel " << x;
            }
        }
}

TEST(MotionBlur, TranslatingQuadCoversAnalyticFraction) {
    test::TempDir dir("motion_quad");
    Renderer renderer(loadScene(writeMotionScene(dir, false)));
    const FrameBuffers f = renderer.render(renderer.scene().settings()).frame;
    checkCoverage(f);
    EXPECT_EQ(f.metadata().extra.at("motionBlur"), "true");
}

TEST(MotionBlur, FeatureVarianceShowsPartTimeCoverage) {
    test::TempDir dir("motion_var");
    Renderer renderer(loadScene(writeMotionScene(dir, false)));
    Settings s = renderer.scene().settings();
    s.spp = 64;
    const FrameBuffers f = renderer.render(s).frame;
    // Pixel 2 is covered by the static quad all the time, pixel 19 by the moving quad part of
    // the time (expected coverage 0.5), pixel 30 never.
    for (Layer l : {Layer::AlbedoVariance, Layer::NormalVariance, Layer::DepthVariance}) {
        const Image& v = f.layer(l);
        const int c = l == Layer::NormalVariance ? 2 : 0;  // normal (0, 0, 1): its z varies
        // Always-covered pixels vary only by float rounding of the hit point (depth ~1e-15).
        // A coverage-0.5 pixel with k hits of 64 samples has variance of the mean
        // q² k (64 − k) / (63 · 64²) for a feature jumping by q (1 for albedo and normal z, 10 for
        // depth): ≥ 0.0029 q² for 16 ≤ k ≤ 48 (stratified time keeps k near 32), so 1e-3
        // separates the cases.
        for (int y = 0; y < kHeight; ++y) {
            EXPECT_LT(v(2, y, c), 1e-9f) << layerInfo(l).name;
            EXPECT_GT(v(19, y, c), 1e-3f) << layerInfo(l).name;
            EXPECT_EQ(v(30, y, c), 0.0f) << layerInfo(l).name;
        }
    }
    // The part-time pixel's depth is a time average of 10 (hit) and 0 (miss): near 5.
    EXPECT_NEAR(f.layer(Layer::Depth)(19, 0, 0), 0.5 * kDepth, 1.5);
}

TEST(MotionBlur, MovingCameraEqualsOppositeObjectMotion) {
    // Camera moving by -25 in X sees both (still) quads move by +25 relative to it: raster
    // [0, 4] → [10, 14] and [12, 17] → [22, 27], never overlapping, so coverages add.
    test::TempDir dir("motion_camera");
    Renderer renderer(loadScene(writeMotionScene(dir, true)));
    Settings s = renderer.scene().settings();
    const FrameBuffers f = renderer.render(s).frame;
    const Image& albedo = f.layer(Layer::Albedo);
    const Image& var = f.layer(Layer::AlbedoVariance);
    const double a = pixelOf(-10.0f), b = pixelOf(2.5f), delta = 0.4 * 25.0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const double expected = expectedCoverage(x, a, b, delta) +
                                    expectedCoverage(x, pixelOf(-40.0f), pixelOf(-30.0f), delta);
            EXPECT_NEAR(albedo(x, y, 0), expected, 5.0 * std::sqrt(double(var(x, y, 0))) + 1e-4)
                << "pixel " << x;
        }
}

/// Scene text with one shape carrying `shapeExtra` (e.g. a motion block).
std::string oneShape(const std::string& shapeExtra, const std::string& camera = "") {
    return R"({"film": {"width": 8, "height": 8}, )" + camera +
           R"("shapes": [{"obj": "sphere.obj")" + shapeExtra + "}]}";
}

TEST(MotionBlur, StaticSceneBuildsNoMotionGeometry) {
    test::TempDir dir("motion_static");
    dir.write("sphere.obj", test::sphereObj(1.0f));
    for (const std::string& extra :
         {std::string(), std::string(R"(, "transform": {"translate": [1, 2, 3]})"),
          // A motion equal to the transform is no motion.
          std::string(R"(, "transform": {"translate": [1, 0, 0]},
                         "motion": {"translate": [1, 0, 0]})")}) {
        const Scene scene = loadScene(dir.write("scene.json", oneShape(extra)));
        EXPECT_FALSE(detail::sceneData(scene).hasMotion()) << extra;
        EXPECT_TRUE(detail::sceneData(scene).motions.empty()) << extra;
        const EmbreeScene embree(detail::sceneData(scene));
        EXPECT_EQ(embree.motionGeometryCount(), 0) << extra;
    }
    // A moving one builds one motion geometry: 2 steps for translation, one per 5° of rotation.
    const Scene moving = loadScene(
        dir.write("scene.json",
                  oneShape(R"(, "motion": {"translate": [1, 0, 0], "rotate": [90, [0, 0, 1]]})")));
    const EmbreeScene embree(detail::sceneData(moving));
    ASSERT_EQ(embree.motionGeometryCount(), 1);
    EXPECT_EQ(embree.timeStepCount(0), 1 + 90 / 5);
    const Scene sliding =
        loadScene(dir.write("scene.json", oneShape(R"(, "motion": {"translate": [1, 0, 0]})")));
    EXPECT_EQ(EmbreeScene(detail::sceneData(sliding)).timeStepCount(0), 2);
}

TEST(MotionBlur, AMovingShapesMeshIsBuiltOnceWhateverItsTimeSteps) {
    // A sphere rolling 640° (129 time steps) is one instance of its mesh's BVH, whose pose Embree
    // interpolates: its build holds about what a still sphere's does, not a BVH a step, and the
    // memory estimate says so.
    test::TempDir dir("motion_memory");
    dir.write("sphere.obj", test::sphereObj(1.0f, 24, 48));
    const Scene still = loadScene(dir.write(
        "still.json",
        oneShape(R"(, "transform": {"translate": [1, 0, 0], "rotate": [10, [0, 0, 1]]})")));
    const Scene rolling = loadScene(
        dir.write("rolling.json",
                  oneShape(R"(, "motion": {"translate": [1, 0, 0], "rotate": [640, [0, 0, 1]]})")));
    const EmbreeScene a(detail::sceneData(still)), b(detail::sceneData(rolling));
    ASSERT_EQ(b.motionGeometryCount(), 1);
    EXPECT_EQ(b.timeStepCount(0), 129);
    EXPECT_GT(a.memory().peak, 0);
    EXPECT_LT(b.memory().peak, 2 * a.memory().peak);  // 129 steps of triangles: about 100x
    EXPECT_EQ(EmbreeScene::estimateBytes(detail::sceneData(rolling), false),
              EmbreeScene::estimateBytes(detail::sceneData(still), false));
}

TEST(MotionBlur, ShadingPoseMatchesEmbreeGeometry) {
    // A sphere rolling (translating and turning 400° about z) and shrinking: at random times,
    // the hit point rebuilt from the posed triangle (as the integrator shades it) must lie on
    // the ray where Embree found it.
    test::TempDir dir("motion_pose");
    dir.write("sphere.obj", test::sphereObj(1.0f, 12, 24));
    const Scene scene = loadScene(
        dir.write("scene.json",
                  oneShape(R"(, "transform": {"translate": [-1, 0, 0], "rotate": [20, [0, 0, 1]]},
                    "motion": {"translate": [1, 0.2, 0], "rotate": [420, [0, 0, 1]], "scale": 0.7})")));
    const detail::SceneData& data = detail::sceneData(scene);
    const EmbreeScene embree(data);
    ASSERT_EQ(embree.motionGeometryCount(), 1);
    EXPECT_EQ(embree.timeStepCount(0), 1 + 80);  // 400° / 5°
    Rng rng(7);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        Ray ray;
        ray.origin = {rng.uniform() * 4.0f - 2.0f, rng.uniform() * 2.0f - 1.0f, 5.0f};
        ray.dir = {0.0f, 0.0f, -1.0f};
        ray.time = rng.uniform();
        Hit hit;
        if (!embree.intersect(ray, 1e30f, hit)) continue;
        ++hits;
        const detail::TriangleView tri =
            data.triangle(hit.surface.instance, hit.surface.prim, ray.time);
        const Vec3 p = tri.p[0] * (1.0f - hit.u - hit.v) + tri.p[1] * hit.u + tri.p[2] * hit.v;
        const Vec3 onRay = ray.origin + ray.dir * hit.t;
        ASSERT_LT(length(p - onRay), 1e-4f) << "time " << ray.time;
    }
    EXPECT_GT(hits, 500);
}

/// The error thrown by loading `json` (with sphere.obj beside it).
Error motionError(const std::string& json) {
    test::TempDir dir("motion_errors");
    dir.write("sphere.obj", test::sphereObj(1.0f, 4, 8));
    try {
        loadScene(dir.write("scene.json", json));
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << "no error for: " << json;
    return Error(ErrorKind::Internal, "none");
}

TEST(MotionBlur, BadMotionInputGivesClearErrors) {
    Error e = motionError(oneShape(R"(, "motion": {"scale": 0})"));
    EXPECT_EQ(e.where(), "/shapes/0/motion/scale");
    EXPECT_NE(e.message().find("non-zero"), std::string::npos) << e.what();

    e = motionError(oneShape(R"(, "motion": {"scale": [1, -1, 1]})"));
    EXPECT_EQ(e.where(), "/shapes/0/motion/scale");
    EXPECT_NE(e.message().find("sign"), std::string::npos) << e.what();

    e = motionError(oneShape("", R"("camera": {"shutter": [1, 0.5]},)"));
    EXPECT_EQ(e.where(), "/camera/shutter");
    EXPECT_NE(e.message().find("must not be before shutter open"), std::string::npos) << e.what();

    e = motionError(oneShape(R"(, "motion": {"spin": 3})"));
    EXPECT_EQ(e.where(), "/shapes/0/motion/spin");

    e = motionError(R"({"film": {"width": 8, "height": 8},
        "materials": {"lamp": {"type": "diffuse", "emission": [1, 1, 1]}},
        "shapes": [{"obj": "sphere.obj", "material": "lamp", "motion": {"translate": [1, 0, 0]}}]})");
    EXPECT_EQ(e.where(), "/shapes/0/motion");
    EXPECT_NE(e.message().find("emissive"), std::string::npos) << e.what();

    e = motionError(oneShape("", R"("camera": {"position": [0, 0, 5], "lookAt": [0, 0, 0],
        "motion": {"position": [0, 5, 0]}},)"));
    EXPECT_EQ(e.where(), "/camera/motion");
    EXPECT_NE(e.message().find("parallel to up"), std::string::npos) << e.what();
}

}  // namespace
}  // namespace glint::render
