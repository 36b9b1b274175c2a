// A mesh's materials: one entry when every triangle shares a material, one per triangle
// otherwise, and the same material for every triangle either way (scene_data.h, Mesh).
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

using detail::Mesh;
using detail::SceneData;

/// Appends `count` triangles (their corners need not exist: only the count matters here).
void appendTriangles(Mesh& mesh, std::size_t count) {
    for (std::size_t i = 0; i < 3 * count; ++i) mesh.indices.push_back(0);
}

/// The material name of every triangle of instance `instance`, through SceneData::materialOf.
std::vector<std::string> triangleMaterials(const SceneData& d, std::uint32_t instance) {
    std::vector<std::string> names;
    const Mesh& mesh = d.meshes[d.instances[instance].mesh];
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t)
        names.push_back(d.materials[d.materialOf(instance, t)].name);
    return names;
}

TEST(MeshMaterials, OneMaterialKeepsOneEntry) {
    Mesh mesh;
    appendTriangles(mesh, 2);
    mesh.assignMaterial(0, 3);
    appendTriangles(mesh, 3);
    mesh.assignMaterial(2, 3);
    EXPECT_EQ(mesh.materials, std::vector<std::uint32_t>{3});
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) EXPECT_EQ(mesh.materialOf(t), 3u);
}

TEST(MeshMaterials, AnotherMaterialExpandsToOnePerTriangle) {
    Mesh mesh;
    appendTriangles(mesh, 2);
    mesh.assignMaterial(0, 3);
    appendTriangles(mesh, 1);
    mesh.assignMaterial(2, 5);
    appendTriangles(mesh, 2);
    mesh.assignMaterial(3, 3);
    EXPECT_EQ(mesh.materials, (std::vector<std::uint32_t>{3, 3, 5, 3, 3}));
    // Nothing appended: nothing changes; a single triangle of another material still expands.
    mesh.assignMaterial(5, 7);
    EXPECT_EQ(mesh.materials.size(), 5u);
    Mesh one;
    appendTriangles(one, 1);
    one.assignMaterial(0, 4);
    appendTriangles(one, 1);
    one.assignMaterial(1, 6);
    EXPECT_EQ(one.materials, (std::vector<std::uint32_t>{4, 6}));
}

/// A glTF mesh of two primitives (quads) with materials `first` and `second`, loaded.
Scene loadTwoPrimitives(const test::TempDir& dir, int first, int second) {
    test_gltf::GltfBuilder b;
    b.doc["materials"] = nlohmann::json::array({{{"name", "body"}}, {{"name", "trim"}}});
    const int mesh = b.quad(first), other = b.quad(second);
    const nlohmann::json primitive = b.doc["meshes"][std::size_t(other)]["primitives"][0];
    b.doc["meshes"][std::size_t(mesh)]["primitives"].push_back(primitive);
    b.doc["meshes"].erase(std::size_t(other));
    b.scene({b.node({{"mesh", mesh}})});
    const std::string name = "two" + std::to_string(first) + std::to_string(second) + ".gltf";
    dir.write(name, b.gltf());
    return loadScene(dir.write(name + ".json", test_gltf::sceneJson(name)));
}

TEST(MeshMaterials, GltfPrimitivesOfOneMaterialShareOneEntry) {
    test::TempDir dir("mesh_materials_gltf");
    const Scene same = loadTwoPrimitives(dir, 0, 0);
    const SceneData& d = detail::sceneData(same);
    ASSERT_EQ(d.meshes.size(), 1u);
    EXPECT_EQ(d.meshes[0].triangleCount(), 4u);
    EXPECT_EQ(d.meshes[0].materials.size(), 1u);
    EXPECT_EQ(triangleMaterials(d, 0), (std::vector<std::string>{"body", "body", "body", "body"}));

    const Scene mixed = loadTwoPrimitives(dir, 0, 1);
    const SceneData& m = detail::sceneData(mixed);
    EXPECT_EQ(m.meshes[0].materials.size(), 4u);
    EXPECT_EQ(triangleMaterials(m, 0), (std::vector<std::string>{"body", "body", "trim", "trim"}));
}

TEST(MeshMaterials, ObjFacesOfOneMaterialShareOneEntry) {
    test::TempDir dir("mesh_materials_obj");
    dir.write("m.mtl", "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n");
    const std::string quads = "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 2 0 0\nv 2 0 1\n";
    auto load = [&](const std::string& obj, const std::string& shapeExtra = "") {
        dir.write("mesh.obj", "mtllib m.mtl\n" + quads + obj);
        return loadScene(dir.write(
            "scene.json", R"({"film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj")" +
                              shapeExtra + R"(}], "environment": {"color": [1, 1, 1]},
                    "materials": {"gold": {"type": "diffuse", "albedo": [1, 0.8, 0]}}})"));
    };
    {
        const Scene s = load("usemtl red\nf 1 4 3 2\nf 2 3 6 5\n");
        const SceneData& d = detail::sceneData(s);
        EXPECT_EQ(d.meshes[0].materials.size(), 1u);
        EXPECT_EQ(triangleMaterials(d, 0), (std::vector<std::string>{"red", "red", "red", "red"}));
    }
    {
        const Scene s = load("usemtl red\nf 1 4 3 2\nusemtl blue\nf 2 3 6 5\n");
        const SceneData& d = detail::sceneData(s);
        EXPECT_EQ(d.meshes[0].materials.size(), 4u);
        EXPECT_EQ(triangleMaterials(d, 0),
                  (std::vector<std::string>{"red", "red", "blue", "blue"}));
    }
    {
        // A shape's "material" replaces every face's: the mesh keeps one entry.
        const Scene s =
            load("usemtl red\nf 1 4 3 2\nusemtl blue\nf 2 3 6 5\n", R"(, "material": "gold")");
        const SceneData& d = detail::sceneData(s);
        EXPECT_EQ(d.meshes[0].materials.size(), 1u);
        EXPECT_EQ(triangleMaterials(d, 0), std::vector<std::string>(4, "gold"));
    }
}

}  // namespace
}  // namespace glint::render
