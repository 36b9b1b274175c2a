// The clustered geometry (embree/cluster_geometry.cpp, Accel::Clusters): Embree's BVH over
// clusters of triangles, Glint's watertight test inside them. Traced with `triangles` and with
// `clusters`, a scene gives the same hits (triangle, instance, t, u, v), single rays and packets,
// in world space and through a shared instanced mesh; the alpha filters run on cluster hits
// (MASK cut-outs, BLEND transmittance); the order holds every triangle once; renders stay
// thread-independent and unbiased; bad `accel` input is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include "cli_fixture.h"
#include "embree/cluster_geometry.h"
#include "embree/embree_scene.h"
#include "glint/image/error.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "sampling/rng.h"
#include "sampling/warp.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/transform.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// An n × n grid over [-1, 1]² in the xz plane, waved in y, as OBJ text (2n² triangles).
std::string wavedGridObj(int n) {
    std::string obj;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = -1.0f + 2.0f * float(i) / float(n),
                        z = -1.0f + 2.0f * float(j) / float(n);
            obj += "v " + std::to_string(x) + " " +
                   std::to_string(0.2f * std::sin(3.0f * x) * std::cos(2.0f * z)) + " " +
                   std::to_string(z) + "\n";
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
            obj += "f " + std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(b) +
                   "\nf " + std::to_string(b) + " " + std::to_string(c) + " " + std::to_string(d) +
                   "\n";
        }
    return obj;
}

/// A sphere (528 triangles) and a waved grid (392, emissive) in world space, and a smaller grid
/// (288) shared by two rotated, scaled instances: a mesh in object space under Embree
/// instances (OBJ shapes get a mesh each, so the second instance is added here).
Scene mixedScene(const test::TempDir& dir) {
    dir.write("sphere.obj", test::sphereObj(1.0f, 12, 24));
    dir.write("grid.obj", wavedGridObj(14));
    dir.write("tile.obj", wavedGridObj(12));
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 1, 8], "lookAt": [0, 0, 0], "fovY": 40},
            "film": {"width": 24, "height": 24},
            "materials": {"white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
                          "lamp": {"type": "diffuse", "albedo": [0, 0, 0],
                                   "emission": [4, 4, 4]}},
            "shapes": [{"obj": "sphere.obj", "material": "white"},
                       {"obj": "grid.obj", "material": "lamp",
                        "transform": {"translate": [0, 3, 0], "rotate": [180, [1, 0, 0]],
                                      "scale": 3}},
                       {"obj": "tile.obj", "material": "white"}]})",
        dir.path() / "scene.json");
    auto data = std::make_unique<detail::SceneData>(detail::sceneData(parsed));
    // The tile scaled by 3 below the sphere, and by 2, turned 70° about z, to its right.
    const double below[3][4] = {{3, 0, 0, 0}, {0, 3, 0, -1.5}, {0, 0, 3, 0}};
    const double c = 2.0 * std::cos(70.0 * kPi / 180.0), s = 2.0 * std::sin(70.0 * kPi / 180.0);
    const double right[3][4] = {{c, -s, 0, 2.5}, {s, c, 0, 0}, {0, 0, 2, 0}};
    detail::Instance& tile = data->instances[2];
    tile.identity = false;
    EXPECT_TRUE(detail::affineFromMatrix(below, tile.transform));
    detail::Instance second = tile;
    EXPECT_TRUE(detail::affineFromMatrix(right, second.transform));
    data->instances.push_back(second);
    return Scene(std::move(data));
}

/// Rays from uniform points of [-4, 4]³ in uniform directions (seed fixed by the caller).
std::vector<Ray> clusterTestRays(int count, std::uint64_t seed) {
    Rng rng(seed);
    std::vector<Ray> rays(static_cast<std::size_t>(count));
    for (Ray& r : rays) {
        r.origin = {8.0f * rng.uniform() - 4.0f, 8.0f * rng.uniform() - 4.0f,
                    8.0f * rng.uniform() - 4.0f};
        r.dir = sampleUniformSphere({rng.uniform(), rng.uniform()});
    }
    return rays;
}

