// Writers shared by the scene-asset tools: triangle meshes as OBJ, RGB images as EXR or PNG.
// Every writer writes a temporary file beside the target and renames it into place.
#pragma once

#include <array>
#include <filesystem>
#include <vector>

namespace glint::tools {

using Vec2 = std::array<float, 2>;
using Vec3 = std::array<float, 3>;

/// A triangle mesh with per-vertex normals and optional texture coordinates (OBJ convention:
/// (0, 0) is the bottom-left corner of the image). Triangles are counter-clockwise seen from
/// the side their geometric normal points to.
struct Mesh {
    std::vector<Vec3> positions;
    std::vector<Vec3> normals;              ///< one per position
    std::vector<Vec2> uvs;                  ///< empty or one per position
    std::vector<std::array<int, 3>> faces;  ///< 0-based vertex indices
};

/// Writes `mesh` as a Wavefront OBJ with `comment` as its first line. Throws glint::Error.
void writeObj(const Mesh& mesh, const std::filesystem::path& path, const std::string& comment);

/// Writes a linear RGB float image (width × height × 3, row 0 at the top) as a half-float,
/// zip-compressed OpenEXR. Throws glint::Error.
void writeHalfExr(const std::vector<float>& rgb, int width, int height,
                  const std::filesystem::path& path);

/// Writes 8-bit sRGB-encoded RGB values (row 0 at the top) as a PNG tagged sRGB.
void writeSrgbPng(const std::vector<unsigned char>& rgb, int width, int height,
                  const std::filesystem::path& path);

}  // namespace glint::tools
