// OBJ/MTL read by tinyobjloader, with what Glint corrects (issue 32, item 5): faces of more than
// three corners ear-clipped in their plane (polygon_triangulation.cpp), correct for concave
// faces and the same wherever a face sits, a face above tinyobjloader's corner limit refused
// with its line; map_Kd relative to the MTL file; one-value MTL colours grey; MTL values in the
// ranges of the JSON keys they become; files that are not OBJ text refused by their first bytes.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "scene/obj_scan.h"
#include "scene/polygon_triangulation.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using detail::kMaxObjFaceCorners;
using detail::Material;
using detail::MaterialType;
using detail::SceneData;
using detail::triangulatePolygon;

struct P2 {
    double x, y;
};

double signedArea(const std::vector<P2>& poly) {
    double a = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const P2& p = poly[i];
        const P2& q = poly[(i + 1) % poly.size()];
        a += p.x * q.y - q.x * p.y;
    }
    return 0.5 * a;
}

double triangleSignedArea(const P2& a, const P2& b, const P2& c) {
    return 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
}

// Even-odd crossing test.
bool insidePolygon(const std::vector<P2>& poly, const P2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const P2& a = poly[i];
        const P2& b = poly[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x)
            inside = !inside;
    }
    return inside;
}

// Expects `triangles` (corner indices of `poly`) to tile the polygon: n − 2 of them, each wound
// as the polygon, each centroid inside it (unless the triangle is flat), their areas summing to
// its area.
void expectTiles(const std::vector<P2>& poly, const std::vector<std::uint32_t>& triangles,
                 const std::string& what) {
    ASSERT_EQ(triangles.size(), 3 * (poly.size() - 2)) << what;
    const double area = signedArea(poly);
    double sum = 0.0;
    for (std::size_t t = 0; t < triangles.size(); t += 3) {
        const P2& a = poly[triangles[t]];
        const P2& b = poly[triangles[t + 1]];
        const P2& c = poly[triangles[t + 2]];
        const double ta = triangleSignedArea(a, b, c);
        EXPECT_GE(ta * area, 0.0) << what << ": triangle " << t / 3 << " is wound backwards";
        sum += ta;
        // A triangle of three collinear corners (the comb's gap bottoms, made a hair convex by
        // float rounding on the tilted plane) covers nothing: its centroid lies on the boundary.
        if (std::fabs(ta) <= 1e-12 * std::fabs(area)) continue;
        const P2 centroid{(a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0};
        EXPECT_TRUE(insidePolygon(poly, centroid))
            << what << ": triangle " << t / 3 << " (corners " << triangles[t] << ", "
            << triangles[t + 1] << ", " << triangles[t + 2] << ") lies outside the polygon";
    }
    EXPECT_NEAR(sum, area, 1e-9 * std::fabs(area)) << what;
}

std::vector<P2> lShape() {
    return {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
}
// A concave quad whose shorter diagonal (the one tinyobjloader split along) lies outside it.
std::vector<P2> arrowhead() {
    return {{0, 0}, {10, 1}, {8, 0}, {10, -1}};
}
std::vector<P2> uShape() {
    return {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
}
// A five-pointed star: every inner corner is reflex.
std::vector<P2> star(int points = 5, double inner = 0.4) {
    std::vector<P2> s;
    for (int i = 0; i < 2 * points; ++i) {
        const double r = i % 2 ? inner : 1.0, phi = M_PI * i / points + 0.1;
        s.push_back({r * std::cos(phi), r * std::sin(phi)});
    }
    return s;
}
// A comb of `teeth` teeth (4 corners each, half of them reflex; past 80 corners the ear clipper
// hashes its corners on a z-order curve): teeth over x in [2i, 2i + 1] up to y = 5, gaps down to
// y = 1.
std::vector<P2> comb(int teeth) {
    std::vector<P2> c{{0, 0}, {double(2 * teeth - 1), 0}};
    for (int i = teeth - 1; i >= 0; --i) {
        c.push_back({2.0 * i + 1.0, 5.0});
        c.push_back({2.0 * i, 5.0});
        if (i > 0) {
            c.push_back({2.0 * i, 1.0});
            c.push_back({2.0 * i - 1.0, 1.0});
        }
    }
    return c;
}
// A circle whose corners alternate between two radii (every second corner reflex).
std::vector<P2> zigzagCircle(int n, double inner) {
    std::vector<P2> z;
    for (int i = 0; i < n; ++i) {
        const double r = i % 2 ? inner : 1.0, phi = 2.0 * M_PI * i / n;
        z.push_back({r * std::cos(phi), r * std::sin(phi)});
    }
    return z;
}

// The polygon on a tilted plane through `origin`: p = origin + x·e1 + y·e2 (e1, e2 orthonormal,
// so areas are kept).
std::vector<Vec3> embed(const std::vector<P2>& poly, const Vec3& origin) {
    const Vec3 e1 = normalize(Vec3{1.0f, 2.0f, 2.0f});
    const Vec3 e2 = normalize(cross(e1, Vec3{0.0f, 0.0f, 1.0f}));
    std::vector<Vec3> out;
    for (const P2& p : poly) out.push_back(origin + float(p.x) * e1 + float(p.y) * e2);
    return out;
}

TEST(PolygonTriangulation, ConcavePolygonsAreTiledWhereverTheySit) {
    const std::vector<std::pair<std::string, std::vector<P2>>> shapes{
        {"L", lShape()},  {"arrowhead", arrowhead()}, {"U", uShape()},
        {"star", star()}, {"comb", comb(40)},         {"zigzag circle", zigzagCircle(1000, 0.9)}};
    for (const auto& [name, shape] : shapes) {
        for (const bool reversed : {false, true}) {
            std::vector<P2> poly = shape;
            if (reversed) std::reverse(poly.begin(), poly.end());
            const std::string what = name + (reversed ? " (clockwise)" : "");
            // In the xy plane at the origin, and on a tilted plane far from it.
            std::vector<Vec3> flat;
            for (const P2& p : poly) flat.push_back({float(p.x), float(p.y), 0.0f});
            std::vector<std::uint32_t> atOrigin, far;
            triangulatePolygon(flat, atOrigin);
            expectTiles(poly, atOrigin, what + " at the origin");
            triangulatePolygon(embed(poly, {1.0e4f, -2.0e4f, 3.0e4f}), far);
            expectTiles(poly, far, what + " far from the origin");
        }
    }
}

TEST(PolygonTriangulation, ZeroAreaPolygonsGetAFan) {
    const std::vector<Vec3> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
    std::vector<std::uint32_t> triangles;
    triangulatePolygon(line, triangles);
    EXPECT_EQ(triangles, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
}

const char* kScene = R"({"film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj"}],
    "environment": {"color": [1, 1, 1]}})";

// A polygon placed in 3D: p = origin + x·e1 + y·e2, computed in double.
struct Placement {
    std::string name;
    std::array<double, 3> origin, e1, e2;
    std::array<double, 3> at(const P2& p) const {
        return {origin[0] + p.x * e1[0] + p.y * e2[0], origin[1] + p.x * e1[1] + p.y * e2[1],
                origin[2] + p.x * e1[2] + p.y * e2[2]};
    }
};

std::vector<Placement> placements() {
    const double s = 1.0 / 3.0, t = 1.0 / std::sqrt(5.0);
    const std::array<double, 3> e1{s, 2 * s, 2 * s}, e2{2 * t, -t, 0.0};  // orthonormal, tilted
    return {{"at the origin", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
            {"far from the origin", {1000, -2000, 3000}, {1, 0, 0}, {0, 1, 0}},
            {"tilted, far from the origin", {1000, -2000, 3000}, e1, e2}};
}

std::string objOfPolygon(const std::vector<P2>& poly, const Placement& place = placements()[0]) {
    std::ostringstream s;
    s.precision(17);
    for (const P2& p : poly) {
        const auto q = place.at(p);
        s << "v " << q[0] << ' ' << q[1] << ' ' << q[2] << '\n';
    }
    s << "f";
    for (std::size_t i = 0; i < poly.size(); ++i) s << ' ' << i + 1;
    s << '\n';
    return s.str();
}

// The loaded mesh's triangles, as corner indices of `poly` (found by position).
std::vector<std::uint32_t> loadedTriangles(const SceneData& data, const std::vector<P2>& poly,
                                           const Placement& place) {
    const auto& mesh = data.meshes.at(0);
    std::map<std::array<float, 3>, std::uint32_t> corner;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const auto q = place.at(poly[i]);
        corner[{float(q[0]), float(q[1]), float(q[2])}] = std::uint32_t(i);
    }
    std::vector<std::uint32_t> out;
    for (const std::uint32_t v : mesh.indices) {
        const Vec3& p = mesh.positions[v];
        out.push_back(corner.at({p.x, p.y, p.z}));
    }
    return out;
}

// Before issue 32 tinyobjloader's triangulation was right at the origin but not far from it:
// the L on a tilted plane at (1000, −2000, 3000) became 1 triangle, the U in the xy plane there
// triangles of total area 9 (the U's is 7), the comb 551 (its area is 239); the arrowhead, a
// concave quad, was split along its shorter diagonal, which lies outside it, everywhere.
TEST(ObjImport, ConcaveFacesAreTriangulatedInsideThePolygonWhereverItSits) {
    for (const auto& [name, poly] :
         std::vector<std::pair<std::string, std::vector<P2>>>{{"L", lShape()},
                                                              {"arrowhead", arrowhead()},
                                                              {"U", uShape()},
                                                              {"star", star()},
                                                              {"comb", comb(40)}}) {
        for (const Placement& place : placements()) {
            test::TempDir dir("obj_concave");
            dir.write("mesh.obj", objOfPolygon(poly, place));
            dir.write("scene.json", kScene);
            const Scene scene = loadScene(dir.path() / "scene.json");
            expectTiles(poly, loadedTriangles(detail::sceneData(scene), poly, place),
                        name + " " + place.name);
        }
    }
}

// tinyobjloader counts a face's corners in a byte: a face of more is refused with its line
// (docs/scene-format.md, "Polygons") rather than read with a wrapped count.
TEST(ObjImport, AFaceAboveTinyobjloadersCornerLimitIsRefusedWithItsLine) {
    const std::vector<P2> within = zigzagCircle(int(kMaxObjFaceCorners), 0.9);
    test::TempDir dir("obj_limit");
    dir.write("mesh.obj", objOfPolygon(within));
    dir.write("scene.json", kScene);
    const Scene scene = loadScene(dir.path() / "scene.json");
    expectTiles(within, loadedTriangles(detail::sceneData(scene), within, placements()[0]),
                "255 corners");
    const std::vector<P2> above = zigzagCircle(int(kMaxObjFaceCorners) + 1, 0.9);
    dir.write("mesh.obj", "# one corner too many\n" + objOfPolygon(above));
    try {
        loadScene(dir.path() / "scene.json");
        FAIL() << "a face above the limit was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_EQ(fs::path(e.file()), dir.path() / "mesh.obj");
        EXPECT_EQ(e.where(), "line " + std::to_string(above.size() + 2));
        EXPECT_NE(e.message().find("at most 255"), std::string::npos) << e.message();
    }
}

// Writes a 2×2 PNG of one colour.
void writePng(const fs::path& path, float r, float g, float b) {
    Image im(2, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) im(x, y, 0) = r, im(x, y, 1) = g, im(x, y, 2) = b;
    writeImage(im, path);
}

// Changes the working folder for one test (to load a scene by a relative path, as a user does).
class WorkingFolder {
  public:
    explicit WorkingFolder(const fs::path& dir) : m_old(fs::current_path()) {
        fs::current_path(dir);
    }
    ~WorkingFolder() { fs::current_path(m_old); }

  private:
    fs::path m_old;
};

// Before issue 32 map_Kd was resolved against the OBJ's folder and then the scene's folder
// again: the decoy beside the scene was used, and a scene loaded by a relative path with its
// OBJ in a subfolder was refused.
TEST(ObjImport, MapKdIsRelativeToTheMtlFilesFolder) {
    test::TempDir dir("obj_map_kd");
    fs::create_directories(dir.path() / "meshes" / "materials");
    dir.write("meshes/mesh.obj", "mtllib materials/m.mtl\nusemtl red\n" + test::quadObj());
    dir.write("meshes/materials/m.mtl", "newmtl red\nKd 1 1 1\nmap_Kd tex.png\n");
    writePng(dir.path() / "meshes" / "materials" / "tex.png", 1.0f, 0.0f, 0.0f);
    writePng(dir.path() / "meshes" / "tex.png", 0.0f, 1.0f, 0.0f);  // decoys
    writePng(dir.path() / "tex.png", 0.0f, 0.0f, 1.0f);
    dir.write("scene.json", R"({"film": {"width": 8, "height": 8},
        "shapes": [{"obj": "meshes/mesh.obj"}], "environment": {"color": [1, 1, 1]}})");
    for (const bool relative : {false, true}) {
        std::optional<WorkingFolder> cwd;
        if (relative) cwd.emplace(dir.path().parent_path());
        const fs::path scenePath =
            relative ? dir.path().filename() / "scene.json" : dir.path() / "scene.json";
        const Scene scene = loadScene(scenePath);
        const SceneData& data = detail::sceneData(scene);
        ASSERT_EQ(data.materials.size(), 1u);
        const int tex = data.materials[0].texture;
        ASSERT_GE(tex, 0);
        EXPECT_TRUE(fs::equivalent(data.textures[std::size_t(tex)].path,
                                   dir.path() / "meshes" / "materials" / "tex.png"))
            << data.textures[std::size_t(tex)].path;
        // A file texture is read through the scene's texture store, not held as an image.
        const Vec4 texel = data.textures[std::size_t(tex)].lookup({0.5f, 0.5f});
        EXPECT_FLOAT_EQ(texel.x, 1.0f);
        EXPECT_FLOAT_EQ(texel.y, 0.0f);
        EXPECT_FLOAT_EQ(texel.z, 0.0f);
    }
    // A texture missing beside the MTL is refused naming it, not looked for elsewhere.
    fs::remove(dir.path() / "meshes" / "materials" / "tex.png");
    try {
        loadScene(dir.path() / "scene.json");
        FAIL() << "a map_Kd missing beside its MTL was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("materials/tex.png"), std::string::npos) << e.what();
    }
}

// Loads a quad whose material is `mtl` (MTL text defining material "m").
Material loadMtlMaterial(const std::string& mtl) {
    test::TempDir dir("obj_mtl");
    dir.write("mesh.obj", "mtllib m.mtl\nusemtl m\n" + test::quadObj());
    dir.write("m.mtl", mtl);
    dir.write("scene.json", kScene);
    const Scene scene = loadScene(dir.path() / "scene.json");
    return detail::sceneData(scene).materials.at(0);
}

void expectVec(const Vec3& v, float x, float y, float z) {
    EXPECT_FLOAT_EQ(v.x, x);
    EXPECT_FLOAT_EQ(v.y, y);
    EXPECT_FLOAT_EQ(v.z, z);
}

// Before issue 32 one value set only the red channel.
TEST(ObjImport, SingleValueMtlColoursAreGrey) {
    const Material m = loadMtlMaterial("newmtl m\nKd 0.5\nKe 10\n");
    EXPECT_EQ(m.type, MaterialType::Diffuse);
    expectVec(m.albedo, 0.5f, 0.5f, 0.5f);
    expectVec(m.emission, 10.0f, 10.0f, 10.0f);
    const Material metal = loadMtlMaterial("newmtl m\nKd 0\nKs 0.7\nNs 98\n");
    EXPECT_EQ(metal.type, MaterialType::Conductor);
    expectVec(metal.specular, 0.7f, 0.7f, 0.7f);
    EXPECT_FLOAT_EQ(metal.roughness, std::sqrt(2.0f / 100.0f));
    const Material three = loadMtlMaterial("newmtl m\nKd 0.1 0.2 0.3\n");
    expectVec(three.albedo, 0.1f, 0.2f, 0.3f);
}

// Before issue 32 these were clamped without a word, while JSON refuses the same values.
TEST(ObjImport, OutOfRangeMtlValuesAreRefusedWithTheirLine) {
    const std::vector<std::pair<std::string, std::string>> cases{
        {"Kd 1.5 0.5 0.5", "1.5"},  {"Kd -0.1", "-0.1"},
        {"Ks 0.5 2 0.5", "'Ks' 2"}, {"Ke 1 -1 1", "-1"},
        {"Ke 1e19", "1e+19"},       {"Ns -5", "Ns"},
        {"Kd 0.5 0.5", "got 2"},    {"Kd spectral x.rfl", "spectral"}};
    for (const auto& [statement, mention] : cases) {
        test::TempDir dir("obj_mtl_range");
        dir.write("mesh.obj", "mtllib m.mtl\nusemtl m\n" + test::quadObj());
        dir.write("m.mtl", "# a material\nnewmtl m\n" + statement + "\n");
        dir.write("scene.json", kScene);
        try {
            loadScene(dir.path() / "scene.json");
            ADD_FAILURE() << "'" << statement << "' was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << statement;
            EXPECT_EQ(fs::path(e.file()), dir.path() / "m.mtl") << statement;
            EXPECT_EQ(e.where(), "line 3") << statement;
            EXPECT_NE(e.message().find(mention), std::string::npos) << e.message();
        }
    }
    // The ends of each range are accepted.
    const Material m = loadMtlMaterial("newmtl m\nKd 0 1 0\nKs 1\nKe 0\nNs 0\n");
    expectVec(m.albedo, 0.0f, 1.0f, 0.0f);
}

// Loads `files` (name → text) from a fresh folder: "mesh.obj" as a bare asset, or scene.json.
Scene loadFiles(test::TempDir& dir, const std::map<std::string, std::string>& files) {
    for (const auto& [name, text] : files) {
        fs::create_directories((dir.path() / name).parent_path());
        std::ofstream(dir.path() / name, std::ios::binary) << text;
    }
    return loadScene(dir.path() / (files.count("scene.json") ? "scene.json" : "mesh.obj"));
}

// Issue 32: a bare OBJ is a scene by itself as a bare glTF asset is (framing camera, white sky).
TEST(ObjImport, ABareObjIsASceneWithAFramingCameraAndAWhiteSky) {
    test::TempDir dir("obj_bare");
    const Scene scene = loadFiles(dir, {{"mesh.obj", test::quadObj()}});
    const SceneData& data = detail::sceneData(scene);
    EXPECT_EQ(data.width, 640);
    EXPECT_EQ(data.height, 480);
    EXPECT_EQ(data.environment.kind, detail::EnvironmentDesc::Kind::Constant);
    EXPECT_FLOAT_EQ(data.camera.lookAt.x, 0.0f);
    EXPECT_GT(data.camera.position.z, 1.0f);  // on +z, outside the quad's bounding sphere
    EXPECT_NE(data.sourceJson.find("\"obj\": \"mesh.obj\""), std::string::npos);
}

// Before: "mtllib a.mtl b.mtl" read a.mtl only; 3ds Max's "my model.mtl" was two missing files.
TEST(ObjImport, EveryMtllibFileIsReadAndNamesMayHoldSpaces) {
    test::TempDir dir("obj_mtllib");
    const Scene scene = loadFiles(
        dir, {{"mesh.obj", "mtllib a.mtl b.mtl\r\nmtllib my model.mtl\r\nusemtl fromB\r\n" +
                               test::quadObj() + "usemtl spaced\nf 1 2 3\n"},
              {"a.mtl", "newmtl fromA\nKd 1 0 0\n"},
              {"b.mtl", "newmtl fromB\nKd 0 1 0\n"},
              {"my model.mtl", "newmtl spaced\nKd 0 0 1\n"}});
    const SceneData& data = detail::sceneData(scene);
    std::map<std::string, Vec3> albedo;
    for (const Material& m : data.materials) albedo[m.name] = m.albedo;
    ASSERT_EQ(albedo.count("fromB"), 1u);
    ASSERT_EQ(albedo.count("spaced"), 1u);
    expectVec(albedo["fromB"], 0.0f, 1.0f, 0.0f);
    expectVec(albedo["spaced"], 0.0f, 0.0f, 1.0f);
}

// Before: a UTF-8 byte order mark hid the first statement ("mtllib" here, "newmtl" in the MTL).
TEST(ObjImport, AByteOrderMarkIsSkipped) {
    test::TempDir dir("obj_bom");
    const std::string bom = "\xEF\xBB\xBF";
    const Scene scene =
        loadFiles(dir, {{"mesh.obj", bom + "mtllib m.mtl\nusemtl m\n" + test::quadObj()},
                        {"m.mtl", bom + "newmtl m\nKd 0.25 0.5 0.75\n"}});
    const SceneData& data = detail::sceneData(scene);
    EXPECT_EQ(data.materials.at(0).name, "m");
    expectVec(data.materials.at(0).albedo, 0.25f, 0.5f, 0.75f);
}

// Before: map_Kd was looked for only as written: Wings 3D's "maps\FLAME1.jpg" (the folder being
// Maps/), DAZ Studio's "/Maps/rust.jpg" and names with spaces were not found; -s and -o were
// ignored.
TEST(ObjImport, TexturePathsFromOtherMachinesAreFoundBesideTheMtl) {
    for (const auto& [written, found] : std::vector<std::pair<std::string, std::string>>{
             {"maps\\Tex.PNG", "Maps/tex.png"},
             {"/Maps/tex.png", "Maps/tex.png"},
             {"C:\\Users\\me\\tex.png", "tex.png"},
             {"-s 2 2 1 -o 0.5 0 Maps/tex.png", "Maps/tex.png"},
             {"my tex.png -bm 1", "my tex.png"}}) {
        test::TempDir dir("obj_texpath");
        fs::create_directories(dir.path() / "Maps");
        for (const char* file : {"Maps/tex.png", "tex.png", "my tex.png"})
            writePng(dir.path() / file, 1.0f, 0.0f, 0.0f);
        const Scene scene =
            loadFiles(dir, {{"mesh.obj", "mtllib m.mtl\nusemtl m\n" + test::quadObj()},
                            {"m.mtl", "newmtl m\nmap_Kd " + written + "\r\n"}});
        const SceneData& data = detail::sceneData(scene);
        const Material& m = data.materials.at(0);
        ASSERT_GE(m.texture, 0) << written;
        EXPECT_TRUE(fs::equivalent(data.textures[std::size_t(m.texture)].path, dir.path() / found))
            << written;
        EXPECT_EQ(m.textureTransform.identity, written[0] != '-');
        if (written[0] == '-')
            expectVec({m.textureTransform.apply({0.25f, 0.5f}).x,
                       m.textureTransform.apply({0.25f, 0.5f}).y, 0.0f},
                      1.0f, 1.0f, 0.0f);
    }
}

// Before: d, Tr and the PBR extension's Pr/Pm were read by tinyobjloader and dropped.
TEST(ObjImport, DissolveAndThePbrExtensionAreRead) {
    const Material d = loadMtlMaterial("newmtl m\nKd 1 1 1\nd 0.25\n");
    EXPECT_EQ(d.alphaMode, detail::AlphaMode::Blend);
    EXPECT_FLOAT_EQ(d.opacity, 0.25f);
    EXPECT_FLOAT_EQ(loadMtlMaterial("newmtl m\nTr 0.75\n").opacity, 0.25f);
    test::TempDir dir("obj_tr1");  // "Tr 1": invisible, or opaque as some exporters mean it
    const Scene tr1 = loadFiles(dir, {{"mesh.obj", "mtllib m.mtl\nusemtl m\n" + test::quadObj()},
                                      {"m.mtl", "newmtl m\nTr 1\n"}});
    EXPECT_NE(::testing::PrintToString(tr1.warnings()).find("'m' is fully transparent"),
              std::string::npos);
    EXPECT_EQ(loadMtlMaterial("newmtl m\nd 1\nTr 0\n").alphaMode, detail::AlphaMode::Opaque);
    const Material pbr = loadMtlMaterial("newmtl m\nKd 0.5 0.25 0\nPr 0.3\nPm 1\n");
    EXPECT_EQ(pbr.type, MaterialType::MetallicRoughness);
    EXPECT_FLOAT_EQ(pbr.roughness, 0.3f);
    EXPECT_FLOAT_EQ(pbr.metallic, 1.0f);
    expectVec(pbr.albedo, 0.5f, 0.25f, 0.0f);
}

// Unread statements are named once each, with file and first line; norm is read (tangents) and
// wins over a bump map; map_d naming map_Kd's file is map_Kd's alpha.
TEST(ObjImport, UnreadMtlStatementsAreNamedOnceAndNormMapsAreRead) {
    test::TempDir dir("obj_unread");
    for (const char* f : {"n.png", "c.png", "h.png"}) writePng(dir.path() / f, 0.5f, 0.5f, 1.0f);
    const Scene scene = loadFiles(
        dir, {{"mesh.obj", "mtllib m.mtl\nusemtl a\n" + test::quadObj() + "usemtl b\nf 1 2 3\n"},
              {"m.mtl",
               "newmtl a\nmap_Bump -bm 2 h.png\nnorm n.png\nmap_Kd -cc on c.png\n"
               "map_d c.png\nnewmtl b\nbump h.png\nmap_Bump h.png\nmap_d other.png\nnewmtl a\n"}});
    const SceneData& data = detail::sceneData(scene);
    const auto& w = scene.warnings();
    auto count = [&](const std::string& text) {
        return std::count_if(w.begin(), w.end(), [&](const std::string& s) {
            return s.find(text) != std::string::npos;
        });
    };
    EXPECT_EQ(count("line 2: the bump map of material 'a' is ignored: it has a normal"), 1);
    EXPECT_EQ(count("bump' is ignored"), 0);  // b's second statement names the same file
    EXPECT_EQ(count("'map_Kd -cc' is ignored"), 1);
    EXPECT_EQ(count("line 9: 'map_d' of material 'b' is ignored"), 1);
    EXPECT_EQ(count("line 10: material 'a' is defined again; the first"), 1);
    EXPECT_EQ(count("'norm' normal map but the faces have no normals"), 1);
    const Material& a = data.materials.at(0);
    EXPECT_TRUE(a.normalMap.present() && !a.bumpMap.present());
    EXPECT_TRUE(data.materials.at(1).bumpMap.present());
    EXPECT_EQ(a.alphaMode, detail::AlphaMode::Blend);
    EXPECT_FLOAT_EQ(a.opacity, 1.0f);
}

// Before: faces without normals were flat whatever their smoothing group ("s 1" without "vn",
// as ZBrush writes); now a group's faces share angle-weighted vertex normals, "s off" stays flat.
TEST(ObjImport, SmoothingGroupsWithoutNormalsAreSmooth) {
    const std::string roof =
        "v -1 0 0\nv 0 1 0\nv 0 1 -1\nv -1 0 -1\nv 1 0 0\nv 1 0 -1\n"
        "f 1 2 3 4\nf 2 5 6 3\n";
    for (const std::string group : {"s 1\n", "s off\n"}) {
        test::TempDir dir("obj_smooth");
        const Scene scene = loadFiles(dir, {{"mesh.obj", group + roof}});
        const auto& mesh = detail::sceneData(scene).meshes.at(0);
        if (group == "s off\n") {
            EXPECT_TRUE(mesh.normals.empty());
            continue;
        }
        ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
        for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            const Vec3& p = mesh.positions[i];
            const Vec3& n = mesh.normals[i];
            EXPECT_NEAR(length(n), 1.0f, 1e-5f);
            // The ridge's normal is straight up; the eaves' are their own face's.
            const float ridge = p.y > 0.5f ? 1.0f : float(std::sqrt(0.5));
            EXPECT_NEAR(n.y, ridge, 1e-5f) << i;
            EXPECT_NEAR(std::fabs(n.x), p.y > 0.5f ? 0.0f : float(std::sqrt(0.5)), 1e-5f) << i;
        }
    }
    // Normals and texture coordinates named in a file that has none (OpenSubdiv's Maya shapes).
    test::TempDir dir("obj_unnamed");
    const Scene s =
        loadFiles(dir, {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1/1 2/2/2 3/3/3\n"}});
    EXPECT_EQ(s.warnings().size(), 2u) << ::testing::PrintToString(s.warnings());
}

// Before issue 32 random bytes and zeros loaded as an empty mesh (glint-render: exit 0). The
// files here are a few KB: a file of 2 GB is refused the same way, from its first 64 KiB, which
// is all that is read of it before deciding.
TEST(ObjImport, FilesThatAreNotObjTextAreRefusedByTheirFirstBytes) {
    std::mt19937 rng(32);
    std::string random(4096, '\0');
    for (char& c : random) c = char(rng() & 0xff);
    struct Case {
        std::string name, text, where, mention;
    };
    const std::vector<Case> cases{
        {"random bytes", random, "line ", "not OBJ text: byte "},
        {"zeros", std::string(4096, '\0'), "line 1", "not OBJ text: byte 0 is 0x00"},
        {"text that is not a mesh", "hello world\nthis is not a mesh\n", "faces", "no faces"},
        {"an OBJ of points only", "# only points\nv 0 0 0\nv 1 0 0\n", "faces", "no faces"},
        {"an empty file", "", "faces", "no faces"},
    };
    for (const Case& c : cases) {
        test::TempDir dir("obj_binary");
        std::ofstream(dir.path() / "mesh.obj", std::ios::binary) << c.text;
        dir.write("scene.json", kScene);
        try {
            loadScene(dir.path() / "scene.json");
            ADD_FAILURE() << c.name << " was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << c.name;
            EXPECT_EQ(fs::path(e.file()), dir.path() / "mesh.obj") << c.name;
            EXPECT_EQ(e.where().rfind(c.where, 0), 0u) << c.name << ": " << e.where();
            EXPECT_NE(e.message().find(c.mention), std::string::npos)
                << c.name << ": " << e.message();
        }
    }
    // CRLF line ends are text.
    test::TempDir dir("obj_crlf");
    dir.write("mesh.obj", "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n");
    dir.write("scene.json", kScene);
    EXPECT_EQ(detail::sceneData(loadScene(dir.path() / "scene.json")).meshes.at(0).triangleCount(),
              1u);
}

}  // namespace
}  // namespace glint::render