/// How two hits of one ray compare.
struct HitComparison {
    int rays = 0, hits = 0, sharedHits = 0, disagree = 0;
    double maxT = 0.0, maxUv = 0.0;  ///< largest relative t and absolute u, v differences

    void add(bool foundA, const Hit& a, bool foundB, const Hit& b, std::uint32_t shared) {
        ++rays;
        if (foundA != foundB || (foundA && (a.surface.instance != b.surface.instance ||
                                            a.surface.prim != b.surface.prim))) {
            ++disagree;
            return;
        }
        if (!foundA) return;
        ++hits;
        sharedHits += a.surface.instance >= shared;
        maxT = std::max(maxT, double(std::fabs(a.t - b.t)) / double(a.t));
        maxUv = std::max({maxUv, double(std::fabs(a.u - b.u)), double(std::fabs(a.v - b.v))});
    }
};

}  // namespace

TEST(ClusterGeometry, TheOrderHoldsEveryTriangleOnceAndKeepsClustersSmall) {
    // A waved grid whose triangles are listed in a shuffled order (fixed seed 19).
    test::TempDir dir("cluster_order");
    dir.write("grid.obj", wavedGridObj(40));
    const Scene scene = parseScene(
        R"({"camera": {"position": [0, 3, 0], "lookAt": [0, 0, 0], "up": [0, 0, 1]},
            "film": {"width": 4, "height": 4}, "shapes": [{"obj": "grid.obj"}]})",
        dir.path() / "scene.json");
    detail::Mesh mesh = detail::sceneData(scene).meshes[0];
    const std::size_t n = mesh.triangleCount();
    ASSERT_EQ(n, 3200u);
    Rng rng(19);
    for (std::size_t t = n - 1; t > 0; --t) {
        const std::size_t s = std::size_t(rng.nextU64() % (t + 1));
        for (int k = 0; k < 3; ++k) std::swap(mesh.indices[3 * t + k], mesh.indices[3 * s + k]);
    }
    const ClusterOrder order = spatialOrder(mesh);
    ASSERT_EQ(order.size(), n);
    std::vector<int> seen(n, 0);
    for (std::uint32_t t : order) {
        ASSERT_LT(t, n);
        ++seen[t];
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), std::ptrdiff_t(n));
    EXPECT_EQ(spatialOrder(mesh), order) << "deterministic";
    // Clusters of 8 in this order span a few grid cells (0.05 wide); in the file's (shuffled)
    // order they span the grid.
    auto meanDiagonal = [&](auto triangleAt) {
        double sum = 0.0;
        for (std::size_t c = 0; c < n / 8; ++c) {
            Vec3 lo{1e9f, 1e9f, 1e9f}, hi{-1e9f, -1e9f, -1e9f};
            for (std::size_t j = 8 * c; j < 8 * c + 8; ++j)
                for (int k = 0; k < 3; ++k) {
                    const Vec3& p = mesh.positions[mesh.indices[3 * triangleAt(j) + k]];
                    for (int a = 0; a < 3; ++a)
                        lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
                }
            sum += double(length(hi - lo));
        }
        return sum / double(n / 8);
    };
    const double clustered = meanDiagonal([&](std::size_t j) { return order[j]; });
    const double shuffled = meanDiagonal([](std::size_t j) { return j; });
    EXPECT_LT(clustered, 0.4);
    EXPECT_GT(shuffled, 1.0);
}

