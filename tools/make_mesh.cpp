// glint-make-mesh: writes the small tessellated meshes the scenes use.
//   glint-make-mesh sphere --segments 48 --rings 24 [--inward] --out sphere.obj
//   glint-make-mesh quad [--uv-repeat N] --out quad.obj
// Shapes are unit-sized and placed by the scene's "transform" (scale, rotate, translate).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <string>

#include "asset_io.h"
#include "glint/image/error.h"

namespace {

using glint::tools::Mesh;
using glint::tools::Vec3;

/// UV sphere of radius 1 about the origin: `rings` bands of latitude, `segments` of longitude,
/// one vertex at each pole, smooth normals (outward, or inward with reversed winding).
Mesh makeSphere(int segments, int rings, bool inward) {
    Mesh mesh;
    const double pi = std::numbers::pi;
    const float sign = inward ? -1.0f : 1.0f;
    auto add = [&](double theta, double phi) {
        // +y is the pole axis; phi runs from -z towards +x (the lat-long convention of
        // docs/scene-format.md, so a textured sphere would line up with the environment).
        const Vec3 p{float(std::sin(theta) * std::sin(phi)), float(std::cos(theta)),
                     float(-std::sin(theta) * std::cos(phi))};
        mesh.positions.push_back(p);
        mesh.normals.push_back({sign * p[0], sign * p[1], sign * p[2]});
    };
    add(0.0, 0.0);  // north pole, index 0
    for (int r = 1; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) add(pi * r / rings, 2.0 * pi * s / segments);
    }
    add(pi, 0.0);  // south pole
    const int south = int(mesh.positions.size()) - 1;
    auto ringVertex = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    // Outward-facing triangles are counter-clockwise seen from outside; `face` flips them
    // for an inward sphere.
    auto face = [&](int a, int b, int c) {
        if (inward) {
            mesh.faces.push_back({a, c, b});
        } else {
            mesh.faces.push_back({a, b, c});
        }
    };
    for (int s = 0; s < segments; ++s) {
        // Polar caps: fans around the poles.
        face(0, ringVertex(1, s + 1), ringVertex(1, s));
        face(south, ringVertex(rings - 1, s), ringVertex(rings - 1, s + 1));
        // Bands: each quad split into two triangles.
        for (int r = 1; r + 1 < rings; ++r) {
            const int a = ringVertex(r, s), b = ringVertex(r, s + 1);
            const int c = ringVertex(r + 1, s + 1), d = ringVertex(r + 1, s);
            face(a, b, c);
            face(a, c, d);
        }
    }
    return mesh;
}

/// Square [-1, 1] × [-1, 1] in the xz-plane facing +y; texture coordinates run over
/// [0, uvRepeat] with u along +x and v along -z.
Mesh makeQuad(float uvRepeat) {
    Mesh mesh;
    mesh.positions = {{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}};
    mesh.normals.assign(4, {0, 1, 0});
    mesh.uvs = {{0, 0}, {uvRepeat, 0}, {uvRepeat, uvRepeat}, {0, uvRepeat}};
    // (v1 - v0) × (v2 - v0) = (2,0,0) × (2,0,-2) = (0,4,0): counter-clockwise seen from +y.
    mesh.faces = {{0, 1, 2}, {0, 2, 3}};
    return mesh;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes the unit sphere and quad meshes of Glint's scenes as OBJ"};
    app.require_subcommand(1);
    std::string out;
    int segments = 48;
    int rings = 24;
    bool inward = false;
    float uvRepeat = 1.0f;
    CLI::App* sphere = app.add_subcommand("sphere", "UV sphere of radius 1 with smooth normals");
    sphere->add_option("--segments", segments, "divisions in longitude")
        ->check(CLI::Range(3, 4096))
        ->capture_default_str();
    sphere->add_option("--rings", rings, "divisions in latitude")
        ->check(CLI::Range(2, 4096))
        ->capture_default_str();
    sphere->add_flag("--inward", inward, "normals and winding face the centre");
    sphere->add_option("--out", out, "output OBJ")->required();
    CLI::App* quad = app.add_subcommand("quad", "square [-1,1]^2 in the xz-plane facing +y");
    quad->add_option("--uv-repeat", uvRepeat, "texture coordinates span [0, N]")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    quad->add_option("--out", out, "output OBJ")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        if (sphere->parsed()) {
            const std::string comment = "glint-make-mesh sphere --segments " +
                                        std::to_string(segments) + " --rings " +
                                        std::to_string(rings) + (inward ? " --inward" : "");
            glint::tools::writeObj(makeSphere(segments, rings, inward), out, comment);
        } else {
            char repeat[32];
            std::snprintf(repeat, sizeof repeat, "%g", double(uvRepeat));
            glint::tools::writeObj(makeQuad(uvRepeat), out,
                                   std::string("glint-make-mesh quad --uv-repeat ") + repeat);
        }
    } catch (const glint::Error& e) {
        std::cerr << "glint-make-mesh: " << e.what() << "\n";
        return e.kind() == glint::ErrorKind::InvalidArgument ? 2 : 1;
    }
    return 0;
}
