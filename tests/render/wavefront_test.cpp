// The wavefront path tracer (PathIntegrator::traceMany) and what it is built from: Embree ray
// packets (EmbreeScene::intersectMany / visibilityMany), batch Sobol numbers
// (SobolSampler::prefetchMany) and the cheaper maths of the hot path (the polynomial sincos of
// cosine sampling, renormalize, the scanned light choice). Each must give what the one-path form
// gives; where Embree's packet and single-ray kernels may round differently, the tests say so and
// bound the difference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "embree/embree_scene.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "integrators/path_integrator.h"
#include "lights/light_sampler.h"
#include "renderer_detail.h"
#include "sampling/distribution.h"
#include "sampling/rng.h"
#include "sampling/sobol.h"
#include "sampling/stratified_sampler.h"
#include "sampling/warp.h"
#include "scene/camera.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

std::filesystem::path scenePath(const std::string& name) {
    return std::filesystem::path(GLINT_SOURCE_DIR) / "scenes" / name / "scene.json";
}

/// Random rays through the scene's bounding box: origin inside it, uniform direction, uniform
/// shutter time.
std::vector<Ray> randomRays(const detail::SceneData& data, int count, std::uint64_t seed) {
    Vec3 lo{1e30f, 1e30f, 1e30f}, hi{-1e30f, -1e30f, -1e30f};
    for (const detail::Mesh& mesh : data.meshes)
        for (const Vec3& p : mesh.positions)
            for (int c = 0; c < 3; ++c)
                lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
    Rng rng(seed);
    std::vector<Ray> rays(static_cast<std::size_t>(count));
    for (Ray& r : rays) {
        r.origin = {lo.x + (hi.x - lo.x) * rng.uniform(), lo.y + (hi.y - lo.y) * rng.uniform(),
                    lo.z + (hi.z - lo.z) * rng.uniform()};
        r.dir = sampleUniformSphere({rng.uniform(), rng.uniform()});
        r.time = rng.uniform();
    }
    return rays;
}

/// Packets against single rays on a static scene and on one with a moving, turning sphere (a
/// motion-blur geometry beside the static one). The counts are not multiples of 16, so the last
/// packet is partly empty. Embree's packet kernel may round t, u, v differently from its
/// single-ray kernel: a ray grazing an edge shared by two triangles may then report the other
/// one. So: at most 0.2 % of rays may disagree on what they hit, t agrees to 1e-4 relative.
TEST(Wavefront, PacketQueriesAgreeWithSingleRays) {
    test::TempDir dir("wavefront_packets");
    dir.write("sphere.obj", test::sphereObj(1.0f, 12, 24));
    dir.write("ground.obj", "v -5 -1 -5\nv 5 -1 -5\nv 5 -1 5\nv -5 -1 5\nf 1 2 3 4\n");
    const std::string moving = dir.write("scene.json", R"({
      "camera": {"position": [0, 0, 6], "lookAt": [0, 0, 0], "fovY": 40},
      "film": {"width": 16, "height": 16},
      "materials": {"white": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
      "shapes": [{"obj": "sphere.obj", "material": "white",
                  "motion": {"translate": [1, 0.2, 0], "rotate": [90, [0, 0, 1]]}},
                 {"obj": "ground.obj", "material": "white"}]})")
                                   .string();
    for (const std::string& path : {scenePath("cornell").string(), moving}) {
        SCOPED_TRACE(path);
        const Scene scene = loadScene(path);
        const detail::SceneData& data = detail::sceneData(scene);
        const EmbreeScene embree(data);
        const std::vector<Ray> rays = randomRays(data, 4001, 11);
        std::vector<const Ray*> pointers;
        for (const Ray& r : rays) pointers.push_back(&r);
        std::vector<Hit> hits(rays.size());
        std::unique_ptr<bool[]> found(new bool[rays.size()]);
        embree.intersectMany(rays.size(), pointers.data(), hits.data(), found.get(), false);
        int disagree = 0, hitCount = 0;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            Hit single;
            const bool f =
                embree.intersect(rays[i], std::numeric_limits<float>::infinity(), single);
            hitCount += f;
            if (f != found[i] || (f && (single.surface.instance != hits[i].surface.instance ||
                                        single.surface.prim != hits[i].surface.prim))) {
                ++disagree;
                continue;
            }
            if (f) {
                EXPECT_NEAR(hits[i].t, single.t, 1e-4f * single.t) << "ray " << i;
            }
        }
        EXPECT_GT(hitCount, 1000);
        EXPECT_LE(disagree, int(rays.size()) / 500);

        // Shadow segments of random lengths, half of them blocked or so.
        std::vector<ShadowRay> segments;
        for (std::size_t i = 0; i < rays.size(); ++i)
            segments.push_back({rays[i].origin, rays[i].dir,
                                found[i] ? hits[i].t * (i % 2 ? 0.5f : 1.5f) : 10.0f,
                                rays[i].time});
        std::vector<const ShadowRay*> segmentPointers;
        for (const ShadowRay& s : segments) segmentPointers.push_back(&s);
        std::unique_ptr<float[]> visible(new float[segments.size()]);
        embree.visibilityMany(segments.size(), segmentPointers.data(), visible.get());
        int blockedCount = 0;
        disagree = 0;
        for (std::size_t i = 0; i < segments.size(); ++i) {
            const ShadowRay& s = segments[i];
            blockedCount += visible[i] == 0.0f;
            disagree += visible[i] != embree.visibility(s.origin, s.dir, s.tMax, s.time);
        }
        EXPECT_GT(blockedCount, 500);
        EXPECT_LT(blockedCount, int(segments.size()) - 500);
        EXPECT_LE(disagree, int(segments.size()) / 500);
    }
}