TEST(ClusterGeometry, GivesTheHitsOfEmbreesTriangles) {
    // 20000 random rays (seed 19) through a scene of world-space meshes and a shared instanced
    // one. Embree's triangle test and Glint's watertight one round differently, so a ray
    // through an edge shared by two triangles may report either: at most 0.1 % of rays may
    // disagree on what they hit; where they agree, t within 1e-4 relative, u and v within 1e-4.
    test::TempDir dir("cluster_hits");
    const Scene scene = mixedScene(dir);
    const detail::SceneData& data = detail::sceneData(scene);
    const std::uint32_t firstShared = 2;  // instances 2 and 3 are the tile's
    ASSERT_EQ(data.instances.size(), 4u);
    ASSERT_FALSE(data.instances[firstShared].identity);
    const EmbreeScene triangles(data, Accel::Triangles), clusters(data, Accel::Clusters);
    EXPECT_EQ(triangles.clusteredMeshCount(), 0);
    EXPECT_EQ(clusters.clusteredMeshCount(), 3);
    EXPECT_EQ(clusters.sharedMeshCount(), 1);
    EXPECT_EQ(clusters.clusterOrderBytes(), (528u + 392u + 288u) * 4u);
    // The auto choice keeps a small scene on Embree's triangles.
    EXPECT_EQ(EmbreeScene(data).clusteredMeshCount(), 0);
    // ... and one whose instances hold more than 2^21 triangles of one shared mesh, which its
    // BVHs hold once (the tile's 288 triangles, 7300 times: 2.1M).
    detail::SceneData many = data;
    many.instances.resize(2);
    for (int i = 0; i < 7300; ++i) {
        detail::Instance copy = data.instances[firstShared];
        copy.transform.t = {float(i % 100) * 7.0f, float(i / 100) * 7.0f, 50.0f};
        many.instances.push_back(copy);
    }
    ASSERT_GT(many.triangleCount(), kClusterTriangles);
    EXPECT_EQ(EmbreeScene(many).clusteredMeshCount(), 0);

    const std::vector<Ray> rays = clusterTestRays(20000, 19);
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<const Ray*> pointers;
    for (const Ray& r : rays) pointers.push_back(&r);
    std::vector<Hit> packetHits(rays.size());
    std::unique_ptr<bool[]> packetFound(new bool[rays.size()]);
    clusters.intersectMany(rays.size(), pointers.data(), packetHits.data(), packetFound.get(),
                           false);
    HitComparison single, packets;
    std::vector<Hit> reference(rays.size());
    std::vector<char> referenceFound(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) {
        Hit a, b;
        referenceFound[i] = triangles.intersect(rays[i], inf, a);
        reference[i] = a;
        single.add(referenceFound[i], a, clusters.intersect(rays[i], inf, b), b, firstShared);
        packets.add(referenceFound[i], a, packetFound[i], packetHits[i], firstShared);
    }
    std::printf(
        "single rays: %d hits (%d on the shared mesh), %d of %d disagree; packets: %d of "
        "%d; largest t difference %.2g relative, u, v %.2g\n",
        single.hits, single.sharedHits, single.disagree, single.rays, packets.disagree,
        packets.rays, std::max(single.maxT, packets.maxT), std::max(single.maxUv, packets.maxUv));
    for (const HitComparison* c : {&single, &packets}) {
        EXPECT_GT(c->hits, 5000);
        EXPECT_GT(c->sharedHits, 1000);
        EXPECT_LE(c->disagree, c->rays / 1000);
        EXPECT_LE(c->maxT, 1e-4);
        EXPECT_LE(c->maxUv, 1e-4);
    }

    // Shadow segments ending before, at 1.5 × or short of the first hit: blocked or clear alike.
    std::vector<ShadowRay> segments;
    for (std::size_t i = 0; i < rays.size(); ++i)
        segments.push_back({rays[i].origin, rays[i].dir,
                            referenceFound[i] ? reference[i].t * (i % 2 ? 0.5f : 1.5f) : 10.0f,
                            0.0f});
    std::vector<const ShadowRay*> segmentPointers;
    for (const ShadowRay& s : segments) segmentPointers.push_back(&s);
    std::vector<float> visible(segments.size());
    clusters.visibilityMany(segments.size(), segmentPointers.data(), visible.data());
    int blocked = 0, disagreeSingle = 0, disagreePackets = 0;
    for (std::size_t i = 0; i < segments.size(); ++i) {
        const ShadowRay& s = segments[i];
        const float expected = triangles.visibility(s.origin, s.dir, s.tMax);
        blocked += expected == 0.0f;
        disagreeSingle += clusters.visibility(s.origin, s.dir, s.tMax) != expected;
        disagreePackets += visible[i] != expected;
    }
    EXPECT_GT(blocked, 2500);
    EXPECT_LT(blocked, int(segments.size()) - 2500);
    EXPECT_LE(disagreeSingle, int(segments.size()) / 1000);
    EXPECT_LE(disagreePackets, int(segments.size()) / 1000);
}

