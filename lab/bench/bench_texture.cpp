// bench_texture: the cost of large textures read through the TextureSystem (issue 32, item 3).
// Writes four 2048² tiled, MIP-mapped half-float EXR textures (make_texture, as maketx would)
// and a 2 × 2 grid of UV spheres into a temporary folder, then renders the asset textured and
// untextured (albedo 0.5 instead) with a texture cache of a quarter of the textures' size.
// After one untimed warm-up render of each, the timed renders alternate in --repeat pairs
// (untextured then textured, then textured then untextured, …) so that a change of the machine's
// load falls on both halves of a pair alike. Prints one JSON object: both times (median of
// --repeat; wall and the process's CPU time), the median and range of the pairs' ratios, the
// ratio of the medians, the textures' bytes, the cache size and the process's peak resident
// memory during each warm-up render (each with only its own renderer in the process).
//   bench_texture [--size 512] [--spp 16] [--threads 2] [--repeat 3] [--texture 2048]
//                 [--cache-mb MB (default: a quarter of the textures' size in memory)]
//                 [--untextured 0|1] [--textured 0|1] (0: skip that render, e.g. for perf record)
//                 [--keep 1] (keep the folder with the scenes and textures; its path is printed)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <nlohmann/json.hpp>

#include "bench_options.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace {

namespace fs = std::filesystem;

/// OBJ text of a UV sphere of radius 1 with normals and texture coordinates (u around, v up).
std::string sphereObj(int stacks, int slices) {
    std::string s;
    char line[160];
    const double pi = 3.14159265358979323846;
    for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j <= slices; ++j) {
            const double theta = pi * i / stacks, phi = 2.0 * pi * j / slices;
            const double x = std::sin(theta) * std::cos(phi), y = std::cos(theta),
                         z = std::sin(theta) * std::sin(phi);
            std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\nvn %.6f %.6f %.6f\nvt %.6f %.6f\n",
                          x, y, z, x, y, z, double(j) / slices, 1.0 - double(i) / stacks);
            s += line;
        }
    auto at = [&](int i, int j) { return i * (slices + 1) + j + 1; };
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const int a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, b,
                          b, b, c, c, c, d, d, d);
            s += line;
        }
    return s;
}

/// Writes texture `index`: 64-texel squares of 0.2 and 0.8 with uniform noise of ±0.1 on top,
/// as a tiled (64²), MIP-mapped half-float EXR.
void writeTexture(const fs::path& file, int size, int index) {
    OIIO::ImageBuf image(OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::FLOAT));
    const float light[3] = {0.8f, 0.7f - 0.1f * float(index), 0.6f}, dark[3] = {0.2f, 0.2f, 0.25f};
    OIIO::ImageBufAlgo::checker(image, 64, 64, 1, light, dark);
    OIIO::ImageBufAlgo::noise(image, "uniform", -0.1f, 0.1f, false, index + 1);
    OIIO::ImageSpec config;
    config.tile_width = config.tile_height = 64;
    config.set_format(OIIO::TypeDesc::HALF);
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, image, file.string(),
                                          config))
        throw glint::Error(glint::ErrorKind::Io, "make_texture failed: " + OIIO::geterror(),
                           file.string());
}

/// The scene: four spheres in a 2 × 2 grid, sphere k textured by tK.exr (or grey), a white sky.
std::string sceneJson(bool textured, int size, int spp) {
    nlohmann::json materials = nlohmann::json::object();
    nlohmann::json shapes = nlohmann::json::array();
    const double centres[4][2] = {{-1.05, 2.1}, {1.05, 2.1}, {-1.05, 0.0}, {1.05, 0.0}};
    for (int k = 0; k < 4; ++k) {
        const std::string name = "m" + std::to_string(k);
        materials[name] =
            textured
                ? nlohmann::json{{"type", "diffuse"}, {"texture", "t" + std::to_string(k) + ".exr"}}
                : nlohmann::json{{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}};
        shapes.push_back({{"obj", "sphere.obj"},
                          {"material", name},
                          {"transform", {{"translate", {centres[k][0], centres[k][1], 0.0}}}}});
    }
    const nlohmann::json j = {
        {"camera", {{"position", {0, 1.05, 6.5}}, {"lookAt", {0, 1.05, 0}}, {"fovY", 40}}},
        {"film", {{"width", size}, {"height", size}}},
        {"materials", materials},
        {"shapes", shapes},
        {"environment", {{"color", {1, 1, 1}}}},
        {"render", {{"spp", spp}, {"maxDepth", 8}}}};
    return j.dump(2);
}

