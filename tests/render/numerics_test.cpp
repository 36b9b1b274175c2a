// Numerical stability at the extremes (docs/numerics.md): radiance from 1e-30 to the largest a
// scene may hold, albedo 0, roughness 0 and 1, grazing rays, degenerate triangles, a million
// samples in one pixel, 1×1 and 1×N films, and frames too big for the machine.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "film/film.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "glint/image/metrics.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

/// tests/render/data/cornell.json at w×h.
Scene cornell(int w, int h) {
    const fs::path dir = GLINT_RENDER_TEST_DATA;
    nlohmann::json j;
    std::ifstream(dir / "cornell.json") >> j;
    j["film"] = {{"width", w}, {"height", h}};
    return parseScene(j.dump(), dir / "cornell.json");
}

/// Peak resident set of this process in bytes.
std::uint64_t peakRss() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return std::uint64_t(u.ru_maxrss) * 1024;
}

/// The current emission strength of the Cornell box's light.
double lightStrength(const Scene& scene) {
    for (const LookItem& item : scene.look())
        if (item.name == "light")
            for (const LookProperty& p : item.properties)
                if (p.name == "strength") return p.value[0];
    ADD_FAILURE() << "no light strength";
    return 0.0;
}

TEST(Numerics, EmissionFromTheSmallestToTheLargestScalesLinearly) {
    Renderer renderer(cornell(24, 24));
    Settings s = renderer.scene().settings();
    s.spp = 8;
    s.threads = 2;
    const double base = lightStrength(renderer.scene());
    const FrameBuffers unit = renderer.render(s).frame;
    // The same random numbers make the same paths at every strength (Russian roulette follows
    // the throughput, not the radiance), so colour / k equals the unit image up to float
    // rounding of each sample (about 1e-7 relative); variance / k² likewise while k² times the
    // unit variance stays a normal float.
    for (double strength : {base * 1e-30, base * 1e-20, base * 1e-10, base * 1e10, 1e18}) {
        const double k = strength / base;
        renderer.scene().setLook("light", "strength", strength);
        const RenderResult r = renderer.render(s);
        EXPECT_EQ(r.stats.nonFiniteSamples, 0) << k;
        EXPECT_EQ(r.frame.color().countNonFinite(), 0u) << k;
        EXPECT_EQ(r.frame.layer(Layer::Variance).countNonFinite(), 0u) << k;
        double diff = 0.0, sum = 0.0, vdiff = 0.0, vsum = 0.0;
        const auto c = r.frame.color().data(), cu = unit.color().data();
        const auto v = r.frame.layer(Layer::Variance).data();
        const auto vu = unit.layer(Layer::Variance).data();
        for (std::size_t i = 0; i < c.size(); ++i) {
            diff += std::abs(double(c[i]) / k - double(cu[i]));
            sum += double(cu[i]);
            vdiff += std::abs(double(v[i]) / (k * k) - double(vu[i]));
            vsum += double(vu[i]);
        }
        EXPECT_LT(diff / sum, 1e-5) << "strength × " << k;
        // A float variance cannot follow below its normal range (1.2e-38, radiance about
        // 1e-19): there the frame says how many pixels it holds as 0 or a denormal, so that no
        // estimator takes them for noise-free.
        const auto& extra = r.frame.metadata().extra;
        const auto flagged = extra.find(kVarianceUnderflowKey);
        if (k >= 1e-10) {
            EXPECT_LT(vdiff / vsum, 1e-4) << "strength × " << k;
            EXPECT_EQ(flagged, extra.end()) << "strength × " << k;
        } else if (k <= 1e-20) {
            ASSERT_NE(flagged, extra.end()) << "strength × " << k;
            EXPECT_GT(std::stoll(flagged->second), 24 * 24 / 2) << "strength × " << k;
        }
    }
    // Beyond the largest radiance (1e18: its variance, about the square, must fit a float) the
    // edit is refused, naming the place.
    try {
        renderer.scene().setLook("light", "strength", 1e30);
        FAIL() << "strength 1e30 was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_EQ(e.where(), "/materials/light/strength") << e.what();
    }
}