TEST(ClusterGeometry, AutoClustersAMeshOfMoreThanTwoToTheTwentyOneTriangles) {
    // The sphere of the mixed scene replaced by a flat grid of 1025² quads: 2,101,250 triangles,
    // just above 2^21 = 2,097,152. auto clusters every static mesh, the shared one included.
    test::TempDir dir("cluster_auto");
    const Scene scene = mixedScene(dir);
    detail::SceneData data = detail::sceneData(scene);
    detail::Mesh& mesh = data.meshes[data.instances[0].mesh];
    const std::uint32_t n = 1025;
    mesh.positions.clear();
    mesh.normals.clear();
    mesh.indices.clear();
    mesh.positions.reserve(std::size_t(n + 1) * (n + 1) + 1);
    for (std::uint32_t j = 0; j <= n; ++j)
        for (std::uint32_t i = 0; i <= n; ++i)
            mesh.positions.push_back({float(i) / float(n), 0.0f, float(j) / float(n)});
    for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
            const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, c, b, b, c, d});
        }
    ASSERT_GT(data.triangleCount(), kClusterTriangles);
    const EmbreeScene embree(data);
    EXPECT_EQ(embree.clusteredMeshCount(), 3);
    EXPECT_EQ(embree.clusterSize(), int(kClusterSize));
    Hit hit;
    ASSERT_TRUE(embree.intersect({{0.3f, 1.0f, 0.6f}, {0, -1, 0}}, 10.0f, hit));
    EXPECT_NEAR(hit.t, 1.0f, 1e-5f);
    EXPECT_EQ(EmbreeScene(data, Accel::Triangles).clusteredMeshCount(), 0);
}

TEST(ClusterGeometry, MovingMeshesAreClusteredInsideTheirMovingInstance) {
    // A moving, turning sphere over a static ground: with clusters both meshes are clustered (the
    // sphere's inside its moving instance), and rays at random shutter times (seed 20) hit what
    // they hit with triangles (tolerances as above).
    test::TempDir dir("cluster_motion");
    dir.write("sphere.obj", test::sphereObj(1.0f, 12, 24));
    dir.write("ground.obj", wavedGridObj(10));
    const Scene scene = parseScene(
        R"({"camera": {"position": [0, 0, 6], "lookAt": [0, 0, 0], "fovY": 40},
            "film": {"width": 8, "height": 8},
            "shapes": [{"obj": "sphere.obj",
                        "motion": {"translate": [1, 0.2, 0], "rotate": [90, [0, 0, 1]]}},
                       {"obj": "ground.obj", "transform": {"translate": [0, -1.5, 0],
                                                          "scale": 4}}]})",
        dir.path() / "scene.json");
    const detail::SceneData& data = detail::sceneData(scene);
    const EmbreeScene triangles(data, Accel::Triangles), clusters(data, Accel::Clusters);
    EXPECT_EQ(clusters.clusteredMeshCount(), 2);
    EXPECT_EQ(clusters.motionGeometryCount(), 1);
    std::vector<Ray> rays = clusterTestRays(5000, 20);
    Rng rng(20);
    for (Ray& r : rays) r.time = rng.uniform();
    HitComparison c;
    int sphereHits = 0;
    for (const Ray& r : rays) {
        Hit a, b;
        const bool fa = triangles.intersect(r, std::numeric_limits<float>::infinity(), a);
        const bool fb = clusters.intersect(r, std::numeric_limits<float>::infinity(), b);
        c.add(fa, a, fb, b, 2);
        sphereHits += fa && a.surface.instance == 0;
    }
    EXPECT_GT(sphereHits, 80);
    EXPECT_GT(c.hits, 1000);
    EXPECT_LE(c.disagree, c.rays / 1000);
    EXPECT_LE(c.maxT, 1e-4);
    EXPECT_LE(c.maxUv, 1e-4);
}

