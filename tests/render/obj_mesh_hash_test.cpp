// The OBJ reader's output does not change with its speed (issue 32, "Large files" in
// docs/obj-assets.md): the committed OBJ scenes and an OBJ of every corner form give the mesh
// arrays the reader before gave (their hashes), also when the file is larger than the blocks
// tinyobjloader is given (obj_import.cpp's GroupedObjBuffer) and its materials, smoothing groups
// and texture seams run across them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "glint/render/scene.h"
#include "mesh_hash.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

TEST(ObjMeshHash, TheCommittedObjScenesGiveTheMeshesOfTheReaderBefore) {
    // The hashes as e2cacb6's reader (a scan keeping every line as a string, corners de-duplicated
    // through a node-based map) gave them.
    const std::vector<std::pair<const char*, std::uint64_t>> scenes = {
        {"scenes/cornell/scene.json", 0xdbefbbd3451fe263ull},
        {"scenes/dof/scene.json", 0xcb54d567c7cca655ull},
        {"scenes/door/scene.json", 0x33b362b1e056524eull},
        {"scenes/envmap/scene.json", 0x0190e48b0db78882ull},
        {"scenes/furnace/scene.json", 0x092d2f2bd80fa81eull},
        {"scenes/furnace/closed.json", 0xd71883c4587d741eull},
        {"scenes/glossy/scene.json", 0x4421f0d36a868979ull},
        {"scenes/pool/scene.json", 0x05d302baa4d52052ull},
        {"scenes/textured/scene.json", 0x66b1369bbc428e1bull},
        {"tests/render/data/cornell.json", 0xd93e0a58ee8ee8c3ull}};
    for (const auto& [file, before] : scenes) {
        const Scene scene = loadScene(fs::path(GLINT_SOURCE_DIR) / file);
        EXPECT_FALSE(detail::sceneData(scene).meshes.empty()) << file;
        EXPECT_EQ(test::meshArraysHash(scene), before) << file;
    }
}

TEST(ObjMeshHash, EveryCornerFormGivesTheMeshOfTheReaderBefore) {
    // Corners shared and not (a texture seam: one position with two uvs), quads and a concave
    // pentagon, negative indices, faces of v, v/vt, v//vn and v/vt/vn, smoothing groups without
    // normals, two materials and faces of none: the arrays e2cacb6's reader gave.
    test::TempDir dir("obj_mesh_hash");
    dir.write("m.mtl", "newmtl red\nKd 0.8 0.1 0.1\nnewmtl grey\nKd 0.5\n");
    std::ostringstream obj;
    obj << "mtllib m.mtl\n";
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            obj << "v " << i << ' ' << 0.1 * std::sin(i + 2 * j) << ' ' << j << "\n";
    obj << "vn 0 1 0\nvn 0 0.9 0.1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n";
    obj << "usemtl red\nf 1/1/1 2/2/1 6/3/2 5/4/1\nf 2/5/2 3/2/1 7/3/1\nf 2/2/1 7/3/1 6/3/2\n"
        << "usemtl grey\ns 1\nf 3 4 8\nf 3 8 7\ns 2\nf 7 8 12 11\ns off\n"
        << "f 9//1 10//2 14//1 13//1\nf -6/-1 -5/-2 -1/-3 -2/-4\n"
        << "usemtl none\nf 11/1 12/2 16/3 15/4\nf 5 6 11 10 9\n";
    const fs::path file = dir.write("forms.obj", obj.str());
    const Scene scene = loadScene(file);
    ASSERT_EQ(detail::sceneData(scene).meshes.size(), 1u);
    EXPECT_EQ(detail::sceneData(scene).meshes[0].triangleCount(), 17u);
    EXPECT_EQ(test::meshArraysHash(scene), 0x4abc2caab266b34dull);
}

TEST(ObjMeshHash, AFileOfManyBlocksGivesTheMeshOfTheReaderBefore) {
    // A 240 x 240 grid (about 11 MB of text: three blocks) whose faces change material every
    // 997, alternate quads and triangle pairs, and where every seventh row names no normals (in
    // smoothing group 1 or 2) and every fifth row its own texture coordinates (seams): the arrays
    // e2cacb6's reader gave.
    test::TempDir dir("obj_mesh_hash_blocks");
    dir.write("m.mtl", "newmtl a\nKd 0.8 0.2 0.2\nnewmtl b\nKd 0.2 0.8 0.2\n");
    const int n = 240;
    std::ostringstream obj;
    obj << "mtllib m.mtl\n";
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            obj << "v " << i * 0.01 << ' ' << 0.05 * std::sin(0.3 * i) * std::cos(0.2 * j) << ' '
                << j * 0.01 << "\nvn " << 0.1 * std::sin(0.3 * i) << " 1 " << 0.1 * std::cos(j)
                << "\nvt " << i / double(n) << ' ' << j / double(n) << "\n";
    obj << "vt 0.5 0.5\n";
    long long faces = 0;
    for (int j = 0; j < n; ++j) {
        if (j % 7 == 3) obj << "s " << 1 + j % 2 << "\n";
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
            auto corner = [&](int v) {
                std::ostringstream k;
                k << v << '/' << (j % 5 == 2 ? (n + 1) * (n + 1) + 1 : v);
                if (j % 7 != 3) k << '/' << v;
                return k.str();
            };
            if (faces % 997 == 0) obj << "usemtl " << (faces / 997 % 2 ? "b" : "a") << "\n";
            if ((i + j) % 2)
                obj << "f " << corner(a) << ' ' << corner(c) << ' ' << corner(d) << ' ' << corner(b)
                    << "\n";
            else
                obj << "f " << corner(a) << ' ' << corner(c) << ' ' << corner(b) << "\nf "
                    << corner(b) << ' ' << corner(c) << ' ' << corner(d) << "\n";
            faces += 1 + (i + j + 1) % 2;
        }
        if (j % 7 == 3) obj << "s off\n";
    }
    const std::string text = obj.str();
    ASSERT_GT(text.size(), std::size_t(2) << 22);
    const Scene scene = loadScene(dir.write("blocks.obj", text));
    ASSERT_EQ(detail::sceneData(scene).meshes.size(), 1u);
    EXPECT_EQ(detail::sceneData(scene).meshes[0].triangleCount(), std::size_t(2 * n * n));
    EXPECT_EQ(test::meshArraysHash(scene), 0x00af050477b4420bull);
}

}  // namespace
}  // namespace glint::render