TEST(Numerics, EmissionOf1e30InSceneJsonIsRefusedWithItsPlace) {
    test::TempDir dir("e30");
    dir.write("quad.obj", test::quadObj());
    const fs::path file = dir.write("scene.json", R"({"film": {"width": 4, "height": 4},
      "materials": {"lamp": {"type": "diffuse", "emission": [1e30, 1, 1]}},
      "shapes": [{"obj": "quad.obj", "material": "lamp"}]})");
    try {
        loadScene(file);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), file.string());
        EXPECT_EQ(e.where(), "/materials/lamp/emission/0") << e.what();
    }
}

TEST(Numerics, AlbedoZeroReflectsNothing) {
    // With every albedo 0 only the light seen directly contributes: the full render equals
    // direct lighting alone, and nothing divides by the zero throughput (Russian roulette
    // survival 0, BSDF weights 0).
    Renderer renderer(cornell(24, 24));
    for (const char* m : {"white", "red", "green"})
        renderer.scene().setLook(m, "albedo", {0.0, 0.0, 0.0});
    Settings s = renderer.scene().settings();
    s.spp = 8;
    s.maxDepth = 32;
    s.rrDepth = 0;
    const RenderResult full = renderer.render(s);
    s.maxDepth = 1;
    const RenderResult direct = renderer.render(s);
    EXPECT_EQ(full.stats.nonFiniteSamples, 0);
    double lit = 0.0;
    for (std::size_t i = 0; i < full.frame.color().data().size(); ++i) {
        EXPECT_NEAR(full.frame.color().data()[i], direct.frame.color().data()[i], 1e-4f) << i;
        lit += full.frame.color().data()[i];
    }
    EXPECT_GT(lit, 0.0);  // the light is in view
    // A black wall pixel (bottom middle is the floor) is exactly 0, its variance too.
    EXPECT_EQ(full.frame.color()(12, 22, 0), 0.0f);
    EXPECT_EQ(full.frame.layer(Layer::Variance)(12, 22, 0), 0.0f);
}

/// A conductor sphere in a constant environment of radiance 1 at `roughness`.
FrameBuffers metalSphere(const test::TempDir& dir, double roughness, int spp) {
    const std::string json = R"({
      "camera": {"position": [0, 0, 4], "lookAt": [0, 0, 0], "fovY": 30},
      "film": {"width": 24, "height": 24},
      "materials": {"metal": {"type": "conductor", "roughness": )" +
                             std::to_string(roughness) + R"(, "specular": [0.9, 0.9, 0.9]}},
      "shapes": [{"obj": "sphere.obj", "material": "metal"}],
      "environment": {"color": [1, 1, 1]}})";
    Renderer renderer(parseScene(json, dir.path() / "scene.json"));
    Settings s = renderer.scene().settings();
    s.spp = spp;
    const RenderResult r = renderer.render(s);
    EXPECT_EQ(r.stats.nonFiniteSamples, 0) << "roughness " << roughness;
    return r.frame;
}

