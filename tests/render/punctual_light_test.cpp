// Punctual lights (glTF's KHR_lights_punctual: point, spot, directional) are delta lights, reached
// by next-event estimation alone: a diffuse floor under each gives the closed-form radiance
// ρ/π · E, with E = I cos θ / r² (point, spot inside its cone) or the light's irradiance
// (directional); a spot's cone cuts off; and MIS gives them weight 1 (no BSDF sample reaches them).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "lights/light_sampler.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

using detail::PunctualLight;

/// A 2 × 2 diffuse floor (albedo 0.5) at y = 0 seen from 10 above through a 0.1° lens (it sees
/// the floor within 0.009 of the origin), lit only by `light`.
Scene litFloor(const test::TempDir& dir, const PunctualLight& light, int size = 8) {
    dir.write("floor.obj", "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 4 3\n");
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 10, 0], "lookAt": [0, 0, 0], "up": [0, 0, 1], "fovY": 0.1},
            "film": {"width": )" +
            std::to_string(size) + R"(, "height": )" + std::to_string(size) + R"(},
            "materials": {"floor": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
            "shapes": [{"obj": "floor.obj", "material": "floor"}]})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    data->punctualLights.push_back(light);
    return Scene(std::move(data));
}

/// The mean colour of a render of `scene` (direct light only).
Vec3 meanColour(Scene scene, MisHeuristic mis = MisHeuristic::Power) {
    Renderer renderer(std::move(scene));
    Settings s = renderer.scene().settings();
    s.spp = 4;
    s.maxDepth = 1;
    s.threads = 2;
    s.mis = mis;
    const FrameBuffers frame = renderer.render(s).frame;
    Vec3 sum{};
    const Image& c = frame.color();
    for (int y = 0; y < c.height(); ++y)
        for (int x = 0; x < c.width(); ++x) sum = sum + Vec3{c(x, y, 0), c(x, y, 1), c(x, y, 2)};
    return sum / float(c.width() * c.height());
}

PunctualLight point(Vec3 position, float intensity) {
    PunctualLight l;
    l.kind = PunctualLight::Kind::Point;
    l.position = position;
    l.intensity = {intensity, intensity, intensity};
    return l;
}

}  // namespace

// The floor seen spans at most 0.009 off the light's foot, where cos³θ ≥ 0.9998 at height 2:
// the mean lies within 1.3 % of the closed form at the foot (the rest is float rounding).
TEST(PunctualLight, APointLightGivesTheInverseSquareIrradiance) {
    test::TempDir dir("point");
    // L = ρ/π · I/h² = 0.5/π · π·4 / 2² = 0.5 at h = 2 (cos θ ≥ 0.999 there).
    const Vec3 c = meanColour(litFloor(dir, point({0, 2, 0}, 4.0f * kPi)));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.5f, 0.5f * 0.013f) << k;
    // Twice as far: a quarter.
    const Vec3 far = meanColour(litFloor(dir, point({0, 4, 0}, 4.0f * kPi)));
    EXPECT_NEAR(far.x, 0.125f, 0.125f * 0.013f);
}

TEST(PunctualLight, ASpotLightsInsideItsConeAndNothingOutside) {
    test::TempDir dir("spot");
    PunctualLight spot = point({0, 2, 0}, 4.0f * kPi);
    spot.kind = PunctualLight::Kind::Spot;
    spot.direction = {0, -1, 0};
    spot.cosInner = std::cos(0.3f);
    spot.cosOuter = std::cos(0.5f);
    EXPECT_NEAR(meanColour(litFloor(dir, spot)).x, 0.5f, 0.5f * 0.013f);
    // Tilted 45° away: the floor under it lies outside the outer cone.
    spot.direction = normalize(Vec3{1, -1, 0});
    EXPECT_EQ(meanColour(litFloor(dir, spot)).x, 0.0f);
    // Halfway through the ramp: ((cos θ − cos outer) / (cos inner − cos outer))² of the full.
    const float theta = 0.4f;
    spot.direction = normalize(Vec3{std::sin(theta), -std::cos(theta), 0});
    const float t = (std::cos(theta) - spot.cosOuter) / (spot.cosInner - spot.cosOuter);
    EXPECT_NEAR(meanColour(litFloor(dir, spot)).x, 0.5f * t * t, 0.5f * t * t * 0.05f);
}

TEST(PunctualLight, ADirectionalLightGivesItsIrradianceAtAnyDistance) {
    test::TempDir dir("sun");
    PunctualLight sun;
    sun.kind = PunctualLight::Kind::Directional;
    sun.direction = {0, -1, 0};
    sun.intensity = {kPi, 2 * kPi, 0};  // lux: L = ρ/π · E
    const Vec3 c = meanColour(litFloor(dir, sun));
    EXPECT_NEAR(c.x, 0.5f, 1e-4f);
    EXPECT_NEAR(c.y, 1.0f, 2e-4f);
    EXPECT_EQ(c.z, 0.0f);
    // At 60° from the normal: cos θ = 0.5.
    sun.direction = normalize(Vec3{std::sqrt(3.0f), -1, 0});
    EXPECT_NEAR(meanColour(litFloor(dir, sun)).x, 0.25f, 1e-4f);
}

TEST(PunctualLight, EveryHeuristicGivesADeltaLightTheSameImage) {
    // No BSDF sample can reach a delta light, so its MIS weight is 1 whatever the heuristic.
    test::TempDir dir("mis");
    const PunctualLight light = point({0.5f, 2, 0}, 10.0f);
    const Vec3 power = meanColour(litFloor(dir, light), MisHeuristic::Power);
    const Vec3 balance = meanColour(litFloor(dir, light), MisHeuristic::Balance);
    EXPECT_GT(power.x, 0.0f);
    EXPECT_EQ(power.x, balance.x);
}

TEST(PunctualLight, LightsAreChosenByPowerWithTheAreaLightsAndTheEnvironment) {
    // A point light beside an emissive triangle: each is chosen in proportion to its power
    // (point: 4π I; the triangle: 2π A L), and the sample says which kind it is.
    test::TempDir dir("choice");
    dir.write("lamp.obj", "v -1 1 -1\nv 1 1 -1\nv 0 1 1\nf 1 3 2\n");
    const Scene parsed = parseScene(R"({"film": {"width": 4, "height": 4},
      "materials": {"lamp": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [1, 1, 1]}},
      "shapes": [{"obj": "lamp.obj", "material": "lamp"}]})",
                                    dir.path() / "scene.json");
    detail::SceneData data = detail::sceneData(parsed);
    data.punctualLights.push_back(point({0, 3, 0}, 1.0f));  // 4π vs 2π · 2 · 1: even odds
    const LightSampler lights(data);
    EXPECT_EQ(lights.punctualLightCount(), 1u);
    int delta = 0;
    const int n = 10000;
    for (int i = 0; i < n; ++i) {
        LightSample s;
        ASSERT_TRUE(lights.sample({0, 0, 0}, (i + 0.5f) / n, {0.3f, 0.3f}, s));
        if (s.delta) {
            ++delta;
            EXPECT_NEAR(s.pdf, 0.5f, 1e-4f);
            EXPECT_NEAR(s.radiance.x, 1.0f / 9.0f, 1e-6f);
            EXPECT_NEAR(s.distance, 3.0f, 1e-6f);
        }
    }
    EXPECT_NEAR(double(delta) / n, 0.5, 1e-3);
}

}  // namespace glint::render
