// The fuzz harnesses (libFuzzer targets in tests/fuzz/, `make fuzz`) and the regression test
// that replays every file of tests/data/fuzz-regressions/ through them (docs/reliability.md).
// A harness feeds one input to a reader the way a user's file would reach it. A glint::Error
// of any kind but Internal is the expected answer to bad input; anything else — a crash, a
// sanitizer report, a broken invariant (ErrorKind::Internal), another exception — is a bug.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/tev_images.h"
#include "glint/image/tev_protocol.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace glint::fuzz {

namespace fs = std::filesystem;

/// A private folder (in /dev/shm when it exists) with a small mesh, material library and
/// textures that fuzzed scenes may reference.
inline const fs::path& workspace() {
    static const fs::path dir = [] {
        const fs::path base =
            fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
        static const fs::path d = base / ("glint-fuzz-" + std::to_string(::getpid()));
        fs::create_directories(d);
        std::atexit([] {
            std::error_code ec;
            fs::remove_all(d, ec);
        });
        std::ofstream(d / "quad.obj") << "mtllib quad.mtl\nv -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
                                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 1 0\n"
                                         "usemtl lamp\nf 1/1/1 4/4/1 3/3/1 2/2/1\n";
        std::ofstream(d / "quad.mtl") << "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1 1 1\n";
        Image tex(4, 4, 3, 0.5f);
        writeImage(tex, d / "tex.png");
        writeImage(tex, d / "sky.exr");
        return d;
    }();
    return dir;
}

/// Runs `body`; bad input must end as a glint::Error that is not Internal.
template <class Body>
void expectCleanError(const char* target, Body&& body) {
    try {
        body();
    } catch (const Error& e) {
        if (e.kind() == ErrorKind::Internal) {
            std::fprintf(stderr, "%s: broken invariant: %s\n", target, e.what());
            std::abort();
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: not a glint::Error: %s\n", target, e.what());
        std::abort();
    }
}

inline void writeFile(const fs::path& path, const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

/// Renders a loaded scene at 1 spp (an adaptive one at its spp, at most 32) when its film is tiny
/// (so that a fuzzed scene exercises the BVH, lights, integrator and adaptive passes, not just
/// the reader).
inline void renderIfSmall(render::Scene scene) {
    if (std::size_t(scene.width()) * std::size_t(scene.height()) > 256) return;
    render::Renderer renderer(std::move(scene));
    render::Settings s = renderer.scene().settings();
    // An adaptive scene keeps its budget (at most 32 a pixel), so that its passes run.
    s.spp = s.adaptive ? std::clamp(s.spp, 1, 32) : 1;
    s.maxDepth = 4;
    s.threads = 1;
    s.timeLimit = 0.0;
    s.integrator = render::Integrator::Path;
    renderer.render(s);
}

/// scene.json text, parsed as a file of the workspace (it may reference quad.obj, tex.png...).
inline void runSceneJson(const std::uint8_t* data, std::size_t size) {
    expectCleanError("scene_json", [&] {
        const std::string text(reinterpret_cast<const char*>(data), size);
        renderIfSmall(render::parseScene(text, workspace() / "fuzz.json"));
    });
}

/// An OBJ file (before the first NUL byte) and its MTL library (after it), loaded by a fixed
/// scene that references them.
inline void runObj(const std::uint8_t* data, std::size_t size) {
    expectCleanError("obj", [&] {
        std::size_t split = 0;
        while (split < size && data[split] != 0) ++split;
        writeFile(workspace() / "fuzz.obj", data, split);
        writeFile(workspace() / "fuzz.mtl", split < size ? data + split + 1 : data,
                  split < size ? size - split - 1 : 0);
        const std::string scene = R"({"camera": {"position": [0, 3, 4], "lookAt": [0, 0, 0]},
            "film": {"width": 8, "height": 8}, "shapes": [{"obj": "fuzz.obj"}],
            "environment": {"color": [0.5, 0.5, 0.5]}})";
        renderIfSmall(render::parseScene(scene, workspace() / "objscene.json"));
    });
}

/// An image file of the kind its first byte picks (PNG, JPEG, EXR, or whatever OpenImageIO
/// recognises), read as a texture is.
inline void runTexture(const std::uint8_t* data, std::size_t size) {
    expectCleanError("texture", [&] {
        if (size == 0) return;
        static const char* kinds[] = {".png", ".jpg", ".exr", ".hdr"};
        const fs::path file = workspace() / (std::string("fuzz") + kinds[data[0] % 4]);
        writeFile(file, data + 1, size - 1);
        const Image im = readImage(file, true);
        (void)im;
    });
}

/// A glTF asset — a .glb when it starts with the binary magic "glTF", else .gltf text (whose
/// buffers and images may be data URIs) — loaded by a fixed scene that places it, then as a
/// bare asset, and rendered when small.
inline void runGltf(const std::uint8_t* data, std::size_t size) {
    expectCleanError("gltf", [&] {
        const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
        const std::string name = binary ? "fuzz.glb" : "fuzz.gltf";
        writeFile(workspace() / name, data, size);
        const std::string scene = R"({"camera": {"position": [0, 1, 4], "lookAt": [0, 0, 0]},
            "film": {"width": 8, "height": 8}, "shapes": [{"gltf": ")" +
                                  name + R"("}],
            "environment": {"color": [0.5, 0.5, 0.5]}})";
        renderIfSmall(render::parseScene(scene, workspace() / "gltfscene.json"));
        const render::Scene bare = render::loadScene(workspace() / name);
        (void)bare;
    });
}

/// A layered EXR, read as glint-denoise and the studio read renders.
inline void runExr(const std::uint8_t* data, std::size_t size) {
    expectCleanError("exr", [&] {
        writeFile(workspace() / "fuzz.exr", data, size);
        const FrameBuffers frame = readExr(workspace() / "fuzz.exr");
        (void)frame;
    });
}

/// The most a fuzzed tev stream's images may hold (the studio passes 0, what is available: the
/// limit itself is tested in tests/image/tev_test.cpp).
inline constexpr std::uint64_t kTevMemory = std::uint64_t(256) << 20;

/// A TCP stream of tev packets as the studio's `--tev-listen` takes it (TevListener): the first
/// byte picks the size of the chunks the rest arrives in (1 … 1786 bytes); each whole packet is
/// decoded and applied, one the images refuse is dropped and the stream goes on, a broken length
/// field ends the stream; each image a packet changed becomes a frame, and a completed one is
/// forgotten.
inline void runTevStream(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return;
    expectCleanError("tev", [&] {
        const std::size_t chunk = 1 + std::size_t(data[0]) * 7;
        tev::PacketStream stream;
        tev::ReceivedImages images;
        for (std::size_t at = 1; at < size; at += chunk) {
            stream.append({data + at, std::min(chunk, size - at)});
            while (const auto bytes = stream.next()) {
                try {
                    const tev::Change change = images.apply(tev::decode(*bytes), kTevMemory);
                    if (change.kind == tev::Change::None || !images.has(change.name)) continue;
                    const FrameBuffers frame = images.frame(change.name);
                    (void)frame;
                    if (images.complete(change.name)) images.forget(change.name);
                } catch (const Error& e) {
                    if (e.kind() == ErrorKind::Internal) throw;  // a bug: expectCleanError aborts
                }
            }
        }
    });
}

}  // namespace glint::fuzz