TEST(Numerics, RoughnessZeroAndOneStayFiniteAndBounded) {
    test::TempDir dir("rough");
    dir.write("sphere.obj", test::sphereObj(1.0f, 24, 48));
    const FrameBuffers mirror = metalSphere(dir, 0.0, 16);
    // alpha = 0.033² = 1.1e-3, just above kMinGgxAlpha (1e-3), below which the lobe is a delta:
    // the narrowest GGX lobe that is still sampled and evaluated.
    const FrameBuffers nearMirror = metalSphere(dir, 0.033, 16);
    const FrameBuffers rough = metalSphere(dir, 1.0, 1024);
    for (const FrameBuffers* f : {&mirror, &nearMirror, &rough}) {
        EXPECT_EQ(f->color().countNonFinite(), 0u);
        EXPECT_EQ(f->layer(Layer::Variance).countNonFinite(), 0u);
        // No energy is created: a sphere in a white furnace never exceeds the environment
        // (5σ of the per-pixel mean allowed above it for the rough one).
        const Image& c = f->color();
        const Image& v = f->layer(Layer::Variance);
        for (int y = 0; y < 24; ++y)
            for (int x = 0; x < 24; ++x)
                EXPECT_LE(c(x, y, 1), 1.0f + 5.0f * std::sqrt(v(x, y, 1)) + 1e-4f);
    }
    // At the centre the mirror reflects the environment times its specular colour (normal
    // incidence: F = 0.9, one bounce since the sphere is convex).
    EXPECT_NEAR(mirror.color()(12, 12, 0), 0.9f, 0.02f);
    // The near-delta GGX lobe converges to the mirror (both see a constant environment).
    EXPECT_LT(relMse(nearMirror.color(), mirror.color()).value, 1e-3);
    // Roughness 1 (alpha 1) keeps only the single-scattering albedo: D = 1/pi, Smith
    // G2 = 1 / (1 + Lambda(wi)) with Lambda = (1/mu - 1) / 2 at normal incidence, so
    // E = integral of F(h) mu / (1 + mu) over mu in [0, 1]: 0.2762 with Schlick F0 = 0.9
    // (1 - ln 2 = 0.307 times the Fresnel term). The centre 2×2 pixels (facet normals within
    // 4 degrees of the view, which moves E by under 0.005) must match within 5σ + 0.01.
    double mean = 0.0, var = 0.0;
    for (int y = 11; y <= 12; ++y)
        for (int x = 11; x <= 12; ++x) {
            mean += 0.25 * rough.color()(x, y, 0);
            var += 0.0625 * rough.layer(Layer::Variance)(x, y, 0);
        }
    EXPECT_NEAR(mean, 0.2762, 5.0 * std::sqrt(var) + 0.01);
}

/// A 200×200 diffuse floor (albedo 0.5) under a constant white sky, seen at a grazing angle
/// from `eye` looking at `target`, the floor moved by `offset`; BSDF sampling only, so every
/// floor sample scores exactly 0.5 unless a bounce ray hits the floor it left.
FrameBuffers grazingFloor(const test::TempDir& dir, double offset, double eyeHeight) {
    auto vec = [](double x, double y, double z) {
        return "[" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + "]";
    };
    const std::string json = R"({"camera": {"position": )" + vec(offset, eyeHeight, offset - 60.0) +
                             R"(, "lookAt": )" + vec(offset, 0.0, offset) + R"(, "fovY": 20},
      "film": {"width": 32, "height": 32},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "shapes": [{"obj": "quad.obj", "material": "floor",
                  "transform": {"scale": 100, "translate": )" +
                             vec(offset, 0.0, offset) + R"(}}],
      "environment": {"color": [1, 1, 1]}})";
    Renderer renderer(parseScene(json, dir.path() / "scene.json"));
    Settings s = renderer.scene().settings();
    s.spp = 16;
    s.mis = MisHeuristic::None;
    s.strategy = Strategy::Bsdf;
    return renderer.render(s).frame;
}

TEST(Numerics, GrazingRaysNeverHitTheSurfaceTheyLeave) {
    test::TempDir dir("grazing");
    dir.write("quad.obj", test::quadObj());
    // Eye 0.5 above a floor 60 units away (under half a degree at the far edge), at the origin
    // and 1e5 away from it, where float spacing is 0.008.
    for (double offset : {0.0, 1e5}) {
        const FrameBuffers f = grazingFloor(dir, offset, 0.5);
        int floorPixels = 0;
        const Image& c = f.color();
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                // Floor 0.5, sky 1, a mix along the horizon; self-intersection would darken.
                ASSERT_GE(c(x, y, 0), 0.5f - 1e-4f)
                    << "(" << x << ", " << y << ") offset " << offset;
                if (std::abs(c(x, y, 0) - 0.5f) < 1e-4f) ++floorPixels;
            }
        EXPECT_GT(floorPixels, 32 * 10) << "offset " << offset;  // the lower part of the image
    }
}