/// The raw-throughput benchmark's packet mode traces the same rays: the same count and, up to
/// the edge cases above, the same hits.
TEST(Wavefront, RawThroughputTracesTheSameRaysInPackets) {
    const Renderer renderer(loadScene(scenePath("cornell")));
    const detail::RayThroughput single = detail::measureRayThroughput(renderer, 20000, 2, 4);
    const detail::RayThroughput packets = detail::measureRayThroughput(renderer, 20000, 2, 4, true);
    EXPECT_EQ(single.rays, 20000u);
    EXPECT_EQ(packets.rays, 20000u);
    EXPECT_GT(single.hits, 10000u);
    EXPECT_NEAR(double(packets.hits), double(single.hits), 0.002 * double(single.hits));
}

/// traceMany against trace, path by path, for the Sobol sampler (with its batch prefetch) and a
/// stream sampler, on a diffuse box with an area light, glossy plates under small lights, and
/// glass under an environment map. The two draw the same numbers in the same order, so a path
/// differs only where Embree's packet kernel rounds a hit differently (a grazing edge, see
/// above); at most 1 % of paths may, and the batch means agree to 1e-3 relative.
TEST(Wavefront, TraceManyGivesWhatTraceGives) {
    for (const char* name : {"cornell", "glossy", "envmap"}) {
        SCOPED_TRACE(name);
        const Scene scene = loadScene(scenePath(name));
        const detail::SceneData& data = detail::sceneData(scene);
        const EmbreeScene embree(data);
        const LightSampler lights(data);
        const Camera camera(data.camera, data.width, data.height);
        Settings settings = scene.settings();
        settings.maxDepth = 8;
        const PathIntegrator integrator(data, embree, lights, camera, settings);

        const int count = 3001;
        std::vector<Ray> cameraRays;
        std::vector<SobolSampler> sobol, sobolOne;
        const StratifiedPattern independent(SamplerKind::Independent, 5, 0, 1);
        std::vector<StratifiedSampler> streams, streamsOne;
        for (int i = 0; i < count; ++i) {
            const int x = (i * 37) % data.width, y = (i * 11) % data.height;
            const auto pixel = std::uint64_t(y) * std::uint64_t(data.width) + std::uint64_t(x);
            sobol.emplace_back(5, pixel, std::uint32_t(i % 64));
            streams.emplace_back(independent, 5, pixel, i % 64);
            const Vec2 jitter = sobol.back().camera2D(0);
            cameraRays.push_back(
                camera.generateRay(float(x) + jitter.x, float(y) + jitter.y, {0.5f, 0.5f}));
        }
        sobolOne = sobol;
        streamsOne = streams;

        auto compare = [&](auto& many, auto& one, const char* sampler) {
            SCOPED_TRACE(sampler);
            std::vector<FilmSample> batch(std::size_t(count), FilmSample{});
            std::uint64_t raysMany = 0, raysOne = 0;
            integrator.traceMany(std::size_t(count), cameraRays.data(), many.data(), batch.data(),
                                 raysMany);
            int differ = 0;
            double sumMany = 0.0, sumOne = 0.0;
            for (int i = 0; i < count; ++i) {
                FilmSample single;
                integrator.trace(cameraRays[std::size_t(i)], one[std::size_t(i)], single, raysOne);
                const FilmSample& b = batch[std::size_t(i)];
                const bool same = b.color.x == single.color.x && b.color.y == single.color.y &&
                                  b.color.z == single.color.z && b.albedo.x == single.albedo.x &&
                                  b.depth == single.depth;
                differ += !same;
                sumMany += double(b.color.x + b.color.y + b.color.z);
                sumOne += double(single.color.x + single.color.y + single.color.z);
            }
            EXPECT_LE(differ, count / 100);
            std::printf("%s: %d of %d paths differ\n", sampler, differ, count);
            EXPECT_GT(sumOne, 0.0);
            EXPECT_NEAR(sumMany, sumOne, 1e-3 * sumOne);
            EXPECT_NEAR(double(raysMany), double(raysOne), 0.01 * double(raysOne));
        };
        compare(sobol, sobolOne, "sobol");
        compare(streams, streamsOne, "stream");
    }
}

