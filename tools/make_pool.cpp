// glint-make-pool: writes the assets of scenes/pool (motion blur over a finely textured cloth).
//   glint-make-pool --out-dir scenes/pool
// cloth.png   256², a woven baize: twill of 2-pixel threads with per-thread shade and fibre noise
// stripe.png  128×64 lat-long ball texture: white with a coloured band (a "striped" ball)
// solid.png   128×64 lat-long ball texture: coloured with two white spots (a "solid" ball)
// ball.obj    UV sphere of radius 1 with smooth normals and lat-long texture coordinates
// cushion.obj the cube [-1,1]³ with flat faces (no vertex normals: sharp edges)
// Everything is deterministic (hash-based noise), so the committed files can be regenerated.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "asset_io.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/random.h"

namespace {

using glint::tools::Mesh;
using Rgb = std::array<float, 3>;

/// Hash of two integers to [0, 1) (SplitMix64 finaliser).
float hash01(std::uint64_t a, std::uint64_t b) {
    const std::uint64_t z =
        glint::mix64(a * 0x9e3779b97f4a7c15ULL + b * 0xc2b2ae3d27d4eb4fULL + 0x165667b19e3779f9ULL);
    return float(z >> 40) * 0x1p-24f;
}

/// Display-referred [0, 1] colour → 8-bit sRGB code value (the colours below are picked in sRGB).
unsigned char code(float v) {
    return (unsigned char)(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
}

std::vector<unsigned char> makeCloth(int size) {
    const Rgb felt{0.10f, 0.42f, 0.22f};
    std::vector<unsigned char> rgb(std::size_t(size) * size * 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            // 2/2 twill: threads are 2 pixels wide; warp (vertical) is on top where the diagonal
            // index (x/2 + y/2) mod 4 < 2, weft (horizontal) elsewhere.
            const int tx = x / 2, ty = y / 2;
            const bool warp = ((tx + ty) & 3) < 2;
            const float thread = warp ? hash01(1, std::uint64_t(tx)) : hash01(2, std::uint64_t(ty));
            const float fibre = hash01(std::uint64_t(x), std::uint64_t(y) + 7919);
            // Thread shade ±12 %, fibre noise ±8 %, a darker gap on each thread's first pixel.
            const bool gap = warp ? (x % 2 == 0) : (y % 2 == 0);
            const float shade =
                (1.0f + 0.24f * (thread - 0.5f) + 0.16f * (fibre - 0.5f)) * (gap ? 0.8f : 1.0f);
            for (int c = 0; c < 3; ++c)
                rgb[(std::size_t(y) * size + x) * 3 + c] = code(felt[std::size_t(c)] * shade);
        }
    return rgb;
}

/// Lat-long ball texture (u = longitude, v = latitude from the top row), white with a band
/// |latitude| < 22° of `colour` (striped) or `colour` with two white spots (solid).
std::vector<unsigned char> makeBall(int width, int height, const Rgb& colour, bool striped) {
    const double pi = std::numbers::pi;
    std::vector<unsigned char> rgb(std::size_t(width) * height * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const double lat = pi * (0.5 - (y + 0.5) / height);
            const double lon = 2.0 * pi * (x + 0.5) / width;
            Rgb c = colour;
            if (striped) {
                if (std::abs(lat) > 22.0 * pi / 180.0) c = {0.95f, 0.94f, 0.90f};
            } else {
                // Spots at longitude 0 and π on the equator: angular radius 25°.
                for (double spot : {0.0, pi}) {
                    const double cosd = std::cos(lat) * std::cos(lon - spot);
                    if (cosd > std::cos(25.0 * pi / 180.0)) c = {0.95f, 0.94f, 0.90f};
                }
            }
            for (int k = 0; k < 3; ++k)
                rgb[(std::size_t(y) * width + x) * 3 + k] = code(c[std::size_t(k)]);
        }
    return rgb;
}

/// UV sphere of radius 1 (+y pole), u = longitude / 2π, v = 1 − polar angle / π; a seam column
/// of duplicated vertices so texture coordinates do not wrap across a triangle.
Mesh makeBall(int segments, int rings) {
    const double pi = std::numbers::pi;
    Mesh mesh;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s <= segments; ++s) {
            const double theta = pi * r / rings, phi = 2.0 * pi * s / segments;
            const std::array<float, 3> p{float(std::sin(theta) * std::cos(phi)),
                                         float(std::cos(theta)),
                                         float(-std::sin(theta) * std::sin(phi))};
            mesh.positions.push_back(p);
            mesh.normals.push_back(p);
            mesh.uvs.push_back({float(s) / float(segments), 1.0f - float(r) / float(rings)});
        }
    const int row = segments + 1;
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const int a = r * row + s, b = a + 1, c = a + row, d = c + 1;
            // Counter-clockwise seen from outside; skip the degenerate triangle at each pole.
            if (r != 0) mesh.faces.push_back({a, c, b});
            if (r != rings - 1) mesh.faces.push_back({b, c, d});
        }
    return mesh;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes the textures and meshes of scenes/pool"};
    std::string outDir;
    app.add_option("--out-dir", outDir, "output folder")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        const std::filesystem::path dir(outDir);
        if (!std::filesystem::is_directory(dir))
            throw glint::Error(glint::ErrorKind::Io, "output folder does not exist", outDir);
        glint::tools::writeSrgbPng(makeCloth(256), 256, 256, dir / "cloth.png");
        glint::tools::writeSrgbPng(makeBall(128, 64, {0.95f, 0.75f, 0.05f}, true), 128, 64,
                                   dir / "stripe.png");
        glint::tools::writeSrgbPng(makeBall(128, 64, {0.75f, 0.06f, 0.05f}, false), 128, 64,
                                   dir / "solid.png");
        glint::tools::writeObj(makeBall(40, 20), dir / "ball.obj",
                               "# glint-make-pool: UV sphere of radius 1, 40 x 20, lat-long uv");
        // The cube without vertex normals (writeObj always writes normals): flat faces.
        glint::writeAtomically(dir / "cushion.obj", [](const std::filesystem::path& tmp) {
            std::ofstream out(tmp);
            out << "# glint-make-pool: cube [-1,1]^3, flat faces (no normals: sharp edges)\n";
            for (int i = 0; i < 8; ++i)
                out << "v " << (i & 1 ? 1 : -1) << " " << (i & 2 ? 1 : -1) << " "
                    << (i & 4 ? 1 : -1) << "\n";
            out << "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
            if (!out) throw glint::Error(glint::ErrorKind::Io, "cannot write", tmp.string());
        });
    } catch (const glint::Error& e) {
        std::cerr << "glint-make-pool: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
