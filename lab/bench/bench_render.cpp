// bench_render: cornell at 256×256, 64 spp, max depth 8, 2 threads (the issue-3 setting).
// Prints one JSON object: Glint samples/s and rays/s (median and best of --repeat runs) and the
// raw Embree throughput (camera + random rays, one query a ray and in packets) on the same scene.
//   bench_render [SCENE.json] [--spp N] [--threads T] [--max-depth D] [--repeat R] [--rays N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "renderer_detail.h"

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    std::string scenePath;
    int spp = 64, threads = 2, maxDepth = 8, repeat = 3;
    long long rays = 8'000'000;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "bench_render: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--spp")
            spp = std::stoi(next());
        else if (a == "--threads")
            threads = std::stoi(next());
        else if (a == "--max-depth")
            maxDepth = std::stoi(next());
        else if (a == "--repeat")
            repeat = std::max(1, std::stoi(next()));
        else if (a == "--rays")
            rays = std::stoll(next());
        else
            scenePath = a;
    }
    if (scenePath.empty()) {
        const fs::path root = GLINT_SOURCE_DIR;
        scenePath = fs::exists(root / "scenes/cornell/scene.json")
                        ? (root / "scenes/cornell/scene.json").string()
                        : (root / "tests/render/data/cornell.json").string();
    }
    try {
        glint::render::Renderer renderer(glint::render::loadScene(scenePath));
        glint::render::Settings s = renderer.scene().settings();
        s.spp = spp;
        s.threads = threads;
        s.maxDepth = maxDepth;
        std::vector<double> sps, rps;
        glint::render::RenderStats last;
        for (int r = 0; r < repeat; ++r) {
            last = renderer.render(s).stats;
            sps.push_back(double(last.samples) / last.seconds);
            rps.push_back(double(last.rays) / last.seconds);
        }
        auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        std::vector<double> raw, rawPackets;
        for (int r = 0; r < repeat; ++r) {
            const auto t = glint::render::detail::measureRayThroughput(
                renderer, std::uint64_t(rays), threads, 1 + r);
            raw.push_back(double(t.rays) / t.seconds);
            const auto p = glint::render::detail::measureRayThroughput(
                renderer, std::uint64_t(rays), threads, 1 + r, true);
            rawPackets.push_back(double(p.rays) / p.seconds);
        }
        const nlohmann::json j = {
            {"scene", scenePath},
            {"width", renderer.scene().width()},
            {"height", renderer.scene().height()},
            {"spp", spp},
            {"maxDepth", maxDepth},
            {"threads", threads},
            {"repeat", repeat},
            {"secondsLastRun", last.seconds},
            {"raysPerSample", double(last.rays) / double(last.samples)},
            {"samplesPerSecondMedian", median(sps)},
            {"samplesPerSecondBest", *std::max_element(sps.begin(), sps.end())},
            {"raysPerSecondMedian", median(rps)},
            {"raysPerSecondBest", *std::max_element(rps.begin(), rps.end())},
            {"embreeRawRaysPerSecondMedian", median(raw)},
            {"embreeRawRaysPerSecondBest", *std::max_element(raw.begin(), raw.end())},
            {"embreeRawPacketRaysPerSecondMedian", median(rawPackets)},
            {"embreeRawPacketRaysPerSecondBest",
             *std::max_element(rawPackets.begin(), rawPackets.end())}};
        std::cout << j.dump(2) << "\n";
    } catch (const glint::Error& e) {
        std::fprintf(stderr, "bench_render: %s\n", e.what());
        return 2;
    }
    return 0;
}
