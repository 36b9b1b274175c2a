// Face normals kept with the world-space meshes of a small scene (Mesh::faceNormals): a hit
// reads its triangle's normal instead of computing it, and gets the same bits either way
// (scene_data.h, SceneData::finishMeshes; docs/renderer.md, "Performance").
#include <cstdint>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "glint/render/scene.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"

namespace glint::render {
namespace {

using detail::SceneData;

bool sameBits(const Vec3& a, const Vec3& b) {
    return std::memcmp(&a, &b, sizeof(Vec3)) == 0;
}

Scene cornellBox() {
    return loadScene(std::filesystem::path(GLINT_SOURCE_DIR) / "scenes/cornell/scene.json");
}

TEST(FaceNormals, AWorldSpaceMeshOfASmallSceneKeepsOneNormalPerTriangle) {
    const Scene scene = cornellBox();
    const SceneData& data = detail::sceneData(scene);
    ASSERT_EQ(data.instances.size(), 1u);
    ASSERT_TRUE(data.instances[0].identity);
    const detail::Mesh& mesh = data.meshes[data.instances[0].mesh];
    ASSERT_GT(mesh.triangleCount(), 0u);
    ASSERT_EQ(mesh.faceNormals.size(), mesh.triangleCount());
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const std::uint32_t* idx = &mesh.indices[3 * std::size_t(t)];
        const Vec3 expected =
            triangleNormal(mesh.positions[idx[0]], mesh.positions[idx[1]], mesh.positions[idx[2]]);
        EXPECT_TRUE(sameBits(mesh.faceNormals[t], expected)) << "triangle " << t;
    }
}

TEST(FaceNormals, TriangleGivesTheSameBitsWithAndWithoutThem) {
    const Scene scene = cornellBox();
    const SceneData& kept = detail::sceneData(scene);
    SceneData computed = kept;
    for (detail::Mesh& mesh : computed.meshes) mesh.faceNormals.clear();
    const detail::Mesh& mesh = kept.meshes[kept.instances[0].mesh];
    for (std::uint32_t t = 0; t < mesh.triangleCount(); ++t) {
        const detail::TriangleView a = kept.triangle(0, t, 0.5f), b = computed.triangle(0, t, 0.5f);
        EXPECT_TRUE(sameBits(a.ng, b.ng)) << "triangle " << t;
        for (int v = 0; v < 3; ++v) EXPECT_TRUE(sameBits(a.p[v], b.p[v])) << "triangle " << t;
    }
}

TEST(FaceNormals, ASceneOfMoreThanTheLimitKeepsNone) {
    // One world-space mesh of kFaceNormalTriangles + 1 triangles (all on one degenerate corner:
    // only the count matters) and one of a single triangle: neither keeps normals, so that a
    // large asset holds no more memory than before.
    SceneData data;
    detail::Mesh& big = data.meshes.emplace_back();
    big.positions = {{0.0f, 0.0f, 0.0f}};
    big.indices.assign(3 * (detail::kFaceNormalTriangles + 1), 0u);
    detail::Mesh& small = data.meshes.emplace_back();
    small.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    small.indices = {0, 1, 2};
    data.instances.resize(2);
    data.instances[1].mesh = 1;
    data.finishMeshes();
    EXPECT_TRUE(data.meshes[0].faceNormals.empty());
    EXPECT_TRUE(data.meshes[1].faceNormals.empty());
    // Computed at the hit instead: the same normal as a kept one would be.
    EXPECT_TRUE(sameBits(data.triangle(1, 0, 0.0f).ng, Vec3{0.0f, 0.0f, 1.0f}));
    // Below the limit the same meshes keep theirs.
    data.meshes[0].indices.resize(3);
    data.finishMeshes();
    EXPECT_EQ(data.meshes[0].faceNormals.size(), 1u);
    EXPECT_EQ(data.meshes[1].faceNormals.size(), 1u);
}

TEST(FaceNormals, AMeshSharedByInstancesKeepsNone) {
    // Two transformed instances of one mesh: it stays in object space, its normals are posed at
    // the hit.
    SceneData data;
    detail::Mesh& mesh = data.meshes.emplace_back();
    mesh.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}};
    mesh.indices = {0, 1, 2};
    data.instances.resize(2);
    for (detail::Instance& inst : data.instances) {
        inst.identity = false;
        inst.transform.t[0] = 2.0f;
    }
    data.finishMeshes();
    EXPECT_TRUE(data.meshes[0].faceNormals.empty());
    EXPECT_TRUE(sameBits(data.triangle(1, 0, 0.0f).ng, Vec3{0.0f, 0.0f, 1.0f}));
}

}  // namespace
}  // namespace glint::render
