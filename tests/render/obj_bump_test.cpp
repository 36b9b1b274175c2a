// MTL bump maps (`bump`, `map_Bump`, `map_bump`) read as heights in scene units (issue 32,
// docs/obj-assets.md): the statement and its options, `-bm` refused where it is not a finite
// number, heights read as data, the shading normal tilted by the height's slope as the displaced
// surface's normal is, left bit for bit where the height is constant, and a bumped surface that
// reflects no more light than a flat one.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "integrators/surface_inputs.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "scene/scene_hash.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::Material;
using detail::SceneData;

/// A 2 × 2 quad in the xy plane (normal +z, no vertex normals), uv = position / 2.
const char* kQuadObj =
    "mtllib m.mtl\nusemtl m\nv 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n";

/// A scene of the quad under a white sky, scaled by `scale`, seen from above.
std::string bumpQuadScene(float scale = 1.0f, int spp = 4) {
    return R"({"camera": {"position": [1, 1, 3], "lookAt": [1, 1, 0], "fovY": 30},
      "film": {"width": 24, "height": 24},
      "shapes": [{"obj": "mesh.obj", "transform": {"scale": )" +
           std::to_string(scale) + R"(}}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": )" +
           std::to_string(spp) + R"(, "maxDepth": 4, "seed": 21}})";
}

/// A float EXR of w × h grey texels value(x, y) (x, y: texel centres in [0, 1], y up).
template <class F>
void writeHeights(const fs::path& path, int w, int h, F value) {
    Image im(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                im(x, y, c) = value((x + 0.5f) / float(w), 1.0f - (y + 0.5f) / float(h));
    writeImage(im, path);
}

/// Loads mesh.obj (kQuadObj), m.mtl = `mtl` and scene.json from `dir`.
Scene loadQuad(const test::TempDir& dir, const std::string& mtl, float scale = 1.0f) {
    dir.write("mesh.obj", kQuadObj);
    dir.write("m.mtl", mtl);
    dir.write("scene.json", bumpQuadScene(scale));
    return loadScene(dir.path() / "scene.json");
}

/// The hit at barycentrics (b1, b2) of triangle `prim` of the scene's first instance.
SurfacePoint hitAt(const SceneData& d, std::uint32_t prim, float b1, float b2,
                   detail::TexFootprint footprint = {}) {
    SurfacePoint at;
    at.id = {0, prim};
    at.b1 = b1, at.b2 = b2;
    at.hasUv = true;
    at.uv = detail::surfaceUv(d.meshes[0], 0, prim, b1, b2);
    at.footprint = footprint;
    return at;
}

/// Points inside both triangles of the quad, away from its edges.
const std::vector<std::array<float, 3>> kPoints{
    {0, 1.0f / 3, 1.0f / 3}, {1, 1.0f / 3, 1.0f / 3}, {0, 0.2f, 0.3f}, {1, 0.5f, 0.25f}};

}  // namespace

TEST(ObjBump, BumpStatementsAndTheirOptionsAreRead) {
    test::TempDir dir("obj_bump_parse");
    writeHeights(dir.path() / "h.exr", 2, 2, [](float, float) { return 0.5f; });
    for (const auto& [statement, multiplier, scaled, clamped] :
         std::vector<std::tuple<std::string, float, bool, bool>>{
             {"bump -bm 0.5 h.exr", 0.5f, false, false},
             {"map_Bump -s 2 3 1 -o 0.5 0 -clamp on -bm -2 h.exr", -2.0f, true, true},
             {"map_bump h.exr -bm 1.5", 1.5f, false, false},
             {"bump h.exr", 1.0f, false, false}}) {
        const Scene scene = loadQuad(dir, "newmtl m\nKd 0.5 0.5 0.5\n" + statement + "\n");
        const SceneData& d = detail::sceneData(scene);
        const Material& m = d.materials.at(0);
        ASSERT_TRUE(m.bumpMap.present()) << statement;
        EXPECT_EQ(m.bumpMultiplier, multiplier) << statement;
        EXPECT_EQ(m.bumpMap.transform.identity, !scaled) << statement;
        if (scaled) {
            const Vec2 uv = m.bumpMap.transform.apply({0.25f, 0.5f});
            EXPECT_FLOAT_EQ(uv.x, 1.0f) << statement;
            EXPECT_FLOAT_EQ(uv.y, 1.5f) << statement;
        }
        const detail::Texture& t = d.textures.at(std::size_t(m.bumpMap.texture));
        EXPECT_EQ(t.wrapS == detail::TextureWrap::Clamp, clamped) << statement;
        EXPECT_EQ(t.use, detail::TextureUse::Data);
        EXPECT_EQ(scene.warnings().size(), 0u) << ::testing::PrintToString(scene.warnings());
    }
}

// Shards of a render compare scene hashes (docs/distributed.md): a bump map and its -bm count.
TEST(ObjBump, TheSceneHashSeesTheBumpMapAndItsMultiplier) {
    test::TempDir dir("obj_bump_hash");
    writeHeights(dir.path() / "h.exr", 2, 2, [](float u, float) { return u; });
    auto hash = [&](const std::string& mtl) {
        return sceneContentHash(detail::sceneData(loadQuad(dir, "newmtl m\n" + mtl)));
    };
    const std::uint64_t flat = hash(""), one = hash("bump h.exr\n"),
                        two = hash("bump -bm 2 h.exr\n");
    EXPECT_NE(flat, one);
    EXPECT_NE(one, two);
    EXPECT_EQ(two, hash("bump -bm 2 h.exr\n"));
}

TEST(ObjBump, BadBumpMultipliersAreRefusedWithTheirLine) {
    for (const auto& [statement, mention] : std::vector<std::pair<std::string, std::string>>{
             {"bump -bm x h.exr", "got 'x'"},
             {"map_Bump -bm nan h.exr", "non-finite"},
             {"map_bump -bm 1e39 h.exr", "overflowing"},
             {"bump -bm", "got ''"},
             {"bump h.exr -bm strong", "got 'strong'"}}) {
        test::TempDir dir("obj_bump_bad");
        writeHeights(dir.path() / "h.exr", 2, 2, [](float, float) { return 0.5f; });
        try {
            loadQuad(dir, "# heights\nnewmtl m\n" + statement + "\n");
            ADD_FAILURE() << "'" << statement << "' was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << statement;
            EXPECT_EQ(fs::path(e.file()), dir.path() / "m.mtl") << statement;
            EXPECT_EQ(e.where(), "line 3") << statement;
            EXPECT_NE(e.message().find(mention), std::string::npos) << e.message();
        }
    }
}

/// Writes a 4 × 4 8-bit PNG whose every texel is `texel` (1 to 4 bytes), as stored, but for its
/// first `blackRows` rows, which are 0.
void writeBytesPng(const fs::path& path, const std::vector<unsigned char>& texel,
                   int blackRows = 0) {
    std::vector<unsigned char> bytes;
    for (int i = 0; i < 16; ++i)
        for (unsigned char b : texel) bytes.push_back(i < 4 * blackRows ? 0 : b);
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out);
    ASSERT_TRUE(
        out->open(path.string(), OIIO::ImageSpec(4, 4, int(texel.size()), OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
    out->close();
}

// An 8-bit PNG of heights is data: byte 128 is 0.502, not the sRGB decoding's 0.216.
TEST(ObjBump, EightBitHeightsAreReadLinearly) {
    test::TempDir dir("obj_bump_png");
    writeBytesPng(dir.path() / "h.png", {128});
    const Scene scene = loadQuad(dir, "newmtl m\nbump h.png\n");
    const SceneData& d = detail::sceneData(scene);
    const detail::Texture& t = d.textures.at(std::size_t(d.materials.at(0).bumpMap.texture));
    EXPECT_FALSE(t.decodeSrgb);
    EXPECT_NEAR(t.lookup({0.5f, 0.5f}).x, 128.0f / 255.0f, 1e-6f);
}

// Blender's exporter writes a tangent-space normal map as map_Bump: a texture of a normal map's
// colours (mean (0.5, 0.5, 1) where not black: Crytek Sponza pads its islands with black) is read
// as one, -bm its strength, with one warning per MTL file; grey heights and a colour photograph
// stay heights.
TEST(ObjBump, ANormalMapInTheBumpSlotIsReadAsOne) {
    test::TempDir dir("obj_bump_normals");
    writeBytesPng(dir.path() / "n.png", {128, 128, 255}, 2);
    writeBytesPng(dir.path() / "photo.png", {90, 140, 200});
    writeBytesPng(dir.path() / "h.png", {200});
    const Scene scene = loadQuad(dir,
                                 "newmtl m\nmap_Bump -bm 0.8 n.png\nnewmtl m2\nbump n.png\n"
                                 "newmtl p\nbump photo.png\nnewmtl h\nbump h.png\n");
    const SceneData& d = detail::sceneData(scene);
    ASSERT_EQ(d.materials.size(), 4u);
    const Material& m = d.materials[0];
    EXPECT_TRUE(m.normalMap.present() && !m.bumpMap.present());
    EXPECT_FLOAT_EQ(m.normalScale, 0.8f);
    EXPECT_TRUE(d.materials[1].normalMap.present());
    for (std::size_t i : {2u, 3u})
        EXPECT_TRUE(d.materials[i].bumpMap.present() && !d.materials[i].normalMap.present())
            << d.materials[i].name;
    const auto& w = scene.warnings();
    EXPECT_EQ(std::count_if(w.begin(), w.end(),
                            [](const std::string& s) {
                                return s.find(
                                           "m.mtl line 2: the bump map 'n.png' of material 'm' "
                                           "holds tangent-space normals") != std::string::npos;
                            }),
              1)
        << ::testing::PrintToString(w);
    EXPECT_EQ(w.size(), 2u) << ::testing::PrintToString(w);  // and: no vertex normals, no tangents
}

// A height ramp h = u (or v) times -bm on a quad of side L scene units slopes by -bm / L: the
// shading normal tilts away from the rising side by atan(slope × mult / L), on either side.
// Tolerance 1e-4 rad: the central differences of float heights near 0.5 over steps of at least
// 0.001 in u are exact to about 1e-4 of the slope.
TEST(ObjBump, ALinearRampTiltsTheNormalByItsSlope) {
    struct Case {
        std::string mtl;
        float scale;     // of the shape (scene units per OBJ unit)
        float expected;  // tan of the tilt
        Vec3 towards;    // the direction the normal leans
    };
    const std::vector<Case> cases{
        {"bump -bm 0.5 u.exr", 1.0f, 0.25f, {-1, 0, 0}},
        {"bump -bm -0.5 u.exr", 1.0f, 0.25f, {1, 0, 0}},
        {"bump -bm 0.5 v.exr", 1.0f, 0.25f, {0, -1, 0}},
        {"bump -bm 0.5 -s 2 1 1 u.exr", 1.0f, 0.5f, {-1, 0, 0}},  // h = frac(2u)
        {"bump -bm 0.5 u.exr", 2.0f, 0.125f, {-1, 0, 0}},         // heights in scene units
    };
    const std::vector<detail::TexFootprint> footprints{
        {}, {{0.02f, 0.0f}, {0.0f, 0.02f}}, detail::kCoarseFootprint};
    for (const Case& c : cases) {
        test::TempDir dir("obj_bump_ramp");
        writeHeights(dir.path() / "u.exr", 64, 4, [](float u, float) { return u; });
        writeHeights(dir.path() / "v.exr", 4, 64, [](float, float v) { return v; });
        const Scene scene = loadQuad(dir, "newmtl m\n" + c.mtl + "\n", c.scale);
        const SceneData& d = detail::sceneData(scene);
        for (const detail::TexFootprint& fp : footprints)
            for (const auto& [prim, b1, b2] : kPoints)
                for (const float side : {1.0f, -1.0f}) {  // seen from the back: ns = -z
                    const SurfacePoint at = hitAt(d, std::uint32_t(prim), b1, b2, fp);
                    const Vec3 n = applyNormalMap(d, d.materials[0], at, {0, 0, side});
                    const float tilt = std::acos(std::clamp(n.z * side, -1.0f, 1.0f));
                    EXPECT_NEAR(tilt, std::atan(c.expected), 1e-4f)
                        << c.mtl << " at uv " << at.uv.x << ", " << at.uv.y << " footprint "
                        << fp.dx.x << " side " << side;
                    // Heights rise towards the viewer on either side: the lean is the same.
                    EXPECT_NEAR(dot(n, c.towards), std::sin(std::atan(c.expected)), 1e-4f)
                        << c.mtl << " side " << side;
                    EXPECT_NEAR(length(n), 1.0f, 1e-6f);
                }
    }
}

// A constant height displaces the surface without bending it: the shading normal comes back
// bit for bit, whatever its direction, side or the lookup's footprint.
TEST(ObjBump, AConstantHeightLeavesTheNormalBitForBit) {
    test::TempDir dir("obj_bump_flat");
    writeImage(Image(8, 8, 3, 0.7f), dir.path() / "h.png");
    writeHeights(dir.path() / "h.exr", 16, 16, [](float, float) { return 0.3f; });
    for (const char* file : {"h.png", "h.exr"}) {
        const Scene scene = loadQuad(dir, std::string("newmtl m\nbump -bm 3 ") + file + "\n");
        const SceneData& d = detail::sceneData(scene);
        for (const detail::TexFootprint& fp :
             {detail::TexFootprint{}, detail::TexFootprint{{0.3f, 0.1f}, {-0.05f, 0.2f}},
              detail::kCoarseFootprint})
            for (const Vec3& ns :
                 {Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalize(Vec3{0.1f, -0.2f, 1.0f})})
                for (const auto& [prim, b1, b2] : kPoints) {
                    const Vec3 n = applyNormalMap(d, d.materials[0],
                                                  hitAt(d, std::uint32_t(prim), b1, b2, fp), ns);
                    EXPECT_EQ(std::memcmp(&n, &ns, sizeof n), 0)
                        << file << ": " << n.x << ", " << n.y << ", " << n.z;
                }
    }
}

// A white (Kd 1) bumped quad under a white sky reflects at most what the flat one does (1 per
// pixel): the image mean stays below 1 + 5σ (σ of the image mean from the variance layer; the
// flat one within 5σ + 1e-3 of 1) and above 0.8 (a shading normal tilted by up to 43° here sees
// at least (1 + cos 43°) / 2 = 0.87 of the sky); the normal feature buffer sees the bumped
// normal, the albedo one stays 1.
TEST(ObjBump, ABumpedQuadReflectsNoMoreThanAFlatOne) {
    test::TempDir dir("obj_bump_furnace");
    // Heights 0.5 + 0.5 sin(2π 4u) sin(2π 3v), -bm 0.15 on the 2 × 2 quad: slopes up to 0.94.
    writeHeights(dir.path() / "h.exr", 256, 256, [](float u, float v) {
        const float pi2 = 6.2831853f;
        return 0.5f + 0.5f * std::sin(pi2 * 4 * u) * std::sin(pi2 * 3 * v);
    });
    auto render = [&](const std::string& bump) {
        dir.write("mesh.obj", kQuadObj);
        dir.write("m.mtl", "newmtl m\nKd 1 1 1\n" + bump);
        dir.write("scene.json", bumpQuadScene(1.0f, 32));
        Renderer renderer(loadScene(dir.path() / "scene.json"));
        return renderer.render(renderer.scene().settings()).frame;
    };
    auto mean = [](const Image& im, int c) {
        double s = 0.0;
        for (int y = 0; y < im.height(); ++y)
            for (int x = 0; x < im.width(); ++x) s += im(x, y, c);
        return s / double(im.pixelCount());
    };
    // The red channel's image mean and its standard error.
    auto meanAndSigma = [&](const FrameBuffers& f) {
        const double pixels = double(f.color().pixelCount());
        return std::pair{mean(f.color(), 0),
                         std::sqrt(mean(f.layer(Layer::Variance), 0) * pixels) / pixels};
    };
    const FrameBuffers flat = render("");
    const FrameBuffers bumped = render("bump -bm 0.15 h.exr\n");
    const auto [flatMean, flatSigma] = meanAndSigma(flat);
    const auto [bumpedMean, bumpedSigma] = meanAndSigma(bumped);
    EXPECT_NEAR(flatMean, 1.0, 5.0 * flatSigma + 1e-3);
    EXPECT_LE(bumpedMean, 1.0 + 5.0 * bumpedSigma) << "sigma " << bumpedSigma;
    EXPECT_GT(bumpedMean, 0.8);
    EXPECT_LT(mean(bumped.layer(Layer::Normal), 2), 0.97);  // flat: 1
    EXPECT_NEAR(mean(flat.layer(Layer::Normal), 2), 1.0, 1e-6);
    EXPECT_NEAR(mean(bumped.layer(Layer::Albedo), 0), 1.0, 1e-6);
}

}  // namespace glint::render