/// The batch prefetch computes exactly (bit for bit) the numbers bounce1D / bounce2D compute
/// one at a time, for every slot, at any depth and for any mix of slots.
TEST(Sobol, PrefetchManyGivesTheNumbersOfTheSlots) {
    Rng rng(3);
    const int n = 777;
    std::vector<SobolSampler> batch, reference;
    std::vector<int> depths;
    std::vector<unsigned> slots;
    for (int i = 0; i < n; ++i) {
        const std::uint64_t pixel = rng.nextU64() % 100000;
        const auto index = std::uint32_t(rng.nextU64() % 4096);
        batch.emplace_back(9, pixel, index);
        reference.emplace_back(9, pixel, index);
        depths.push_back(int(rng.nextU64() % 9));
        slots.push_back(unsigned(rng.nextU64() % 32));
    }
    std::vector<SobolSampler*> pointers;
    for (SobolSampler& s : batch) pointers.push_back(&s);
    SobolSampler::prefetchMany(std::size_t(n), pointers.data(), depths.data(), slots.data());
    const BounceDim pairs[] = {BounceDim::LightPoint, BounceDim::BsdfDirection};
    const BounceDim singles[] = {BounceDim::LightSelect, BounceDim::BsdfComponent,
                                 BounceDim::Roulette};
    for (int i = 0; i < n; ++i) {
        const std::size_t k = std::size_t(i);
        for (BounceDim slot : pairs) {
            const Vec2 a = batch[k].bounce2D(depths[k], slot);
            const Vec2 b = reference[k].bounce2D(depths[k], slot);
            EXPECT_EQ(a.x, b.x) << i;
            EXPECT_EQ(a.y, b.y) << i;
        }
        for (BounceDim slot : singles)
            EXPECT_EQ(batch[k].bounce1D(depths[k], slot), reference[k].bounce1D(depths[k], slot))
                << i;
        // Another depth is computed afresh, not taken from the prefetch.
        EXPECT_EQ(batch[k].bounce1D(depths[k] + 1, BounceDim::Roulette),
                  reference[k].bounce1D(depths[k] + 1, BounceDim::Roulette));
    }
}