TEST(Numerics, DegenerateTrianglesChangeNothing) {
    // A lamp and a floor, each with zero-area triangles mixed in (a repeated vertex, three
    // collinear points): they are never hit, never sampled as lights, and no NaN comes of them.
    test::TempDir dir("degenerate");
    const std::string quad = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 4 3\nf 1 3 2\n";
    dir.write("floor.obj", quad);
    dir.write("lamp.obj", quad);
    const std::string degenerate = "v 0 0 0\nv 0.5 0 0\nv 0.25 0 0\nf 5 5 6\nf 5 6 7\nf 7 7 7\n";
    dir.write("floor_bad.obj", quad + degenerate);
    dir.write("lamp_bad.obj", quad + degenerate);
    auto render = [&](const std::string& floor, const std::string& lamp) {
        const std::string json = R"({"camera": {"position": [0, 1.5, -3], "lookAt": [0, 0, 0]},
          "film": {"width": 24, "height": 24},
          "materials": {"white": {"type": "diffuse", "albedo": [0.8, 0.8, 0.8]},
                        "lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [4, 4, 4]}},
          "shapes": [{"obj": ")" +
                                 floor + R"(", "material": "white"},
                     {"obj": ")" +
                                 lamp + R"(", "material": "lamp",
                      "transform": {"scale": 0.3, "rotate": [180, [1, 0, 0]], "translate": [0, 1, 0]}}]})";
        Renderer renderer(parseScene(json, dir.path() / "scene.json"));
        Settings s = renderer.scene().settings();
        s.spp = 64;
        return renderer.render(s);
    };
    const RenderResult clean = render("floor.obj", "lamp.obj");
    const RenderResult bad = render("floor_bad.obj", "lamp_bad.obj");
    EXPECT_EQ(bad.stats.nonFiniteSamples, 0);
    EXPECT_EQ(bad.frame.color().countNonFinite(), 0u);
    // Same light, same floor: the images agree far below the 64-spp noise (relMSE ~1e-2).
    EXPECT_LT(relMse(bad.frame.color(), clean.frame.color()).value, 1e-6);
}

TEST(Numerics, AMillionSamplesInOnePixelDoNotDrift) {
    // A 1×1 film under a constant sky: every sample is exactly 0.7, so the mean must stay 0.7
    // and the variance 0 after a million samples from two threads.
    test::TempDir dir("million");
    const fs::path file = dir.write("scene.json", R"({"film": {"width": 1, "height": 1},
      "environment": {"color": [0.7, 0.7, 0.7]}})");
    Renderer renderer(loadScene(file));
    Settings s = renderer.scene().settings();
    s.spp = 1000000;
    s.threads = 2;
    const FrameBuffers f = renderer.render(s).frame;
    EXPECT_EQ(f.color()(0, 0, 0), 0.7f);
    EXPECT_EQ(f.layer(Layer::Variance)(0, 0, 0), 0.0f);
    EXPECT_EQ(f.layer(Layer::SampleCount)(0, 0, 0), 1e6f);
}