namespace {

constexpr const char* kClusterQuad =
    "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";

/// The material named "pane".
detail::Material& paneMaterial(detail::SceneData& data) {
    for (detail::Material& m : data.materials)
        if (m.name == "pane") return m;
    throw Error(ErrorKind::Internal, "no material 'pane'");
}

/// One or two quads (a shared mesh for two: the second an Embree instance of the first, 1
/// nearer the camera) over a white floor at z = -5, the quads' material BLEND of `opacity`.
detail::SceneData blendStack(const test::TempDir& dir, int count, float opacity) {
    dir.write("quad.obj", kClusterQuad);
    dir.write("floor.obj", test::floorObj(-5));
    const Scene parsed = parseScene(
        R"({"camera": {"position": [0, 0, 30], "lookAt": [0, 0, 0], "fovY": 30},
            "film": {"width": 4, "height": 4},
            "materials": {"white": {"type": "diffuse", "albedo": [1, 1, 1]},
                          "pane": {"type": "diffuse", "albedo": [0, 0, 0]}},
            "shapes": [{"obj": "floor.obj", "material": "white"},
                       {"obj": "quad.obj", "material": "pane"}]})",
        dir.path() / "scene.json");
    detail::SceneData data = detail::sceneData(parsed);
    detail::Material& pane = paneMaterial(data);
    pane.alphaMode = detail::AlphaMode::Blend;
    pane.opacity = opacity;
    if (count == 2) {
        data.instances[1].identity = false;
        detail::Instance nearer = data.instances[1];
        nearer.transform.t = {0, 0, 1};
        data.instances.push_back(nearer);
    }
    return data;
}

}  // namespace

