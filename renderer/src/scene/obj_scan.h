// A validating pre-pass over an OBJ file: tinyobjloader does not check what faces reference, nor
// that numbers are numbers, and it does not say where it read them. The scan names the file and
// line of the first problem and remembers the line of every vertex so that later checks (after
// the shape's transform) can name it too. It reads the text in place, once.
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "scene/load_memory.h"

namespace glint::render::detail {

/// The most corners an OBJ face may have: tinyobjloader counts a face's corners in a byte.
inline constexpr std::size_t kMaxObjFaceCorners = 255;

/// A texture statement of an MTL material (`map_Kd`, `norm`, `map_d`, `bump`): the file name as
/// written, options removed (it may hold spaces and Windows backslashes), its line, its `-s`/`-o`
/// (u, v) and `-clamp` options, and `-bm` (the bump multiplier, written before or after the
/// name).
struct MtlTexture {
    std::string name;  ///< empty: none
    int line = 0;
    float scale[2] = {1.0f, 1.0f}, offset[2] = {0.0f, 0.0f};
    bool clamp = false;
    float bumpMultiplier = 1.0f;
};

/// What the scan saw of one MTL material that tinyobjloader reads differently from the MTL
/// specification or does not read: where it is defined (its texture paths are relative to that
/// file), which colours were given as one value (the specification's grey; tinyobjloader sets
/// red only), whether it gives the PBR extension's `Pr` or `Pm`, and its textures (`bump`: the
/// first of its `bump`, `map_Bump` and `map_bump` statements).
struct MtlMaterialInfo {
    std::filesystem::path file;
    bool greyKd = false, greyKs = false, greyKe = false;
    bool pbr = false;
    MtlTexture mapKd, norm, mapD, bump;
};

/// Lines (1-based) of the OBJ's `v` statements, in order, and how many `vn` and `vt` it has; its
/// MTL files (every
/// `mtllib` name, once, in order); what the scan saw of their materials (the first definition
/// of a name, as tinyobjloader keeps); and one warning per kind of statement Glint does not read
/// (a bump map, a texture option, vertex colours, a material defined again...), naming its file
/// and first line.
struct ObjLines {
    std::vector<int> vertices;
    std::size_t normalCount = 0, texcoordCount = 0;
    std::vector<std::filesystem::path> mtlFiles;
    std::map<std::string, MtlMaterialInfo> materials;
    std::vector<std::string> warnings;
    /// The first face naming a normal (texture coordinate) in a file that has none (0: none).
    int unnamedNormalLine = 0, unnamedTexcoordLine = 0;
};

/// The file an OBJ or MTL names (`mtllib`, `map_Kd`), as exporters on other machines write it:
/// `name` relative to `folder` (or absolute) with `\` read as a folder separator; else the same
/// path matched without regard to case; else, for an absolute name, the same below `folder`
/// without its root; else, for a name with folders, its file name alone in `folder` (each part
/// matched without regard to case). Returns an empty path when none exists.
std::filesystem::path findNamedFile(const std::filesystem::path& folder, const std::string& name);

/// The text of an OBJ or MTL file without a leading UTF-8 byte order mark (which tinyobjloader
/// would read as part of the first statement). Throws glint::Error(Io) when it cannot be read.
std::string readObjText(const std::filesystem::path& path, const char* kind);

/// Reads the OBJ at `path` and checks every statement Glint uses: `v`/`vn`/`vt` hold finite
/// numbers (3, 3 and 1–3 of them; `v` may add 3 colour values); every face has at least 3
/// corners (and at most kMaxObjFaceCorners), and each corner's vertex, texture and normal index
/// (1-based, or negative: relative to the statements read so far) names an existing statement;
/// every `mtllib` file exists (names are split as Blender splits them: a name runs to the next
/// `.mtl`, so "mtllib my model.mtl" is one file). Throws glint::Error(Format) naming the file
/// and "line N", Io when it or an MTL file cannot be read or found.
ObjLines scanObj(const std::filesystem::path& path);

/// Checks the numeric statements of an MTL file (Ka/Kd/Ks/Ke/Tf: 1 or 3 finite numbers; Ns/Ni/
/// d/Tr/illum/Pr/Pm: 1; a texture's `-bm`: 1) with the ranges of the JSON keys they become (Kd and
/// Ks in [0, 1], Ke in [0, kMaxRadiance], Ns ≥ 0, d, Tr, Pr and Pm in [0, 1]), and throws
/// glint::Error(Format) naming its file and line; adds its materials to `out.materials` (names
/// already there are kept) and a warning to `out.warnings` for each kind of statement Glint does
/// not read. scanObj calls it for every `mtllib` file.
void scanMtl(const std::filesystem::path& path, ObjLines& out);

/// The OBJ format's predictLoad (obj_load_memory.cpp): predicts the load of the OBJ at `path` from
/// one pass over its text (a block at a time) counting its v, vt, vn and f statements and its face
/// corners: the check's copy of the text, tinyobjloader's arrays and the mesh they become.
LoadPrediction predictObjLoad(const std::filesystem::path& path);

}  // namespace glint::render::detail