/// The polynomial (cos x, sin x) of cosine sampling is as accurate as float allows on
/// [-π/4, π/4] (2.5e-7 absolute, two float roundings of values ≤ 1), and the concentric disk
/// keeps its radius: the point at square coordinate (ox, oy) lies at max(|ox|, |oy|).
TEST(Warp, PolynomialSinCosIsAccurateToFloat) {
    double worst = 0.0;
    for (int i = 0; i <= 100000; ++i) {
        const double x = (double(i) / 100000.0 - 0.5) * 0.5 * 3.14159265358979323846;
        const Vec2 cs = cosSinQuarterPi(float(x));
        worst = std::max({worst, std::abs(double(cs.x) - std::cos(double(float(x)))),
                          std::abs(double(cs.y) - std::sin(double(float(x))))});
    }
    EXPECT_LT(worst, 2.5e-7);
    Rng rng(5);
    for (int i = 0; i < 10000; ++i) {
        const Vec2 u{rng.uniform(), rng.uniform()};
        const Vec2 d = sampleConcentricDisk(u);
        const float r = std::max(std::abs(2.0f * u.x - 1.0f), std::abs(2.0f * u.y - 1.0f));
        EXPECT_NEAR(std::sqrt(d.x * d.x + d.y * d.y), r, 1e-6f);
    }
}

/// renormalize makes a unit vector that went through a frame unit to float precision.
TEST(Warp, RenormalizeRestoresUnitLength) {
    Rng rng(8);
    for (int i = 0; i < 10000; ++i) {
        const Vec3 n = sampleUniformSphere({rng.uniform(), rng.uniform()});
        const Vec3 local = sampleCosineHemisphere({rng.uniform(), rng.uniform()});
        const Vec3 v = renormalize(Frame::fromNormal(n).toWorld(local));
        EXPECT_NEAR(length(v), 1.0f, 3e-7f);
    }
    // A vector off by 1e-3 comes back to within (1e-3)² of unit.
    EXPECT_NEAR(length(renormalize(Vec3{1.001f, 0.0f, 0.0f})), 1.0f, 2e-6f);
}

/// The scan that finds a light among a few and the bisection that finds a bin among many pick
/// the same bin, zero-probability bins included: the last bin whose CDF is ≤ u.
TEST(Distribution1D, ScanAndBisectionPickTheSameBins) {
    // Bins 1 and 2 are empty: u = 0.5 lands on bin 3 (never on an empty bin).
    const std::vector<float> few{1.0f, 0.0f, 0.0f, 1.0f};
    std::vector<float> many(20, 0.0f);
    many[0] = many[3] = 1.0f;  // the same CDF steps, padded by empty bins
    const Distribution1D a(few), b(many);
    EXPECT_EQ(a.sampleDiscrete(0.5f), 3);
    EXPECT_EQ(b.sampleDiscrete(0.5f), 3);
    EXPECT_EQ(a.sampleDiscrete(0.4999f), 0);
    EXPECT_EQ(b.sampleDiscrete(0.4999f), 0);
    EXPECT_EQ(a.sampleDiscrete(0.0f), 0);
    EXPECT_EQ(a.sampleDiscrete(0x1.fffffep-1f), 3);
    EXPECT_EQ(b.sampleDiscrete(0x1.fffffep-1f), 3);
    Rng rng(2);
    const std::vector<float> weights{0.3f, 2.0f, 0.0f, 0.7f, 1.0f, 0.0f, 4.0f};
    std::vector<float> padded = weights;
    padded.resize(16, 0.0f);
    const Distribution1D small(weights), large(padded);
    for (int i = 0; i < 10000; ++i) {
        const float u = rng.uniform();
        const int s = small.sampleDiscrete(u);
        EXPECT_GT(weights[std::size_t(s)], 0.0f) << "u = " << u;
        // Empty bins past the end leave the CDF's steps where they were (scan vs bisection).
        EXPECT_EQ(large.sampleDiscrete(u), s) << "u = " << u;
    }
}

}  // namespace
}  // namespace glint::render
