// glint-make-texture: writes the procedural 8-bit sRGB textures the scenes use.
//   glint-make-texture checker --size 512 --cells 64 --out floor.png
// The checker alternates a light and a dark colour; every cell is bordered by a one-pixel
// grout line of a third colour so the pattern has detail at two scales.
#include <CLI/CLI.hpp>

#include <array>
#include <iostream>
#include <string>
#include <vector>

#include "asset_io.h"
#include "glint/image/error.h"

namespace {

/// Checkerboard of `cells` × `cells` squares on a `size` × `size` image (size % cells == 0).
std::vector<unsigned char> makeChecker(int size, int cells, bool grout) {
    using Rgb8 = std::array<unsigned char, 3>;
    const Rgb8 light{222, 214, 196};
    const Rgb8 dark{52, 60, 78};
    const Rgb8 line{128, 112, 92};
    const int cell = size / cells;
    std::vector<unsigned char> rgb(std::size_t(size) * size * 3);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const bool odd = ((x / cell) + (y / cell)) % 2 == 1;
            const bool border = grout && cell >= 4 && (x % cell == 0 || y % cell == 0);
            const Rgb8& c = border ? line : (odd ? dark : light);
            for (int k = 0; k < 3; ++k) rgb[(std::size_t(y) * size + x) * 3 + k] = c[k];
        }
    }
    return rgb;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes procedural textures for Glint's scenes as 8-bit sRGB PNG"};
    app.require_subcommand(1);
    int size = 512;
    int cells = 64;
    bool noGrout = false;
    std::string out;
    CLI::App* checker = app.add_subcommand("checker", "checkerboard with grout lines");
    checker->add_option("--size", size, "width and height in pixels")
        ->check(CLI::Range(2, 16384))
        ->capture_default_str();
    checker->add_option("--cells", cells, "squares per side (must divide --size)")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    checker->add_flag("--no-grout", noGrout, "plain two-colour checker");
    checker->add_option("--out", out, "output PNG")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    if (size % cells != 0) {
        std::cerr << "glint-make-texture: --cells " << cells << " must divide --size " << size
                  << "\n";
        return 2;
    }
    try {
        glint::tools::writeSrgbPng(makeChecker(size, cells, !noGrout), size, size, out);
    } catch (const glint::Error& e) {
        std::cerr << "glint-make-texture: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
