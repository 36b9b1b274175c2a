// Bad scenes give one clear glint::Error naming the file and the place.
#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// Loads `json` from a temp folder holding a quad.obj; returns the error thrown.
Error loadError(const std::string& json, bool withObj = true) {
    test::TempDir dir("errors");
    if (withObj) dir.write("quad.obj", test::quadObj());
    const auto path = dir.write("scene.json", json);
    try {
        loadScene(path);
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), path.string()) << e.what();
        return e;
    }
    ADD_FAILURE() << "no error for: " << json;
    return Error(ErrorKind::Internal, "none");
}

const char* kGood = R"({"film": {"width": 4, "height": 4}, "shapes": [{"obj": "quad.obj"}]})";

TEST(SceneErrors, GoodSceneLoads) {
    test::TempDir dir("good");
    dir.write("quad.obj", test::quadObj());
    const Scene scene = loadScene(dir.write("scene.json", kGood));
    EXPECT_EQ(scene.width(), 4);
    EXPECT_EQ(scene.triangleCount(), 2u);
    EXPECT_FALSE(scene.hasEnvironment());
}

TEST(SceneErrors, MalformedJsonGivesLineAndColumn) {
    const Error e = loadError("{\n  \"film\": {\"width\": 4,\n    \"height\": }\n}");
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_EQ(e.where(), "line 3, column 15") << e.what();
}

TEST(SceneErrors, MissingObjNamesTheFile) {
    const Error e =
        loadError(R"({"film": {"width": 4, "height": 4}, "shapes": [{"obj": "nope.obj"}]})");
    EXPECT_EQ(e.kind(), ErrorKind::Io);
    EXPECT_EQ(e.where(), "/shapes/0/obj");
    EXPECT_NE(e.message().find("nope.obj"), std::string::npos) << e.what();
}

TEST(SceneErrors, UnknownMaterialTypeNamesTheJsonPath) {
    const Error e = loadError(R"({"film": {"width": 4, "height": 4},
      "materials": {"gold": {"type": "metal"}}, "shapes": [{"obj": "quad.obj"}]})");
    EXPECT_EQ(e.where(), "/materials/gold/type");
    EXPECT_NE(e.message().find("metal"), std::string::npos);
}

TEST(SceneErrors, AKeyOfAnotherMaterialKindNamesItAndTheKeysOfTheKind) {
    // Each kind reads the parameters it describes: a dielectric's ior on a diffuse material
    // would be ignored, so it is refused.
    const Error e = loadError(R"({"film": {"width": 4, "height": 4},
      "materials": {"chalk": {"type": "diffuse", "ior": 1.5}}, "shapes": [{"obj": "quad.obj"}]})");
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_EQ(e.where(), "/materials/chalk/ior");
    EXPECT_NE(e.message().find("unknown key 'ior' (expected one of: type, texture, albedo, "
                               "emission)"),
              std::string::npos)
        << e.what();
}

TEST(SceneErrors, NegativeSpp) {
    const Error e = loadError(R"({"film": {"width": 4, "height": 4},
      "shapes": [{"obj": "quad.obj"}], "render": {"spp": -4}})");
    EXPECT_EQ(e.where(), "/render/spp");
    EXPECT_NE(e.message().find("-4"), std::string::npos);
}

TEST(SceneErrors, ZeroAreaLight) {
    test::TempDir dir("zero");
    dir.write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    const auto path = dir.write("scene.json", R"({"film": {"width": 4, "height": 4},
      "materials": {"lamp": {"type": "diffuse", "emission": [1, 1, 1]}},
      "shapes": [{"obj": "flat.obj", "material": "lamp"}]})");
    try {
        loadScene(path);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.where(), "/shapes/0");
        EXPECT_NE(e.message().find("zero-area light"), std::string::npos) << e.what();
    }
}

TEST(SceneErrors, UnknownKeyNamesKeyAndPath) {
    const Error e = loadError(R"({"film": {"width": 4, "height": 4, "depth": 3},
      "shapes": [{"obj": "quad.obj"}]})");
    EXPECT_EQ(e.where(), "/film/depth");
    EXPECT_NE(e.message().find("unknown key 'depth'"), std::string::npos);
}

TEST(SceneErrors, MissingFilmAndBadValues) {
    EXPECT_EQ(loadError(R"({"shapes": [{"obj": "quad.obj"}]})").where(), "/film");
    EXPECT_EQ(loadError(R"({"film": {"width": 0, "height": 4}})").where(), "/film/width");
    EXPECT_EQ(loadError(R"({"film": {"width": 4, "height": 4}, "shapes": [{"obj": "quad.obj",
      "material": "missing"}]})")
                  .where(),
              "/shapes/0/material");
    EXPECT_EQ(
        loadError(R"({"film": {"width": 4, "height": 4}, "environment": {"image": "sky.exr"}})")
            .where(),
        "/environment/image");
    EXPECT_EQ(loadError(R"({"film": {"width": 4, "height": 4}, "render": {"mis": "best"},
      "shapes": [{"obj": "quad.obj"}]})")
                  .where(),
              "/render/mis");
}

TEST(SceneErrors, MissingSceneFile) {
    try {
        loadScene("/nonexistent/scene.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Io);
        EXPECT_EQ(e.file(), "/nonexistent/scene.json");
    }
}

}  // namespace
}  // namespace glint::render
