// bench_asset_load: how long a large glTF or OBJ asset takes to set up and how much memory it
// needs.
//   bench_asset_load write FILE.glb|FILE.obj [--triangles N]
//                       a wavy grid of about N triangles (positions, normals, 32-bit indices);
//                       as OBJ text, `v`, `vn` and faces `f a//a b//b c//c`
//   bench_asset_load load FILE [--threads T] [--accel auto|triangles|clusters] [--rays N]
//                       load it and build its BVH; prints JSON
// Run `load` in a fresh process (as docs/assets.md and docs/obj-assets.md do) so that the peak
// resident size is the asset's alone ("loadCpuSeconds": the process's user + system time while
// loading). "meshBytes" is the asset's vertex and index data (a .glb's
// BIN chunk; else the bytes of Glint's mesh arrays); "loadPeakRss"
// the peak after loading (before the BVH), "peakRss" the peak once the BVH is built; "rss" the
// resident size once built, and "trimmedRss" after malloc_trim(0) hands freed heap back.
// "glintMesh" counts Glint's mesh arrays byte by byte (their sizes, and "capacity" what is
// allocated), "embree" what Embree's device holds once built and held at most during the build
// (its memory monitor; the mesh arrays it reads in place are Glint's). "accel" is the choice asked
// for and "bvh" what was built: "clusters" when a mesh is traced as clusters of triangles
// (docs/assets.md, "Speed and memory"), with their triangle order's bytes ("clusterOrder", Glint's
// beside Embree's) and the triangles a cluster holds, else "triangles" (Embree's own). With
// --rays N (after the memory figures), "trace" times N rays of the raw kernel (half camera rays,
// half random rays in the bounding box; detail::measureRayThroughput, seed 19) one query a ray
// and in packets: wall and CPU seconds (the process's user + system time) and rays per CPU second.
#include <malloc.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <tbb/global_control.h>
#include <nlohmann/json.hpp>

#include "bench_options.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings.h"
#include "renderer_detail.h"
#include "scene/scene_access.h"

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point from) {
    return std::chrono::duration<double>(Clock::now() - from).count();
}

/// Peak resident size of this process so far, bytes.
double peakRssBytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_maxrss) * 1024.0;
}

/// Resident size of this process now (VmRSS), bytes.
double rssBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) * 1024.0;
    return 0.0;
}

/// Bytes of each array of the scene's meshes (their sizes), and what they allocate.
nlohmann::json meshArrays(const glint::render::Scene& scene) {
    std::size_t positions = 0, normals = 0, tangents = 0, uvs = 0, indices = 0, materials = 0,
                capacity = 0;
    auto count = [&](std::size_t& sum, const auto& array) {
        using T = typename std::decay_t<decltype(array)>::value_type;
        sum += array.size() * sizeof(T);
        capacity += array.capacity() * sizeof(T);
    };
    for (const auto& mesh : glint::render::detail::sceneData(scene).meshes) {
        count(positions, mesh.positions), count(normals, mesh.normals);
        count(tangents, mesh.tangents), count(uvs, mesh.uvs);
        count(indices, mesh.indices), count(materials, mesh.materials);
    }
    return {{"positions", positions},
            {"normals", normals},
            {"tangents", tangents},
            {"uvs", uvs},
            {"indices", indices},
            {"materials", materials},
            {"total", positions + normals + tangents + uvs + indices + materials},
            {"capacity", capacity}};
}

void append32(std::string& out, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(char((v >> (8 * i)) & 0xffu));
}

/// An nx × ny grid of quads (two triangles each) over [-1, 1]², gently waved so that its BVH is
/// not that of a flat plane.
struct Grid {
    int nx = 0, ny = 0;
    std::vector<float> positions, normals;
    std::vector<std::uint32_t> indices;
};

Grid makeGrid(long long triangles) {
    const int ny = std::max(1, int(std::sqrt(double(triangles) / 4.0)));
    const int nx = std::max(1, int(triangles / (2LL * ny)));
    const std::size_t vertices = std::size_t(nx + 1) * std::size_t(ny + 1);
    std::vector<float> positions, normals;
    positions.reserve(3 * vertices);
    normals.reserve(3 * vertices);
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(nx);
            const float z = -1.0f + 2.0f * float(j) / float(ny);
            positions.insert(positions.end(),
                             {x, 0.05f * std::sin(8.0f * x) * std::cos(8.0f * z), z});
            normals.insert(normals.end(), {0.0f, 1.0f, 0.0f});
        }
    std::vector<std::uint32_t> indices;
    indices.reserve(std::size_t(6) * std::size_t(nx) * std::size_t(ny));
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const std::uint32_t a = std::uint32_t(j * (nx + 1) + i), b = a + 1,
                                c = a + std::uint32_t(nx + 1), d = c + 1;
            indices.insert(indices.end(), {a, c, b, b, c, d});
        }
    return {nx, ny, std::move(positions), std::move(normals), std::move(indices)};
}

