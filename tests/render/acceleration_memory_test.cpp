// What the renderer's Embree device holds, as its memory monitor counts it
// (renderer_detail.h, accelerationMemory; bench_asset_load reports it).
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "renderer_detail.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// The device's bytes once a UV sphere of `stacks` × 2·stacks quads is built.
detail::AccelerationMemory sphereBvhMemory(int stacks) {
    test::TempDir dir("acceleration_memory");
    dir.write("sphere.obj", test::sphereObj(1.0f, stacks, 2 * stacks));
    Renderer renderer(loadScene(
        dir.write("scene.json",
                  R"({"film": {"width": 8, "height": 8}, "shapes": [{"obj": "sphere.obj"}],
            "environment": {"color": [1, 1, 1]}})")));
    return detail::accelerationMemory(renderer);
}

TEST(AccelerationMemory, CountsTheBvhAndGrowsWithTheMesh) {
    // 2·16·32 = 1,024 against 2·256·512 = 262,144 triangles: Embree holds at least a few
    // bytes a triangle (its BVH leaves name every triangle), so the larger one holds more by
    // far; the peak is never below what is held after the build.
    const detail::AccelerationMemory small = sphereBvhMemory(16), large = sphereBvhMemory(256);
    EXPECT_GT(small.current, 0);
    EXPECT_GE(small.peak, small.current);
    EXPECT_GE(large.peak, large.current);
    EXPECT_GT(large.current - small.current, std::int64_t(4) * 262144);
}

}  // namespace
}  // namespace glint::render