TEST(ClusterGeometry, RunsTheAlphaFiltersOnClusterHits) {
    test::TempDir dir("cluster_alpha");
    // BLEND: a shadow segment through a 0.25-alpha pane keeps 0.75, through two shared panes
    // of 0.5 (instances: the filter reads the instance of the hit) 0.25, single rays and
    // packets; a closest-hit ray stops at the pane (the caller chooses at BLEND surfaces).
    for (const auto& [count, opacity, expected] :
         {std::tuple{1, 0.25f, 0.75f}, std::tuple{2, 0.5f, 0.25f}}) {
        SCOPED_TRACE(count);
        const detail::SceneData data = blendStack(dir, count, opacity);
        const EmbreeScene embree(data, Accel::Clusters);
        ASSERT_EQ(embree.clusteredMeshCount(), 2);  // the floor and the pane(s)
        ASSERT_EQ(embree.sharedMeshCount(), count - 1);
        EXPECT_EQ(embree.visibility({0.3f, -0.2f, 20.0f}, {0, 0, -1}, 24.0f), expected);
        std::vector<ShadowRay> rays;
        for (int i = 0; i < 37; ++i)
            rays.push_back({{-0.9f + 0.05f * float(i), 0.45f - 0.02f * float(i), 20.0f},
                            {0, 0, -1},
                            24.0f,
                            0.0f});
        std::vector<const ShadowRay*> pointers;
        for (const ShadowRay& r : rays) pointers.push_back(&r);
        std::vector<float> visible(rays.size());
        embree.visibilityMany(rays.size(), pointers.data(), visible.data());
        for (float v : visible) EXPECT_EQ(v, expected);
        // Clear of the panes: the floor blocks a segment that reaches it.
        EXPECT_EQ(embree.visibility({5.0f, 0.0f, 20.0f}, {0, 0, -1}, 30.0f), 0.0f);
        Hit hit;
        ASSERT_TRUE(embree.intersect({{0.3f, -0.2f, 20.0f}, {0, 0, -1}}, 100.0f, hit));
        EXPECT_NEAR(hit.t, 20.0f - float(count - 1), 1e-4f);
    }
    // MASK: the pane's texture alpha is 0 on its left half and 1 on its right (cut-off 0.5):
    // rays pass on the left, stop on the right — the filter reads the cluster hit's u, v.
    detail::SceneData data = blendStack(dir, 1, 1.0f);
    detail::Texture texture;
    texture.path = "alpha";
    texture.wrapS = texture.wrapT = detail::TextureWrap::Clamp;
    texture.image = Image(2, 1, 4, 0.0f);
    texture.image(1, 0, 3) = 1.0f;
    data.textures.push_back(std::move(texture));
    detail::Material& pane = paneMaterial(data);
    pane.texture = int(data.textures.size()) - 1;
    pane.textureTimesFactor = true;
    pane.alphaMode = detail::AlphaMode::Mask;
    pane.alphaCutoff = 0.5f;
    for (Accel accel : {Accel::Triangles, Accel::Clusters}) {
        SCOPED_TRACE(accelName(accel));
        const EmbreeScene embree(data, accel);
        for (float y : {-0.7f, 0.1f, 0.6f}) {
            Hit left, right;
            ASSERT_TRUE(embree.intersect({{-0.6f, y, 20.0f}, {0, 0, -1}}, 100.0f, left));
            ASSERT_TRUE(embree.intersect({{0.6f, y, 20.0f}, {0, 0, -1}}, 100.0f, right));
            EXPECT_NEAR(left.t, 25.0f, 1e-4f) << "through the hole to the floor";
            EXPECT_NEAR(right.t, 20.0f, 1e-4f) << "on the pane";
            EXPECT_EQ(embree.visibility({-0.6f, y, 20.0f}, {0, 0, -1}, 24.0f), 1.0f);
            EXPECT_EQ(embree.visibility({0.6f, y, 20.0f}, {0, 0, -1}, 24.0f), 0.0f);
        }
    }
}

namespace {

/// `mixedScene` rendered at 16 × 16... its own film (24²) with `accel`.
FrameBuffers renderMixed(const test::TempDir& dir, Accel accel, int threads, std::uint64_t seed,
                         int spp) {
    Renderer renderer(mixedScene(dir), accel);
    Settings s = renderer.scene().settings();
    s.spp = spp;
    s.maxDepth = 4;
    s.threads = threads;
    s.seed = seed;
    return renderer.render(s).frame;
}

}  // namespace

TEST(ClusterGeometry, RendersAreThreadIndependentAndUnbiased) {
    test::TempDir dir("cluster_render");
    // Bit-identical at 1 and 2 threads.
    const FrameBuffers one = renderMixed(dir, Accel::Clusters, 1, 21, 8);
    const FrameBuffers two = renderMixed(dir, Accel::Clusters, 2, 21, 8);
    const Image &a = one.color(), &b = two.color();
    ASSERT_EQ(a.width(), b.width());
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int c = 0; c < 3; ++c) ASSERT_EQ(a(x, y, c), b(x, y, c)) << x << "," << y;
    // Independent renders (seeds 21 and 22, 64 spp): the image means agree within 4 standard
    // errors of their difference.
    const test::MeanEstimate clusters =
        test::meanAndError(renderMixed(dir, Accel::Clusters, 2, 21, 64));
    const test::MeanEstimate triangles =
        test::meanAndError(renderMixed(dir, Accel::Triangles, 2, 22, 64));
    EXPECT_GT(triangles.mean, 0.01);
    EXPECT_NEAR(
        clusters.mean, triangles.mean,
        4.0 * std::sqrt(clusters.sigma * clusters.sigma + triangles.sigma * triangles.sigma));
}