/// Writes the grid as OBJ text (to a temporary name, then renamed): every position and normal
/// as `v` and `vn` (printf's %g: 6 significant digits, as exporters often write), each triangle
/// `f a//a b//b c//c`.
void writeGridObj(const std::string& file, const Grid& grid) {
    const std::string part = file + ".part";
    {
        std::FILE* out = std::fopen(part.c_str(), "wb");
        if (!out) throw std::runtime_error("cannot write " + part);
        const std::size_t vertices = grid.positions.size() / 3;
        for (std::size_t i = 0; i < vertices; ++i) {
            const float* p = &grid.positions[3 * i];
            std::fprintf(out, "v %g %g %g\n", double(p[0]), double(p[1]), double(p[2]));
        }
        for (std::size_t i = 0; i < vertices; ++i) {
            const float* n = &grid.normals[3 * i];
            std::fprintf(out, "vn %g %g %g\n", double(n[0]), double(n[1]), double(n[2]));
        }
        for (std::size_t t = 0; t < grid.indices.size(); t += 3) {
            const std::uint32_t* f = &grid.indices[t];
            std::fprintf(out, "f %u//%u %u//%u %u//%u\n", f[0] + 1, f[0] + 1, f[1] + 1, f[1] + 1,
                         f[2] + 1, f[2] + 1);
        }
        if (std::fclose(out) != 0) throw std::runtime_error("cannot write " + part);
    }
    if (std::rename(part.c_str(), file.c_str()) != 0)
        throw std::runtime_error("cannot rename " + part + " to " + file);
    std::printf("%s: %zu triangles, %zu vertices, %.1f MB of mesh data\n", file.c_str(),
                grid.indices.size() / 3, grid.positions.size() / 3,
                double(4 * (2 * grid.positions.size() + grid.indices.size())) / 1e6);
}

/// Writes a .glb of one mesh: the grid.
void writeGrid(const std::string& file, long long triangles) {
    const Grid grid = makeGrid(triangles);
    if (file.size() >= 4 && file.compare(file.size() - 4, 4, ".obj") == 0)
        return writeGridObj(file, grid);
    const int nx = grid.nx, ny = grid.ny;
    const std::size_t vertices = grid.positions.size() / 3;
    const std::vector<float>&positions = grid.positions, &normals = grid.normals;
    const std::vector<std::uint32_t>& indices = grid.indices;
    const std::size_t pBytes = positions.size() * 4, iBytes = indices.size() * 4;
    const std::size_t binBytes = 2 * pBytes + iBytes;
    const nlohmann::json doc = {
        {"asset", {{"version", "2.0"}, {"generator", "glint bench_asset_load"}}},
        {"scene", 0},
        {"scenes", {{{"nodes", {0}}}}},
        {"nodes", {{{"mesh", 0}}}},
        {"meshes",
         {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}}}}}}},
        {"buffers", {{{"byteLength", binBytes}}}},
        {"bufferViews",
         {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", pBytes}},
          {{"buffer", 0}, {"byteOffset", pBytes}, {"byteLength", pBytes}},
          {{"buffer", 0}, {"byteOffset", 2 * pBytes}, {"byteLength", iBytes}}}},
        {"accessors",
         {{{"bufferView", 0},
           {"componentType", 5126},
           {"count", vertices},
           {"type", "VEC3"},
           {"min", {-1.0, -0.05, -1.0}},
           {"max", {1.0, 0.05, 1.0}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", vertices}, {"type", "VEC3"}},
          {{"bufferView", 2},
           {"componentType", 5125},
           {"count", indices.size()},
           {"type", "SCALAR"}}}}};
    std::string json = doc.dump();
    json.append((4 - json.size() % 4) % 4, ' ');
    std::string header;
    append32(header, 0x46546C67u);  // "glTF"
    append32(header, 2);
    append32(header, std::uint32_t(12 + 8 + json.size() + 8 + binBytes));
    append32(header, std::uint32_t(json.size()));
    append32(header, 0x4E4F534Au);  // "JSON"
    header += json;
    append32(header, std::uint32_t(binBytes));
    append32(header, 0x004E4942u);  // "BIN"
    std::ofstream out(file, std::ios::binary);
    out.write(header.data(), std::streamsize(header.size()));
    out.write(reinterpret_cast<const char*>(positions.data()), std::streamsize(pBytes));
    out.write(reinterpret_cast<const char*>(normals.data()), std::streamsize(pBytes));
    out.write(reinterpret_cast<const char*>(indices.data()), std::streamsize(iBytes));
    if (!out) throw std::runtime_error("cannot write " + file);
    std::printf("%s: %lld triangles, %zu vertices, %.1f MB of mesh data\n", file.c_str(),
                2LL * nx * ny, vertices, double(binBytes) / 1e6);
}

/// The BIN chunk's length of a .glb (its mesh data), read from the chunk header.
double binChunkBytes(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    unsigned char head[20];
    if (!in.read(reinterpret_cast<char*>(head), 20)) return 0.0;
    std::uint32_t jsonLength = 0, binLength = 0;
    std::memcpy(&jsonLength, head + 12, 4);
    in.seekg(20 + std::streamoff(jsonLength));
    if (!in.read(reinterpret_cast<char*>(&binLength), 4)) return 0.0;
    return double(binLength);
}

