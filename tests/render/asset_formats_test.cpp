// The asset formats as kinds (scene/asset_format.h): a format registered here, in the test, is
// loaded as a bare asset and as a scene.json shape, listed in the public list, checked against
// the memory limit by its own prediction and named in the shape messages, with no change to
// the loader. And the scene's bounding box, computed once when loading ends.
#include <cctype>
#include <cstdio>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/render/asset_formats.h"
#include "glint/render/scene.h"
#include "scene/asset_format.h"
#include "scene/loader.h"
#include "scene/scene_access.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

/// The toy format's import: a ".tri" file is nine numbers, one triangle, of material "toy".
void importToyTriangle(detail::Loader& loader, const detail::AssetShape& shape) {
    std::ifstream in(shape.file);
    detail::Mesh mesh;
    mesh.name = shape.file.filename().string();
    for (int v = 0; v < 3; ++v) {
        Vec3 p;
        if (!(in >> p.x >> p.y >> p.z))
            throw Error(ErrorKind::Format, "expected nine numbers", shape.file.string());
        mesh.positions.push_back(p);
    }
    mesh.indices = {0, 1, 2};
    int material = loader.materialIndex("toy");
    if (material < 0) {
        detail::Material m;
        m.name = "toy";
        material = loader.addMaterial(std::move(m));
    }
    mesh.materials = {std::uint32_t(material)};
    detail::SceneData& scene = loader.scene();
    scene.meshes.push_back(std::move(mesh));
    loader.placeMesh(std::uint32_t(scene.meshes.size() - 1), shape);
}

/// A prediction of 1 GB for every toy file, so that a memory limit refuses it.
detail::LoadPrediction predictToyLoad(const fs::path&) {
    detail::LoadPrediction p;
    p.bytes = std::uint64_t(1) << 30;
    p.counted = "one toy triangle";
    p.advice = "toys are small";
    return p;
}

detail::AssetFormat toyFormat() {
    detail::AssetFormat f;
    f.name = "Toy triangle";
    f.key = "tri";
    f.shapeDescription = "a toy triangle file";
    f.fileWord = "toy";
    f.expected = "a .tri file";
    f.extensions = {".tri"};
    f.predictLoad = predictToyLoad;
    f.import = importToyTriangle;
    return f;
}

TEST(AssetFormats, AFormatRegisteredInTheTestIsListedAndLoadsAsABareAsset) {
    const detail::AssetFormat toy = toyFormat();
    const detail::ScopedAssetFormat registered(toy);
    EXPECT_EQ(assetExtensions().back(), ".tri");
    EXPECT_EQ(assetFormats().back().name, "Toy triangle");
    EXPECT_TRUE(isAssetFile("A.TRI"));
    test::TempDir dir("toy_bare");
    const fs::path asset = dir.write("one.tri", "0 0 0  1 0 0  0 1 0\n");
    const Scene scene = loadScene(asset);
    EXPECT_EQ(scene.triangleCount(), 1u);
    EXPECT_TRUE(scene.hasEnvironment());  // no light of its own: the constant sky
    EXPECT_EQ(scene.width(), 640);
    // The framing camera looks at the centre of the box.
    const detail::SceneData& data = detail::sceneData(scene);
    EXPECT_EQ(data.camera.lookAt.x, 0.5f);
    EXPECT_EQ(data.camera.lookAt.y, 0.5f);
    // Saved as the scene.json it stands for, with the format's key.
    EXPECT_NE(data.sourceJson.find("\"tri\": \"one.tri\""), std::string::npos) << data.sourceJson;
}

