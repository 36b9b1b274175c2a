// The editable look: enumerate materials, lights and the environment, change them, re-render
// without a BVH rebuild, save back to JSON that renders bit for bit the same.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "renderer_detail.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

const fs::path kData = GLINT_RENDER_TEST_DATA;
const fs::path kScenes = fs::path(GLINT_SOURCE_DIR) / "scenes";

Settings small(const Renderer& r, int spp = 4) {
    Settings s = r.scene().settings();
    s.spp = spp;
    s.threads = 2;
    return s;
}

// A copy of tests/render/data/cornell.json at 32x32 in `dir` (the OBJ/MTL stay where they are).
fs::path cornellCopy(const test::TempDir& dir) {
    nlohmann::json j;
    std::ifstream(kData / "cornell.json") >> j;
    j["film"] = {{"width", 32}, {"height", 32}};
    j["shapes"][0]["obj"] = (kData / "cornell_box.obj").string();
    return dir.write("cornell.json", j.dump(2));
}

const LookItem* findItem(const std::vector<LookItem>& items, const std::string& name) {
    for (const LookItem& it : items)
        if (it.name == name) return &it;
    return nullptr;
}

const LookProperty* findProperty(const LookItem& item, const std::string& name) {
    for (const LookProperty& p : item.properties)
        if (p.name == name) return &p;
    return nullptr;
}

double meanColor(const FrameBuffers& f) {
    double s = 0.0;
    for (float v : f.color().data()) s += v;
    return s / double(f.color().data().size());
}

TEST(Look, ListsMaterialsLightsAndEnvironmentWithDescribedProperties) {
    const Scene cornell = loadScene(kData / "cornell.json");
    const std::vector<LookItem> items = cornell.look();
    ASSERT_EQ(items.size(), 4u);  // white, red, green, light (from the MTL file); no environment
    const LookItem* light = findItem(items, "light");
    ASSERT_NE(light, nullptr);
    EXPECT_TRUE(light->light);
    EXPECT_EQ(light->type, "diffuse");
    const LookProperty* strength = findProperty(*light, "strength");
    ASSERT_NE(strength, nullptr);
    EXPECT_FALSE(strength->isColour);
    EXPECT_EQ(strength->value[0], 17.0);
    EXPECT_EQ(strength->scale, ParamScale::Log);
    const LookProperty* emission = findProperty(*light, "emission");
    ASSERT_NE(emission, nullptr);
    EXPECT_TRUE(emission->isColour);
    EXPECT_NEAR(emission->value[1], 12.0 / 17.0, 1e-6);
    const LookItem* red = findItem(items, "red");
    ASSERT_NE(red, nullptr);
    EXPECT_FALSE(red->light);
    const LookProperty* albedo = findProperty(*red, "albedo");
    ASSERT_NE(albedo, nullptr);
    EXPECT_NEAR(albedo->value[0], 0.63, 1e-6);
    EXPECT_EQ(albedo->max, 1.0);
    EXPECT_FALSE(albedo->help.empty());

    const Scene envmap = loadScene(kScenes / "envmap" / "scene.json");
    const std::vector<LookItem> envItems = envmap.look();
    const LookItem* env = findItem(envItems, "environment");
    ASSERT_NE(env, nullptr);
    EXPECT_EQ(env->kind, LookItemKind::Environment);
    EXPECT_EQ(env->type, "image");
    EXPECT_NE(findProperty(*env, "rotate"), nullptr);
    const LookItem* gold = findItem(envItems, "gold");
    ASSERT_NE(gold, nullptr);
    EXPECT_NE(findProperty(*gold, "roughness"), nullptr);
    EXPECT_EQ(findProperty(*gold, "ior"), nullptr);
    const LookItem* glass = findItem(envItems, "glass");
    ASSERT_NE(glass, nullptr);
    EXPECT_NE(findProperty(*glass, "ior"), nullptr);
}

