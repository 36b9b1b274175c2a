// A validating pre-pass over an OBJ file: tinyobjloader does not check what faces reference, nor
// that numbers are numbers, and it does not say where it read them. The scan names the file and
// line of the first problem and remembers the line of every vertex, normal and texture
// coordinate so that later checks (after the shape's transform) can name it too.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace glint::render::detail {

/// The most corners an OBJ face may have: tinyobjloader counts a face's corners in a byte.
inline constexpr std::size_t kMaxObjFaceCorners = 255;

/// What the scan saw of one MTL material that tinyobjloader reads differently from the MTL
/// specification: where it is defined (its texture paths are relative to that file), and which
/// colours were given as one value (the specification's grey; tinyobjloader sets red only).
struct MtlMaterialInfo {
    std::filesystem::path file;
    bool greyKd = false, greyKs = false, greyKe = false;
};

/// Lines (1-based) of the OBJ's `v`, `vn` and `vt` statements, in order, and what the scan saw
/// of its MTL materials (the first definition of a name, as tinyobjloader keeps).
struct ObjLines {
    std::vector<int> vertices, normals, texcoords;
    std::map<std::string, MtlMaterialInfo> materials;
};

/// Reads the OBJ at `path` and checks every statement Glint uses: `v`/`vn`/`vt` hold finite
/// numbers (3, 3 and 1–3 of them; `v` may add 3 colour values); every face has at least 3
/// corners (and at most kMaxObjFaceCorners), and each corner's vertex, texture and normal index
/// (1-based, or negative: relative to the statements read so far) names an existing statement.
/// Throws glint::Error(Format) naming the file and "line N", Io when it cannot be read.
ObjLines scanObj(const std::filesystem::path& path);

/// Checks the numeric statements of an MTL file (Ka/Kd/Ks/Ke/Tf: 1 or 3 finite numbers; Ns/Ni/
/// d/Tr/illum: 1) with the ranges of the JSON keys they become (Kd and Ks in [0, 1], Ke in
/// [0, kMaxRadiance], Ns ≥ 0), and throws glint::Error(Format) naming its file and line; adds
/// its materials to `materials` (names already there are kept). scanObj calls it for every
/// `mtllib` file (a missing one is reported later).
void scanMtl(const std::filesystem::path& path, std::map<std::string, MtlMaterialInfo>& materials);

}  // namespace glint::render::detail
