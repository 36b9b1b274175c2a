// Helpers shared by the integration tests: render a committed scene through the renderer's
// public API and read its committed reference EXR (paths relative to the repository root, the
// tests' working directory).
#pragma once

#include <string>

#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace glint::integration {

/// Renders scenes/<name>/scene.json with the file's render settings, `spp` samples per pixel
/// and `seed`, on all hardware threads (the output does not depend on the thread count).
inline FrameBuffers renderScene(const std::string& name, int spp, std::uint64_t seed) {
    render::Scene scene = render::loadScene("scenes/" + name + "/scene.json");
    render::Settings settings = scene.settings();
    settings.spp = spp;
    settings.seed = seed;
    settings.threads = 0;
    render::Renderer renderer(std::move(scene));
    return renderer.render(settings).frame;
}

/// Reads scenes/<name>/reference.exr.
inline FrameBuffers readReference(const std::string& name) {
    return readExr("scenes/" + name + "/reference.exr");
}

}  // namespace glint::integration