// The issue's "done when": a material change re-renders cornell without a BVH rebuild and
// matches a fresh load of the saved JSON bit for bit.
TEST(Look, EditRerendersWithoutRebuildAndSavedSceneMatchesBitForBit) {
    test::TempDir dir("look_save");
    Renderer renderer(loadScene(cornellCopy(dir)));
    const FrameBuffers before = renderer.render(small(renderer)).frame;
    renderer.scene().setLook("red", "albedo", {0.1, 0.2, 0.7});
    renderer.scene().setLook("light", "strength", 34.0);
    const FrameBuffers after = renderer.render(small(renderer)).frame;
    EXPECT_EQ(detail::accelerationBuilds(renderer), 1);
    EXPECT_EQ(detail::lightBuilds(renderer), 2);
    EXPECT_FALSE(test::sameLayer(before, after, Layer::Color));
    // Twice the light: twice the image (the same random numbers, so exactly up to rounding).
    EXPECT_GT(meanColor(after), 1.5 * meanColor(before));
    // A render with no edit since does not rebuild the lights either.
    renderer.render(small(renderer));
    EXPECT_EQ(detail::lightBuilds(renderer), 2);

    const fs::path saved = dir.path() / "sub" / "edited.json";
    fs::create_directories(saved.parent_path());
    saveScene(renderer.scene(), saved);
    Renderer reloaded(loadScene(saved));
    test::expectSameFrames(after, reloaded.render(small(reloaded)).frame);
    // The look reads back as set.
    const std::vector<LookItem> items = reloaded.scene().look();
    const LookItem* red = findItem(items, "red");
    ASSERT_NE(red, nullptr);
    EXPECT_NEAR(findProperty(*red, "albedo")->value[2], 0.7, 1e-6);
}

TEST(Look, EnvironmentScaleAndRotationEditAndSave) {
    test::TempDir dir("look_env");
    Renderer renderer(loadScene(kScenes / "envmap" / "scene.json"));
    Settings s = small(renderer, 2);
    const FrameBuffers before = renderer.render(s).frame;
    renderer.scene().setLook("environment", "scale", 0.5);
    renderer.scene().setLook("environment", "rotate", 90.0);
    renderer.scene().setLook("gold", "roughness", 0.6);
    const FrameBuffers after = renderer.render(s).frame;
    EXPECT_FALSE(test::sameLayer(before, after, Layer::Color));
    EXPECT_LT(meanColor(after), 0.75 * meanColor(before));
    EXPECT_EQ(detail::accelerationBuilds(renderer), 1);
    // Saved in another folder: the OBJ and sky paths are rebased and still found.
    const fs::path saved = dir.path() / "envmap_edit.json";
    saveScene(renderer.scene(), saved);
    Renderer reloaded(loadScene(saved));
    test::expectSameFrames(after, reloaded.render(s).frame);
}

TEST(Look, GlassRoughnessEditsRendersAndSaves) {
    // A dielectric's roughness is editable: the glass turns rough (a different image, no BVH
    // rebuild), the saved scene holds it and renders the same.
    test::TempDir dir("look_glass");
    Renderer renderer(loadScene(kScenes / "envmap" / "scene.json"));
    const std::vector<LookItem> items = renderer.scene().look();
    const LookItem* glass = findItem(items, "glass");
    ASSERT_NE(glass, nullptr);
    ASSERT_NE(findProperty(*glass, "roughness"), nullptr);
    EXPECT_EQ(findProperty(*glass, "roughness")->value[0], 0.0);
    Settings s = small(renderer, 2);
    const FrameBuffers before = renderer.render(s).frame;
    renderer.scene().setLook("glass", "roughness", 0.4);
    const FrameBuffers after = renderer.render(s).frame;
    EXPECT_FALSE(test::sameLayer(before, after, Layer::Color));
    EXPECT_EQ(detail::accelerationBuilds(renderer), 1);
    const fs::path saved = dir.path() / "rough_glass.json";
    saveScene(renderer.scene(), saved);
    std::ifstream in(saved);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_NEAR(j["materials"]["glass"]["roughness"].get<double>(), 0.4, 1e-6);
    Renderer reloaded(loadScene(saved));
    test::expectSameFrames(after, reloaded.render(s).frame);
}

TEST(Look, ZeroStrengthKeepsTheColourAndTheLightGoesOut) {
    test::TempDir dir("look_zero");
    Renderer renderer(loadScene(cornellCopy(dir)));
    renderer.scene().setLook("light", "emission", {1.0, 0.5, 0.25});
    renderer.scene().setLook("light", "strength", 0.0);
    const FrameBuffers dark = renderer.render(small(renderer)).frame;
    EXPECT_EQ(meanColor(dark), 0.0);
    EXPECT_EQ(dark.color().countNonFinite(), 0u);
    const std::vector<LookItem> items = renderer.scene().look();
    const LookItem* light = findItem(items, "light");
    EXPECT_FALSE(light->light);
    EXPECT_EQ(findProperty(*light, "emission")->value[1], 0.5);
    renderer.scene().setLook("light", "strength", 10.0);
    EXPECT_GT(meanColor(renderer.render(small(renderer)).frame), 0.0);
}