TEST(ClusterGeometry, BadAccelIsRefusedNamingThePlace) {
    test::TempDir dir("cluster_bad");
    dir.write("sphere.obj", test::sphereObj(1.0f, 4, 8));
    auto parse = [&](const std::string& accel) {
        return parseScene(R"({"camera": {"position": [0, 0, 5], "lookAt": [0, 0, 0]},
                              "film": {"width": 4, "height": 4},
                              "shapes": [{"obj": "sphere.obj"}],
                              "render": {"accel": )" +
                              accel + "}}",
                          dir.path() / "scene.json");
    };
    EXPECT_EQ(parse("\"clusters\"").settings().accel, Accel::Clusters);
    EXPECT_EQ(parse("\"triangles\"").settings().accel, Accel::Triangles);
    for (const std::string bad : {"3", "\"fast\""}) {
        try {
            parse(bad);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(e.where().find("/render/accel"), std::string::npos) << e.where();
            EXPECT_NE(e.message().find("triangles"), std::string::npos) << e.message();
        }
    }
    EXPECT_THROW(parseAccel("fast"), Error);
}

namespace {

class ClusterCli : public glint::testing::CliFixture {
  protected:
    ClusterCli() : CliFixture("glint-render") {}
};

}  // namespace

TEST_F(ClusterCli, AccelFlagRunsAndBadValuesExitTwo) {
    std::ofstream(path("sphere.obj")) << test::sphereObj(1.0f, 6, 12);
    std::ofstream(path("scene.json")) << R"({
        "camera": {"position": [0, 0, 5], "lookAt": [0, 0, 0]},
        "film": {"width": 8, "height": 8},
        "shapes": [{"obj": "sphere.obj"}], "environment": {"color": [1, 1, 1]}})";
    const std::string out = path("x.exr");
    const glint::testing::RunResult ok =
        run(path("scene.json") + " --spp 2 --set accel=clusters --json --out " + out);
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_NE(ok.out.find("\"accel\":\"clusters\""), std::string::npos) << ok.out;
    std::filesystem::remove(out);
    const glint::testing::RunResult bad =
        run(path("scene.json") + " --spp 2 --set accel=fast --out " + out);
    EXPECT_EQ(bad.exitCode, 2);
    // The stage lines before it, then the error on one line.
    std::string err = bad.err;
    while (!err.empty() && err.back() == '\n') err.pop_back();
    err = err.substr(err.rfind('\n') + 1);
    EXPECT_EQ(err.rfind("glint-render: command line: --set accel: ", 0), 0u) << err;
    EXPECT_NE(err.find("--set accel"), std::string::npos) << err;
    EXPECT_NE(err.find("auto, triangles or clusters"), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(out));
    // The scene's "accel": 3 the same way, naming the file and the place.
    std::ofstream(path("three.json")) << R"({
        "camera": {"position": [0, 0, 5], "lookAt": [0, 0, 0]},
        "film": {"width": 8, "height": 8}, "shapes": [{"obj": "sphere.obj"}],
        "render": {"accel": 3}})";
    const glint::testing::RunResult three = run(path("three.json") + " --spp 2 --out " + out);
    EXPECT_EQ(three.exitCode, 2);
    err = three.err;
    while (!err.empty() && err.back() == '\n') err.pop_back();
    err = err.substr(err.rfind('\n') + 1);
    EXPECT_NE(err.find("three.json: /render/accel: expected \"auto\", \"triangles\" or "
                       "\"clusters\""),
              std::string::npos)
        << err;
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace glint::render