/// A /proc/self/status figure in bytes ("VmHWM", "VmRSS").
std::uint64_t procStatusBytes(const std::string& key) {
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1)) * 1024;
    return 0;
}

/// The process's CPU time so far (user + system), in seconds.
double cpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
    return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

/// Resets the peak resident size (VmHWM) to the current one (Linux 4.0+).
void resetPeakRss() {
    std::ofstream("/proc/self/clear_refs") << "5";
}

}  // namespace

int main(int argc, char** argv) {
    int size = 512, spp = 16, threads = 2, repeat = 3, textureSize = 2048, cacheOption = 0;
    int runUntextured = 1, runTextured = 1, keep = 0;
    if (const int code = glint::bench::parseOptions(
            "bench_texture", argc, argv, [&](const std::string& name, const std::string& value) {
                const int v = glint::bench::intOption(name, value);
                if (name == "--size")
                    size = v;
                else if (name == "--spp")
                    spp = v;
                else if (name == "--threads")
                    threads = v;
                else if (name == "--repeat")
                    repeat = std::max(1, v);
                else if (name == "--texture")
                    textureSize = v;
                else if (name == "--cache-mb")
                    cacheOption = v;
                else if (name == "--untextured")
                    runUntextured = v;
                else if (name == "--textured")
                    runTextured = v;
                else if (name == "--keep")
                    keep = v;
                else
                    return false;
                return true;
            }))
        return code;
    const fs::path dir =
        fs::temp_directory_path() / ("glint_bench_texture_" + std::to_string(::getpid()));
    try {
        fs::create_directories(dir);
        std::ofstream(dir / "sphere.obj") << sphereObj(64, 128);
        std::uint64_t textureBytes = 0;
        for (int k = 0; k < 4; ++k) {
            const fs::path file = dir / ("t" + std::to_string(k) + ".exr");
            writeTexture(file, textureSize, k);
            textureBytes += fs::file_size(file);
        }
        // A quarter of the textures' size in memory (half floats, RGB, with MIP levels: the
        // files are zip-compressed, so their size on disk is less).
        const std::uint64_t memoryBytes = std::uint64_t(4) * std::uint64_t(textureSize) *
                                          std::uint64_t(textureSize) * 3 * 2 * 4 / 3;
        const int cacheMb =
            cacheOption > 0 ? cacheOption : std::max(1, int(memoryBytes / 4 / (1 << 20)));
        std::ofstream(dir / "textured.json") << sceneJson(true, size, spp);
        std::ofstream(dir / "plain.json") << sceneJson(false, size, spp);

        // Wall and CPU seconds of one render (the process's user + system time over the render:
        // on a shared machine it counts the render's work, not the waits for a core).
        struct Timing {
            double wall = 0.0, cpu = 0.0;
        };
        using Renderer = glint::render::Renderer;
        auto settingsOf = [&](const Renderer& renderer) {
            glint::render::Settings s = renderer.scene().settings();
            s.threads = threads;
            s.textureCacheMb = cacheMb;
            return s;
        };
        auto timeOnce = [&](Renderer& renderer) {
            const glint::render::Settings s = settingsOf(renderer);
            const double before = cpuSeconds();
            const double wall = renderer.render(s).stats.seconds;
            return Timing{wall, cpuSeconds() - before};
        };
        // The untimed warm-up render of a new renderer, and the process's peak resident size
        // over it (reset before the renderer is made).
        auto warmUp = [&](const fs::path& scene, std::uint64_t& peakRss) {
            resetPeakRss();
            auto renderer = std::make_unique<Renderer>(glint::render::loadScene(scene));
            timeOnce(*renderer);
            peakRss = procStatusBytes("VmHWM");
            return renderer;
        };
        // Warm up each alone for its peak: the untextured renderer is dropped before the textured
        // one is made, then made and warmed up again for the timed pairs.
        std::uint64_t plainRss = 0, texturedRss = 0, unused = 0;
        std::unique_ptr<Renderer> plainRenderer, texturedRenderer;
        if (runUntextured) plainRenderer = warmUp(dir / "plain.json", plainRss);
        if (runTextured) {
            plainRenderer.reset();
            texturedRenderer = warmUp(dir / "textured.json", texturedRss);
            if (runUntextured) plainRenderer = warmUp(dir / "plain.json", unused);
        }
        // The timed renders: pair r runs untextured first for even r, textured first for odd r.
        std::vector<Timing> plainTimes, texturedTimes;
        for (int r = 0; r < repeat; ++r) {
            const bool plainFirst = r % 2 == 0;
            if (plainRenderer && plainFirst) plainTimes.push_back(timeOnce(*plainRenderer));
            if (texturedRenderer) texturedTimes.push_back(timeOnce(*texturedRenderer));
            if (plainRenderer && !plainFirst) plainTimes.push_back(timeOnce(*plainRenderer));
        }
        auto median = [](std::vector<double> v) {
            if (v.empty()) return 0.0;
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        auto medianOf = [&](const std::vector<Timing>& times) {
            std::vector<double> wall, cpu;
            for (const Timing& t : times) {
                wall.push_back(t.wall);
                cpu.push_back(t.cpu);
            }
            return Timing{median(wall), median(cpu)};
        };
        const Timing plain = medianOf(plainTimes), textured = medianOf(texturedTimes);
        // Each pair's textured / untextured ratio (none when either render is skipped).
        std::vector<double> pairWall, pairCpu;
        for (std::size_t r = 0; r < plainTimes.size() && r < texturedTimes.size(); ++r) {
            if (plainTimes[r].wall > 0.0)
                pairWall.push_back(texturedTimes[r].wall / plainTimes[r].wall);
            if (plainTimes[r].cpu > 0.0)
                pairCpu.push_back(texturedTimes[r].cpu / plainTimes[r].cpu);
        }
        auto low = [](const std::vector<double>& v) {
            return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
        };
        auto high = [](const std::vector<double>& v) {
            return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
        };
        const nlohmann::json j = {{"folder", keep ? dir.string() : std::string()},
                                  {"width", size},
                                  {"height", size},
                                  {"spp", spp},
                                  {"threads", threads},
                                  {"repeat", repeat},
                                  {"textures", 4},
                                  {"textureSize", textureSize},
                                  {"textureFileBytes", textureBytes},
                                  {"textureMemoryBytes", memoryBytes},
                                  {"textureCacheMb", cacheMb},
                                  {"secondsUntextured", plain.wall},
                                  {"secondsTextured", textured.wall},
                                  {"ratio", plain.wall > 0.0 ? textured.wall / plain.wall : 0.0},
                                  {"cpuSecondsUntextured", plain.cpu},
                                  {"cpuSecondsTextured", textured.cpu},
                                  {"cpuRatio", plain.cpu > 0.0 ? textured.cpu / plain.cpu : 0.0},
                                  {"peakRssUntexturedMb", double(plainRss) / (1 << 20)},
                                  {"peakRssTexturedMb", double(texturedRss) / (1 << 20)},
                                  {"order", "interleaved"},
                                  {"pairRatio", median(pairWall)},
                                  {"pairRatioMin", low(pairWall)},
                                  {"pairRatioMax", high(pairWall)},
                                  {"cpuPairRatio", median(pairCpu)},
                                  {"cpuPairRatioMin", low(pairCpu)},
                                  {"cpuPairRatioMax", high(pairCpu)},
                                  {"pairRatios", pairWall},
                                  {"cpuPairRatios", pairCpu}};
        std::cout << j.dump(2) << "\n";
        if (keep) return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_texture: %s\n", e.what());
        fs::remove_all(dir);
        return 2;
    }
    fs::remove_all(dir);
    return 0;
}
