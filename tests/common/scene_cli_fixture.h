// A CLI fixture with a scene: before each test, scene.json in the test's temporary folder renders
// the Cornell box OBJ of tests/render/data (GLINT_RENDER_TEST_DATA) at a tiny film, for the tests
// of the CLIs that render (glint-render, glint-final).
#pragma once

#include <fstream>
#include <string>
#include <utility>

#include "cli_fixture.h"

namespace glint::testing {

/// The film and path length of the scene a SceneCliFixture writes (4 spp).
struct TinyScene {
    int width = 24;
    int height = 24;
    int maxDepth = 4;
};

/// CliFixture for `binaryName` whose SetUp also writes scene.json (path("scene.json")).
class SceneCliFixture : public CliFixture {
  protected:
    SceneCliFixture(std::string binaryName, TinyScene scene)
        : CliFixture(std::move(binaryName)), m_scene(scene) {}

    void SetUp() override {
        CliFixture::SetUp();
        if (HasFatalFailure()) return;
        const std::string obj = std::string(GLINT_RENDER_TEST_DATA) + "/cornell_box.obj";
        std::ofstream(m_dir / "scene.json")
            << R"({"camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], )"
            << R"("fovY": 39.3}, "film": {"width": )" << m_scene.width << R"(, "height": )"
            << m_scene.height << R"(}, "shapes": [{"obj": ")" << obj << R"("}], )"
            << R"("render": {"spp": 4, "maxDepth": )" << m_scene.maxDepth << "}}";
    }

  private:
    TinyScene m_scene;
};

}  // namespace glint::testing