TEST(Numerics, WelfordAccumulationOfAMillionUnequalSamplesIsExactToDoublePrecision) {
    // Alternating 0.1 and 0.3 (and a 1e6 outlier) into one film pixel: a float running sum
    // would drift by ~1e-3 after 1e6 adds; Welford in double stays within 1e-12 of the truth.
    Film film(1, 1);
    FilmSample a, b;
    a.color = {0.1f, 0.1f, 0.1f};
    b.color = {0.3f, 0.3f, 0.3f};
    const int n = 1000000;
    for (int i = 0; i < n; ++i) film.add(0, 0, (i % 2) ? b : a);
    FilmSample spike;
    spike.color = {1e6f, 1e6f, 1e6f};
    film.add(0, 0, spike);
    const FrameBuffers f = film.resolve(false);
    const double exact = (0.5 * (double(0.1f) + double(0.3f)) * n + 1e6) / (n + 1);
    EXPECT_NEAR(f.color()(0, 0, 0), exact, exact * 1e-7);  // float output: 1 ulp
    // Sample variance of the mean: two values ±0.1 around 0.2, plus the spike.
    double m2 = 0.0;
    const double d0 = double(0.1f) - exact, d1 = double(0.3f) - exact, ds = 1e6 - exact;
    m2 = (n / 2) * (d0 * d0 + d1 * d1) + ds * ds;
    const double varOfMean = m2 / double(n) / double(n + 1);
    EXPECT_NEAR(f.layer(Layer::Variance)(0, 0, 0), varOfMean, varOfMean * 1e-6);
}

TEST(Numerics, OneByOneAndOneByNFilmsRender) {
    for (auto [w, h] : {std::pair{1, 1}, std::pair{1, 40}, std::pair{40, 1}}) {
        Renderer renderer(cornell(w, h));
        Settings s = renderer.scene().settings();
        s.spp = 4;
        const FrameBuffers f = renderer.render(s).frame;
        ASSERT_EQ(f.width(), w);
        ASSERT_EQ(f.height(), h);
        EXPECT_EQ(f.color().countNonFinite(), 0u);
        for (float c : f.layer(Layer::SampleCount).data()) EXPECT_EQ(c, 4.0f);
    }
}

TEST(Numerics, An8192FrameIsCheckedBeforeAnythingIsAllocated) {
    Renderer renderer(cornell(8192, 8192));
    Settings s = renderer.scene().settings();
    s.spp = 1;
    // Film statistics (Welford mean and M2 of 13 channels in double, 2 counters: 216 bytes)
    // plus the resolved frame and a snapshot (21 floats each): 384 bytes a pixel, 24 GiB.
    const std::uint64_t pixels = 8192ull * 8192ull;
    EXPECT_EQ(renderer.estimateMemory(s), pixels * (216 + 2 * 84));
    s.positionLayer = true;
    EXPECT_EQ(renderer.estimateMemory(s), pixels * (216 + 2 * 96));
    s.positionLayer = false;
    s.integrator = Integrator::Mlt;
    s.mlt.groups = 4;
    EXPECT_EQ(renderer.estimateMemory(s), pixels * (216 + 3 * 84 + 4 * 24));
    s.integrator = Integrator::Path;
    // With a 1 GiB budget the render is refused at once, naming the scene and the film, and
    // nothing is allocated for it.
    s.memoryLimit = std::uint64_t(1) << 30;
    const std::uint64_t before = peakRss();
    try {
        renderer.render(s);
        FAIL() << "an 8192x8192 render fit in 1 GiB";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_EQ(e.where(), "/film");
        EXPECT_NE(e.file().find("cornell.json"), std::string::npos);
        EXPECT_NE(e.message().find("24.0 GiB"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("1.00 GiB"), std::string::npos) << e.what();
    }
    EXPECT_LT(peakRss() - before, std::uint64_t(64) << 20);
}

TEST(Numerics, ARenderBiggerThanTheMachineIsRefusedByDefault) {
    // 16384² with Metropolis' 16 groups: 2^28 pixels × 852 bytes, about 213 GiB, more than any
    // machine this runs on has available; the default limit is the machine's.
    Renderer renderer(cornell(16384, 16384));
    Settings s = renderer.scene().settings();
    s.spp = 1;
    s.integrator = Integrator::Mlt;
    ASSERT_GT(renderer.estimateMemory(s), availableMemory());
    EXPECT_THROW(
        {
            try {
                renderer.render(s);
            } catch (const Error& e) {
                EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
                EXPECT_NE(e.message().find("available on this machine"), std::string::npos)
                    << e.what();
                throw;
            }
        },
        Error);
}

}  // namespace
}  // namespace glint::render