/// The --accel value, or OptionError naming the option.
glint::render::Accel accelOption(const std::string& name, const std::string& value) {
    try {
        return glint::render::parseAccel(value);
    } catch (const glint::Error& e) {
        throw glint::bench::OptionError(name + ": " + e.message());
    }
}

/// CPU time (user + system) of this process so far, seconds.
double cpuSeconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// `rays` rays of the renderer's raw kernel on `threads` threads, one query a ray or in packets.
nlohmann::json traceRays(const glint::render::Renderer& renderer, long long rays, int threads,
                         bool packets) {
    const double cpu = cpuSeconds();
    const auto t = glint::render::detail::measureRayThroughput(renderer, std::uint64_t(rays),
                                                               threads, 19, packets);
    const double used = cpuSeconds() - cpu;
    return {{"rays", t.rays},
            {"hits", t.hits},
            {"seconds", t.seconds},
            {"cpuSeconds", used},
            {"raysPerCpuSecond", used > 0.0 ? double(t.rays) / used : 0.0}};
}

/// Loads `file` and builds its BVH over the primitives `accel` names on `threads` worker threads;
/// prints one JSON line (with `rays` > 0, also the kernel's speed).
int load(const std::string& file, int threads, glint::render::Accel accel, long long rays) {
    tbb::global_control workers(tbb::global_control::max_allowed_parallelism,
                                std::size_t(std::max(1, threads)));
    const auto start = Clock::now();
    const double startCpu = cpuSeconds();
    glint::render::Scene scene = glint::render::loadScene(file);
    const double loadSeconds = seconds(start), loadCpuSeconds = cpuSeconds() - startCpu;
    const double loadPeak = peakRssBytes();
    const auto bvhStart = Clock::now();
    glint::render::Renderer renderer(std::move(scene), accel);
    const double bvhSeconds = seconds(bvhStart);
    const double peak = peakRssBytes(), rss = rssBytes();
    malloc_trim(0);
    const double trimmedRss = rssBytes();
    const auto embree = glint::render::detail::accelerationMemory(renderer);
    const nlohmann::json arrays = meshArrays(renderer.scene());
    const bool glb = file.size() >= 4 && file.compare(file.size() - 4, 4, ".glb") == 0;
    const double mesh = glb ? binChunkBytes(file) : arrays["total"].get<double>();
    nlohmann::json out = {{"file", file},
                          {"triangles", renderer.scene().triangleCount()},
                          {"meshBytes", mesh},
                          {"loadSeconds", loadSeconds},
                          {"loadCpuSeconds", loadCpuSeconds},
                          {"bvhSeconds", bvhSeconds},
                          {"setupSeconds", loadSeconds + bvhSeconds},
                          {"loadPeakRss", loadPeak},
                          {"peakRss", peak},
                          {"rss", rss},
                          {"trimmedRss", trimmedRss},
                          {"glintMesh", arrays},
                          {"embree", {{"bytes", embree.current}, {"peakBytes", embree.peak}}},
                          {"accel", glint::render::accelName(accel)},
                          {"bvh", embree.clusteredMeshes > 0 ? "clusters" : "triangles"},
                          {"clusteredMeshes", embree.clusteredMeshes},
                          {"clusterSize", embree.clusterSize},
                          {"clusterOrder", embree.clusterOrder},
                          {"loadPeakOverMesh", mesh > 0 ? loadPeak / mesh : 0.0},
                          {"peakOverMesh", mesh > 0 ? peak / mesh : 0.0}};
    if (rays > 0)
        out["trace"] = {{"single", traceRays(renderer, rays, threads, false)},
                        {"packets", traceRays(renderer, rays, threads, true)}};
    std::printf("%s\n", out.dump().c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(
            stderr,
            "usage: bench_asset_load write|load FILE.glb|FILE.obj [--triangles N] [--threads T] "
            "[--accel auto|triangles|clusters] [--rays N]\n");
        return 2;
    }
    const std::string mode = argv[1], file = argv[2];
    long long triangles = 4'000'000, rays = 0;
    int threads = 2;
    glint::render::Accel accel = glint::render::Accel::Auto;
    const int status =
        glint::bench::parseOptions("bench_asset_load", argc - 2, argv + 2,
                                   [&](const std::string& name, const std::string& value) {
                                       if (name == "--triangles")
                                           triangles = glint::bench::intOption(name, value);
                                       else if (name == "--threads")
                                           threads = glint::bench::intOption(name, value);
                                       else if (name == "--rays")
                                           rays = glint::bench::intOption(name, value);
                                       else if (name == "--accel")
                                           accel = accelOption(name, value);
                                       else
                                           return false;
                                       return true;
                                   });
    if (status != 0) return status;
    try {
        if (mode == "write") {
            writeGrid(file, triangles);
            return 0;
        }
        if (mode == "load") return load(file, threads, accel, rays);
        std::fprintf(stderr, "bench_asset_load: mode '%s' is neither write nor load\n",
                     mode.c_str());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_asset_load: %s\n", e.what());
        return 1;
    }
}