TEST(Look, BadEditsAreRefusedNamingTheFileAndPlaceAndChangeNothing) {
    test::TempDir dir("look_bad");
    const fs::path file = cornellCopy(dir);
    Scene scene = loadScene(file);
    const std::uint64_t revision = scene.lookRevision();
    struct Case {
        std::string item, property;
        std::array<double, 3> value;
        std::string mention;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Case cases[] = {
        {"blue", "albedo", {0.5, 0.5, 0.5}, "red"},  // unknown item lists the others
        {"red", "ior", {1.5, 0, 0}, "albedo"},       // not a dielectric
        {"red", "albedo", {0.5, 1.5, 0.5}, "/materials/red/albedo/1"},
        {"red", "albedo", {nan, 0.5, 0.5}, "[0, 1]"},
        {"light", "strength", {-1.0, 0, 0}, "/materials/light/strength"},
        {"light", "strength", {1e19, 0, 0}, "1e+18"},
        {"environment", "scale", {1.0, 0, 0}, "no material or environment"},
    };
    for (const Case& c : cases) {
        try {
            scene.setLook(c.item, c.property, c.value);
            ADD_FAILURE() << c.item << "." << c.property << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(c.mention), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(scene.lookRevision(), revision);
    const std::vector<LookItem> items = scene.look();
    const LookItem* red = findItem(items, "red");
    EXPECT_NEAR(findProperty(*red, "albedo")->value[1], 0.065, 1e-6);
}

TEST(Look, AMovingShapeCannotBecomeALight) {
    test::TempDir dir("look_motion");
    dir.write("ball.obj", test::sphereObj(1.0f, 6, 8));
    const fs::path file = dir.write("moving.json", R"({
      "camera": {"position": [0, 0, 5], "lookAt": [0, 0, 0]},
      "film": {"width": 8, "height": 8},
      "materials": {"ball": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "shapes": [{"obj": "ball.obj", "material": "ball", "motion": {"translate": [1, 0, 0]}}],
      "environment": {"color": [1, 1, 1]}
    })");
    Scene scene = loadScene(file);
    try {
        scene.setLook("ball", "strength", 5.0);
        ADD_FAILURE() << "emission accepted on a moving shape";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("moving"), std::string::npos) << e.what();
    }
    // The colour of a constant environment is editable.
    EXPECT_NO_THROW(scene.setLook("environment", "color", {0.2, 0.3, 0.4}));
}

TEST(Look, SaveRefusesAnUnwritablePathAndLeavesNothingBehind) {
    test::TempDir dir("look_unwritable");
    const Scene scene = loadScene(cornellCopy(dir));
    EXPECT_THROW(saveScene(scene, dir.path() / "missing" / "folder" / "x.json"), Error);
    EXPECT_FALSE(fs::exists(dir.path() / "missing"));
}

// The Khronos duck (textured, metallic 0, roughness 1) placed by a scene.json in `dir`, 24×24.
fs::path duckScene(const test::TempDir& dir, const nlohmann::json& shapeExtra = {}) {
    nlohmann::json shape = {{"gltf", (kScenes / "assets/duck/Duck.glb").string()}};
    for (const auto& item : shapeExtra.items()) shape[item.key()] = item.value();
    const nlohmann::json j = {{"film", {{"width", 24}, {"height", 24}}},
                              {"environment", {{"color", {1, 1, 1}}}},
                              {"shapes", {shape}}};
    return dir.write("duck.json", j.dump(2));
}

TEST(Look, AGltfMaterialsFactorsEditSaveAsTheShapesEditsAndKeepTheTextures) {
    test::TempDir dir("look_gltf");
    Renderer renderer(loadScene(duckScene(dir)));
    const std::vector<LookItem> items = renderer.scene().look();
    const LookItem* duck = findItem(items, "blinn3-fx");
    ASSERT_NE(duck, nullptr);
    EXPECT_EQ(duck->type, "metallicRoughness");
    for (const char* name :
         {"albedo", "metallic", "roughness", "ior", "transmission", "emission", "strength"})
        EXPECT_NE(findProperty(*duck, name), nullptr) << name;
    EXPECT_EQ(findProperty(*duck, "albedo")->label, "base colour factor");  // textured
    EXPECT_EQ(findProperty(*duck, "metallic")->value[0], 0.0);
    EXPECT_EQ(findProperty(*duck, "roughness")->value[0], 1.0);

    const FrameBuffers before = renderer.render(small(renderer)).frame;
    renderer.scene().setLook("blinn3-fx", "metallic", 1.0);
    renderer.scene().setLook("blinn3-fx", "roughness", 0.25);
    renderer.scene().setLook("blinn3-fx", "albedo", {0.5, 0.6, 0.7});
    renderer.scene().setLook("blinn3-fx", "transmission", 0.5);
    const FrameBuffers after = renderer.render(small(renderer)).frame;
    EXPECT_EQ(detail::accelerationBuilds(renderer), 1);
    EXPECT_FALSE(test::sameLayer(before, after, Layer::Color));

    const fs::path saved = dir.path() / "edited.json";
    saveScene(renderer.scene(), saved);
    nlohmann::json j;
    std::ifstream(saved) >> j;
    ASSERT_FALSE(j.contains("materials")) << j.dump();  // not a JSON material: no texture lost
    const nlohmann::json& edit = j["shapes"][0]["edits"]["blinn3-fx"];
    EXPECT_EQ(edit["metallic"], 1.0);
    EXPECT_EQ(edit["roughness"], 0.25);
    EXPECT_EQ(edit["transmission"], 0.5);
    EXPECT_NEAR(edit["albedo"][2].get<double>(), 0.7, 1e-6);
    Renderer reloaded(loadScene(saved));
    test::expectSameFrames(after, reloaded.render(small(reloaded)).frame);
    const std::vector<LookItem> reloadedItems = reloaded.scene().look();
    const LookItem* again = findItem(reloadedItems, "blinn3-fx");
    ASSERT_NE(again, nullptr);
    EXPECT_EQ(findProperty(*again, "albedo")->label, "base colour factor");  // still textured
    EXPECT_EQ(findProperty(*again, "metallic")->value[0], 1.0);
}

TEST(Look, ABareAssetsEditsSaveAsAScenePlacingIt) {
    test::TempDir dir("look_bare");
    Renderer renderer(loadScene(kScenes / "assets/duck/Duck.glb"));
    renderer.scene().setLook("blinn3-fx", "roughness", 0.3);
    Settings s = small(renderer, 1);
    const FrameBuffers edited = renderer.render(s).frame;
    const fs::path saved = dir.path() / "duck.json";
    saveScene(renderer.scene(), saved);
    Renderer reloaded(loadScene(saved));
    test::expectSameFrames(edited, reloaded.render(s).frame);
}

TEST(Look, BadGltfEditsAreRefusedNamingThePlace) {
    test::TempDir dir("look_gltf_bad");
    const std::vector<std::pair<nlohmann::json, std::string>> cases = {
        {{{"edits", {{"nope", {{"metallic", 1}}}}}}, "/shapes/0/edits/nope"},
        {{{"edits", {{"blinn3-fx", {{"metallic", 2}}}}}}, "/shapes/0/edits/blinn3-fx/metallic"},
        {{{"edits", {{"blinn3-fx", {{"shininess", 2}}}}}}, "/shapes/0/edits/blinn3-fx/shininess"},
        {{{"edits", {{"blinn3-fx", {{"ior", 0.5}}}}}}, "/shapes/0/edits/blinn3-fx/ior"},
        {{{"edits", 3}}, "/shapes/0/edits"}};
    for (const auto& [extra, place] : cases) {
        try {
            loadScene(duckScene(dir, extra));
            ADD_FAILURE() << extra.dump() << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), place) << e.what();
        }
    }
    Scene scene = loadScene(duckScene(dir));
    EXPECT_THROW(scene.setLook("blinn3-fx", "metallic", 1.5), Error);
    EXPECT_THROW(scene.setLook("blinn3-fx", "ior", 0.9), Error);
}

}  // namespace
}  // namespace glint::render