TEST(AssetFormats, AFormatRegisteredInTheTestIsAShapeWithItsKeyAndItsMessages) {
    const detail::AssetFormat toy = toyFormat();
    const detail::ScopedAssetFormat registered(toy);
    test::TempDir dir("toy_shape");
    dir.write("one.tri", "0 0 0  1 0 0  0 1 0\n");
    dir.write("quad.obj", test::quadObj());
    const Scene scene =
        loadScene(dir.write("scene.json",
                            R"({"film": {"width": 4, "height": 4}, "shapes": [{"tri": "one.tri"},
             {"tri": "one.tri", "transform": {"translate": [0, 0, 5]}}, {"obj": "quad.obj"}]})"));
    EXPECT_EQ(scene.triangleCount(), 4u);
    auto error = [&](const std::string& shape, std::uint64_t limit = 0) {
        try {
            loadScene(dir.write("bad.json", R"({"film": {"width": 4, "height": 4}, "shapes": [)" +
                                                shape + "]}"),
                      limit);
        } catch (const Error& e) {
            return e;
        }
        ADD_FAILURE() << "no error for " << shape;
        return Error(ErrorKind::Internal, "none");
    };
    const Error none = error(R"({"material": "x"})");
    EXPECT_EQ(none.where(), "/shapes/0");
    EXPECT_NE(none.message().find("or 'tri' (a toy triangle file)"), std::string::npos)
        << none.what();
    const Error unknown = error(R"({"tri": "one.tri", "size": 2})");
    EXPECT_NE(unknown.message().find("expected one of: obj, gltf, tri, material"),
              std::string::npos)
        << unknown.what();
    const Error edits = error(R"({"tri": "one.tri", "edits": {}})");
    EXPECT_EQ(edits.where(), "/shapes/0/edits");
    EXPECT_NE(edits.message().find("'edits' does not apply to a toy triangle file"),
              std::string::npos)
        << edits.what();
    // A format's own reason for another format's key, as the OBJ format gives it.
    const Error objEdits = error(R"({"obj": "quad.obj", "edits": {}})");
    EXPECT_EQ(objEdits.where(), "/shapes/0/edits");
    EXPECT_EQ(objEdits.message(),
              "'edits' changes a glTF asset's material factors; an OBJ shape's materials are "
              "edited as JSON materials of the same name");
    const Error objMaterials = error(R"({"obj": "quad.obj", "materials": {}, "edits": {}})");
    EXPECT_EQ(objMaterials.where(), "/shapes/0/materials");
    const Error missing = error(R"({"tri": "none.tri"})");
    EXPECT_EQ(missing.where(), "/shapes/0/tri");
    EXPECT_NE(missing.message().find("toy file"), std::string::npos) << missing.what();
    // The memory limit asks the format's own prediction, and says its advice.
    const Error memory = error(R"({"tri": "one.tri"})", std::uint64_t(1) << 20);
    EXPECT_EQ(memory.kind(), ErrorKind::OutOfMemory);
    EXPECT_NE(memory.message().find("one toy triangle"), std::string::npos) << memory.what();
    EXPECT_NE(memory.message().find("; toys are small"), std::string::npos) << memory.what();
}

TEST(AssetFormats, WithoutTheRegistrationTheExtensionIsNoAsset) {
    {
        const detail::AssetFormat toy = toyFormat();
        const detail::ScopedAssetFormat registered(toy);
        EXPECT_TRUE(isAssetFile("one.tri"));
    }
    EXPECT_FALSE(isAssetFile("one.tri"));
    for (const std::string& ext : assetExtensions()) EXPECT_NE(ext, ".tri");
}

TEST(AssetFormats, TheBuiltInFormatsListTheirExtensionsInLowerCase) {
    std::vector<std::string> keys;
    for (const AssetFormatInfo& f : assetFormats()) {
        keys.push_back(f.key);
        for (const std::string& ext : f.extensions) {
            EXPECT_EQ(ext.front(), '.');
            for (char c : ext) EXPECT_FALSE(std::isupper(static_cast<unsigned char>(c))) << ext;
            EXPECT_TRUE(isAssetFile("MODEL" + ext));
        }
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"obj", "gltf"}));
    EXPECT_EQ(assetExtensions(), (std::vector<std::string>{".obj", ".gltf", ".glb"}));
    EXPECT_FALSE(isAssetFile("scene.json"));
}

TEST(SceneBounds, TheBoxIsTheShutterOpenPoseAndTheExtentEveryPose) {
    test::TempDir dir("bounds");
    dir.write("quad.obj", test::quadObj());
    const Scene scene = loadScene(dir.write("scene.json", R"({"film": {"width": 4, "height": 4},
        "shapes": [{"obj": "quad.obj", "transform": {"translate": [10, 0, 0]},
                    "motion": {"translate": [30, 0, 0]}}]})"));
    const detail::SceneData& data = detail::sceneData(scene);
    ASSERT_FALSE(data.bounds.empty());
    // test::quadObj() spans [-1, 1] in x; at shutter open it is moved by 10, at close by 30.
    EXPECT_EQ(data.bounds.lo.x, 9.0f);
    EXPECT_EQ(data.bounds.hi.x, 11.0f);
    EXPECT_EQ(data.extent, 22.0f);  // x from 9 to 31
}

TEST(SceneBounds, ASceneWithoutGeometryHasAnEmptyBox) {
    test::TempDir dir("bounds_empty");
    const Scene scene = loadScene(
        dir.write("scene.json",
                  R"({"film": {"width": 4, "height": 4}, "environment": {"color": [1, 1, 1]}})"));
    EXPECT_TRUE(detail::sceneData(scene).bounds.empty());
    EXPECT_EQ(detail::sceneData(scene).extent, 1.0f);
}

}  // namespace
}  // namespace glint::render
