// A camera without a view basis in float (up zero, too short to normalise, parallel to the view
// direction) is bad input on every path that sets a camera: scene.json (loadScene, the studio's
// Document), a glTF asset's camera node, and a Scene handed to the Renderer API. It used to reach
// Embree as NaN rays (an assertion, exit 134) with the path and Metropolis integrators alike.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

// The up vectors of the report: zero, and two too short to normalise in float.
const std::vector<std::string> kDegenerateUps = {"[0, 0, 0]", "[0, 1e-30, 0]", "[0, 1e-40, 0]"};

std::string sceneWithUp(const std::string& up) {
    return R"({"camera": {"position": [0.3, 0.3, 3], "lookAt": [0.3, 0.3, 0], "up": )" + up +
           R"(}, "film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj"}],
      "environment": {"color": [1, 1, 1]}})";
}

const char* kCameraTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

TEST(CameraBasis, ADegenerateUpInSceneJsonIsOneErrorNamingCameraUp) {
    std::vector<std::string> ups = kDegenerateUps;
    ups.push_back("[0, 0, -2]");  // parallel to the view direction
    for (const std::string& up : ups) {
        test::TempDir dir("camera_up");
        dir.write("mesh.obj", kCameraTriangle);
        const fs::path file = dir.write("scene.json", sceneWithUp(up));
        try {
            loadScene(file);
            ADD_FAILURE() << up << ": loaded";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << up << ": " << e.what();
            EXPECT_EQ(fs::path(e.file()), file) << up << ": " << e.what();
            EXPECT_EQ(e.where(), "/camera/up") << up << ": " << e.what();
        }
    }
}

// (A zero scale makes the node's transform singular: the reader skips what such a node holds,
// with a warning, so the asset is framed by a camera of Glint's.)
TEST(CameraBasis, AGltfCameraNodeSquashedAlongItsUpIsRefusedNamingTheNode) {
    for (const double scale : {1e-30, 1e-40}) {
        test::TempDir dir("gltf_camera_up");
        test_gltf::GltfBuilder b;
        const int mesh = b.quad();
        b.doc["cameras"] = test_gltf::json::array(
            {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}});
        b.scene(
            {b.node({{"mesh", mesh}}),
             b.node({{"camera", 0}, {"translation", {0.5, 0.5, 3}}, {"scale", {1, scale, 1}}})});
        const fs::path asset = test_gltf::writeBytes(dir.path() / "model.glb", b.glb());
        try {
            loadScene(asset);
            ADD_FAILURE() << scale << ": loaded";
        } catch (const Error& e) {
            EXPECT_NE(e.kind(), ErrorKind::Internal) << e.what();
            EXPECT_EQ(fs::path(e.file()).filename(), "model.glb") << e.what();
            EXPECT_EQ(e.where(), "nodes[1]") << e.what();
            EXPECT_NE(std::string(e.what()).find("degenerate orientation"), std::string::npos)
                << e.what();
        }
    }
}

// A Scene made without the loader (the Renderer API's own contract): refused before the BVH is
// built, not traced as NaN rays.
TEST(CameraBasis, TheRendererRefusesASceneWhoseCameraHasNoViewBasis) {
    const std::vector<Vec3> ups = {{0, 0, 0}, {0, 1e-30f, 0}, {0, 1e-40f, 0}, {0, 0, 1}};
    for (const Vec3& up : ups) {
        auto data = std::make_unique<detail::SceneData>();
        data->path = "api-scene.json";
        data->width = data->height = 8;
        data->camera.position = {0, 0, 0};
        data->camera.lookAt = {0, 0, -1};
        data->camera.up = up;
        data->environment.kind = detail::EnvironmentDesc::Kind::Constant;
        data->environment.baseColor = data->environment.color = {1, 1, 1};
        try {
            Renderer renderer(Scene(std::move(data)));
            ADD_FAILURE() << up.y << ", " << up.z << ": built";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument) << e.what();
            EXPECT_EQ(e.file(), "api-scene.json") << e.what();
            EXPECT_EQ(e.where(), "/camera/up") << e.what();
        }
    }
}

class CameraBasisCli : public glint::testing::CliFixture {
  protected:
    CameraBasisCli() : CliFixture("glint-render") {}
};

TEST_F(CameraBasisCli, ADegenerateUpExitsTwoWithTheIntegratorAndAccelerationOfTheReport) {
    std::ofstream(m_dir / "mesh.obj") << kCameraTriangle;
    for (std::size_t i = 0; i < kDegenerateUps.size(); ++i) {
        const std::string scene = path("scene" + std::to_string(i) + ".json");
        std::ofstream(scene) << sceneWithUp(kDegenerateUps[i]);
        for (const char* extra : {"", " --set integrator=mlt", " --set accel=clusters"}) {
            const auto r = run(scene + " --spp 1" + extra + " --out " + path("out.exr"));
            const std::string what = kDegenerateUps[i] + extra;
            EXPECT_EQ(r.exitCode, 2) << what << "\n" << r.err;
            EXPECT_NE(r.err.find("scene" + std::to_string(i) + ".json: /camera/up: "),
                      std::string::npos)
                << what << "\n"
                << r.err;
            EXPECT_FALSE(fs::exists(path("out.exr"))) << what;
        }
    }
}

}  // namespace
}  // namespace glint::render
