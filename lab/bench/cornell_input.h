// The denoising benches' input (bench_auto, bench_bank): cornell at size × size, a low spp,
// rendered untimed.
#pragma once

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace glint::bench {

/// scenes/cornell at size² pixels and `spp` samples a pixel on `threads` threads, with half
/// buffers when `halves`.
inline FrameBuffers cornellInput(int size, int spp, int threads, bool halves) {
    const std::filesystem::path file =
        std::filesystem::path(GLINT_SOURCE_DIR) / "scenes/cornell/scene.json";
    std::ifstream in(file);
    nlohmann::json scene = nlohmann::json::parse(in);
    scene["film"] = {{"width", size}, {"height", size}};
    render::Renderer renderer(render::parseScene(scene.dump(), file));
    render::Settings s = renderer.scene().settings();
    s.spp = spp;
    s.threads = threads;
    s.halfBuffers = halves;
    return renderer.render(s).frame;
}

}  // namespace glint::bench
