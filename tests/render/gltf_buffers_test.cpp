// glTF buffers read from their files (renderer/src/scene/gltf_buffers.{h,cpp}, gltf_file.cpp,
// gltf_accessor.cpp, gltf_mesh.cpp): a .glb, a .gltf with its buffer in a .bin file (both read
// piece by piece from the file) and a .gltf with a data URI (read by tinygltf) give the same
// meshes, byte for byte those of the loader before; buffers are bounded by their real size; a file
// cut short while it is read is an error; a mesh's arrays are allocated once at their final size.

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/image.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "gltf_builder.h"
#include "mesh_hash.h"
#include "scene/gltf_buffers.h"
#include "scene/gltf_file.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace test_gltf;

std::vector<unsigned char> readAll(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A .glb's document and its buffer 0 (the BIN chunk cut to buffer 0's byteLength).
std::pair<json, std::vector<unsigned char>> splitGlb(const std::vector<unsigned char>& glb) {
    auto u32 = [&](std::size_t at) {
        return std::uint32_t(glb[at]) | std::uint32_t(glb[at + 1]) << 8 |
               std::uint32_t(glb[at + 2]) << 16 | std::uint32_t(glb[at + 3]) << 24;
    };
    const std::size_t jsonSize = u32(12);
    json doc = json::parse(glb.begin() + 20, glb.begin() + 20 + std::ptrdiff_t(jsonSize));
    const std::size_t bin = 20 + jsonSize + 8;
    const std::size_t length = doc["buffers"][0]["byteLength"].get<std::size_t>();
    return {doc, {glb.begin() + std::ptrdiff_t(bin), glb.begin() + std::ptrdiff_t(bin + length)}};
}

/// The three ways of storing `glb`'s asset in `dir`: the .glb itself, a .gltf naming a .bin
/// file, and a .gltf with the buffer as a data URI.
std::vector<fs::path> threeForms(const test::TempDir& dir, const std::vector<unsigned char>& glb) {
    auto [doc, bin] = splitGlb(glb);
    const fs::path asGlb = writeBytes(dir.path() / "asset.glb", glb);
    writeBytes(dir.path() / "asset buffer.bin", bin);
    doc["buffers"][0]["uri"] = "asset%20buffer.bin";  // decoded as tinygltf decodes it
    const fs::path asFiles = dir.write("files.gltf", doc.dump());
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
    const fs::path asDataUri = dir.write("datauri.gltf", doc.dump());
    return {asGlb, asFiles, asDataUri};
}

TEST(GltfBuffers, TheBinChunkAndBufferFilesAreReadFromTheirFilesAndDataUrisAreNot) {
    const std::vector<unsigned char> glb =
        readAll(fs::path(GLINT_SOURCE_DIR) / "scenes/assets/duck/Duck.glb");
    const std::vector<unsigned char> bin = splitGlb(glb).second;
    test::TempDir dir("gltf_buffers_files");
    const std::vector<fs::path> forms = threeForms(dir, glb);
    for (std::size_t f = 0; f < forms.size(); ++f) {
        tinygltf::Model model;
        detail::GltfBuffers buffers;
        detail::readGltfFile(forms[f], model, buffers);
        ASSERT_EQ(buffers.count(), 1u);
        const bool fromFile = f < 2;
        EXPECT_EQ(buffers.fromFile(0), fromFile) << forms[f].filename();
        // tinygltf holds a one-byte placeholder for a buffer read from its file.
        EXPECT_EQ(model.buffers[0].data.size(), fromFile ? 1u : bin.size()) << forms[f].filename();
        ASSERT_EQ(buffers.size(0), bin.size()) << forms[f].filename();
        std::vector<unsigned char> scratch;
        const unsigned char* bytes = buffers.bytes(0, 0, bin.size(), scratch);
        EXPECT_EQ(std::memcmp(bytes, bin.data(), bin.size()), 0) << forms[f].filename();
        EXPECT_EQ(bytes == scratch.data(), fromFile) << forms[f].filename();
        bytes = buffers.bytes(0, 1000, 1010, scratch);
        EXPECT_EQ(std::memcmp(bytes, bin.data() + 1000, 10), 0) << forms[f].filename();
    }
}

TEST(GltfBuffers, AtMostSixtyFourBufferFilesAreHeldOpenTheRestReadByTinygltf) {
    // 70 buffers, each a file holding one triangle's positions: the first 64 are read from their
    // files, the others whole by tinygltf, and the mesh is the same either way.
    test::TempDir dir("gltf_buffers_many");
    json doc = {{"asset", {{"version", "2.0"}}}};
    json primitives = json::array();
    for (int i = 0; i < 70; ++i) {
        const std::vector<float> p = {float(i), 0, 0, float(i) + 1, 0, 0, float(i), 1, 0};
        std::vector<unsigned char> bytes(p.size() * 4);
        std::memcpy(bytes.data(), p.data(), bytes.size());
        const std::string name = "b" + std::to_string(i) + ".bin";
        writeBytes(dir.path() / name, bytes);
        doc["buffers"].push_back({{"byteLength", bytes.size()}, {"uri", name}});
        doc["bufferViews"].push_back({{"buffer", i}, {"byteLength", bytes.size()}});
        doc["accessors"].push_back(
            {{"bufferView", i}, {"componentType", 5126}, {"type", "VEC3"}, {"count", 3}});
        primitives.push_back({{"attributes", {{"POSITION", i}}}});
    }
    doc["meshes"] = json::array({{{"primitives", primitives}}});
    doc["nodes"] = json::array({{{"mesh", 0}}});
    doc["scenes"] = json::array({{{"nodes", {0}}}});
    const fs::path asset = dir.write("many.gltf", doc.dump());
    tinygltf::Model model;
    detail::GltfBuffers buffers;
    detail::readGltfFile(asset, model, buffers);
    ASSERT_EQ(buffers.count(), 70u);
    for (std::size_t i = 0; i < 70; ++i)
        EXPECT_EQ(buffers.fromFile(i), i < 64) << "buffers[" << i << "]";
    const Scene scene = loadScene(asset);
    const detail::Mesh& m = detail::sceneData(scene).meshes.at(0);
    ASSERT_EQ(m.positions.size(), 210u);
    EXPECT_EQ(m.positions[3 * 65 + 1].x, 66.0f);
}

TEST(GltfBuffers, AFileCutShortWhileTheAssetIsReadIsAnErrorNamingTheBuffer) {
    // A file another program truncates after it was opened (an exporter saving over it) gives
    // a short read: one error, not a crash (as a file mapped into memory would give).
    const std::vector<unsigned char> glb =
        readAll(fs::path(GLINT_SOURCE_DIR) / "scenes/assets/duck/Duck.glb");
    const std::size_t bytes = splitGlb(glb).second.size();
    test::TempDir dir("gltf_buffers_cut");
    const std::vector<fs::path> forms = threeForms(dir, glb);
    for (const fs::path& asset : {forms[0], forms[1]}) {
        tinygltf::Model model;
        detail::GltfBuffers buffers;
        detail::readGltfFile(asset, model, buffers);
        const fs::path file = asset.extension() == ".glb" ? asset : dir.path() / "asset buffer.bin";
        fs::resize_file(file, fs::file_size(file) - 1000);
        std::vector<unsigned char> scratch;
        EXPECT_NO_THROW(buffers.bytes(0, 0, 1000, scratch)) << asset.filename();
        try {
            buffers.bytes(0, bytes - 2000, bytes, scratch);
            ADD_FAILURE() << asset.filename() << ": the cut file was read";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Io);
            EXPECT_EQ(e.file(), asset.string());
            EXPECT_EQ(e.where(), "buffers[0]");
            EXPECT_NE(e.message().find("changed while it was read"), std::string::npos) << e.what();
        }
    }
}

TEST(GltfBuffers, TheCommittedAssetsGiveTheMeshesOfTheLoaderBefore) {
    // The hashes of the mesh arrays as 0932a18's loader (tinygltf holding every buffer, the
    // accessors copied into vectors) gave them; every form must give them now.
    const std::vector<std::pair<const char*, std::uint64_t>> assets = {
        {"scenes/assets/duck/Duck.glb", 0x17144e8edc52a397ull},
        {"scenes/assets/blender_scene.glb", 0x3c55767b6ef81387ull}};
    for (const auto& [asset, before] : assets) {
        test::TempDir dir("gltf_buffers_assets");
        for (const fs::path& form : threeForms(dir, readAll(fs::path(GLINT_SOURCE_DIR) / asset))) {
            const Scene scene = loadScene(form);
            EXPECT_FALSE(detail::sceneData(scene).meshes.empty());
            EXPECT_EQ(test::meshArraysHash(scene), before) << asset << " as " << form.filename();
        }
    }
}

TEST(GltfBuffers, AMeshOfSeveralPrimitivesIsAllocatedOnceAtItsFinalSize) {
    // Two primitives of two materials, the second without indices or uvs: its arrays are
    // appended into arrays reserved at their final size (the positions with a vertex of
    // padding), which would otherwise have grown by doubling.
    GltfBuilder b;
    b.quad(-1, true);
    b.quad(-1, false);
    json prims = b.doc["meshes"][0]["primitives"];
    prims.push_back(b.doc["meshes"][1]["primitives"][0]);
    b.doc["materials"] = json::array({{{"name", "a"}}, {{"name", "b"}}});
    prims[0]["material"] = 0;
    prims[1]["material"] = 1;
    prims[1]["attributes"].erase("TEXCOORD_0");
    b.doc["meshes"] = json::array({{{"primitives", prims}}});
    b.scene({b.node({{"mesh", 0}})});
    test::TempDir dir("gltf_buffers_primitives");
    for (const fs::path& form : threeForms(dir, b.glb())) {
        const Scene scene = loadScene(form);
        ASSERT_EQ(detail::sceneData(scene).meshes.size(), 1u);
        const detail::Mesh& m = detail::sceneData(scene).meshes[0];
        // The arrays 0932a18's loader gave (its hash), with no slack.
        EXPECT_EQ(test::meshArraysHash(scene), 0xf9e343a4b85fb9a4ull) << form.filename();
        EXPECT_EQ(m.positions.size(), 10u);
        EXPECT_EQ(m.positions.capacity(), m.positions.size() + 1);
        EXPECT_EQ(m.normals.capacity(), m.normals.size());
        EXPECT_EQ(m.uvs.size(), 10u);  // the second primitive's are zero
        EXPECT_EQ(m.uvs.capacity(), m.uvs.size());
        EXPECT_EQ(m.indices.size(), 12u);
        EXPECT_EQ(m.indices.capacity(), m.indices.size());
        EXPECT_EQ(m.materials.size(), 4u);
        EXPECT_EQ(m.materials.capacity(), m.materials.size());
        EXPECT_EQ(m.tangents.capacity(), 0u);
    }
}

TEST(GltfBuffers, GeneratedTangentsOfSeveralPrimitivesAreAllocatedOnce) {
    // Three normal-mapped primitives without tangents: the tangents generated for each are
    // written into an array reserved for all (grown primitive by primitive, 4, 10, then 14
    // vertices, its capacity would reach 20).
    test::TempDir dir("gltf_buffers_tangents");
    Image texture(2, 2, 3, 0.5f);
    writeImage(texture, dir.path() / "normal.png");
    GltfBuilder b;
    b.quad(0, true);
    b.quad(0, false);
    json prims = b.doc["meshes"][0]["primitives"];
    prims.push_back(b.doc["meshes"][1]["primitives"][0]);
    prims.push_back(b.doc["meshes"][0]["primitives"][0]);
    b.doc["meshes"] = json::array({{{"primitives", prims}}});
    b.doc["images"] = json::array({{{"uri", "normal.png"}}});
    b.doc["textures"] = json::array({{{"source", 0}}});
    b.doc["materials"] = json::array({{{"normalTexture", {{"index", 0}}}}});
    b.scene({b.node({{"mesh", 0}})});
    for (const fs::path& form : threeForms(dir, b.glb())) {
        const Scene scene = loadScene(form);
        const detail::Mesh& m = detail::sceneData(scene).meshes.at(0);
        ASSERT_EQ(m.positions.size(), 14u) << form.filename();
        EXPECT_EQ(m.positions.capacity(), m.positions.size() + 1) << form.filename();
        ASSERT_EQ(m.tangents.size(), 14u) << form.filename();
        EXPECT_EQ(m.tangents.capacity(), m.tangents.size()) << form.filename();
    }
}

TEST(GltfBuffers, InterleavedAttributesReadWholeAMegabyteAtATime) {
    // Positions and normals interleaved in one 3 MB bufferView: each is read from the file a
    // megabyte at a time (elements across the pieces' ends included), the same bytes twice.
    const std::size_t count = 3 * 43691;  // 131073 vertices, 24 bytes each: 3.0 MB
    std::vector<float> interleaved;
    interleaved.reserve(count * 6);
    for (std::size_t i = 0; i < count; ++i) {
        const float x = float(i % 1000), y = float(i / 1000);
        interleaved.insert(interleaved.end(), {x, y, 0.25f * x, 0.0f, 0.0f, 1.0f});
    }
    GltfBuilder b;
    b.bin.resize(interleaved.size() * 4);
    std::memcpy(b.bin.data(), interleaved.data(), b.bin.size());
    b.doc["bufferViews"] = json::array(
        {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", b.bin.size()}, {"byteStride", 24}}});
    b.doc["accessors"] = json::array({{{"bufferView", 0},
                                       {"byteOffset", 0},
                                       {"componentType", 5126},
                                       {"type", "VEC3"},
                                       {"count", count}},
                                      {{"bufferView", 0},
                                       {"byteOffset", 12},
                                       {"componentType", 5126},
                                       {"type", "VEC3"},
                                       {"count", count}}});
    b.doc["meshes"] =
        json::array({{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}}}}});
    b.scene({b.node({{"mesh", 0}})});
    test::TempDir dir("gltf_buffers_interleaved");
    const std::vector<fs::path> forms = threeForms(dir, b.glb());
    for (const fs::path& form : {forms[0], forms[1]}) {
        const Scene scene = loadScene(form);
        const detail::Mesh& m = detail::sceneData(scene).meshes.at(0);
        ASSERT_EQ(m.positions.size(), count) << form.filename();
        ASSERT_EQ(m.normals.size(), count) << form.filename();
        std::size_t wrong = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const float* e = &interleaved[6 * i];
            wrong += m.positions[i].x != e[0] || m.positions[i].y != e[1] ||
                     m.positions[i].z != e[2] || m.normals[i].x != e[3] || m.normals[i].y != e[4] ||
                     m.normals[i].z != e[5];
        }
        EXPECT_EQ(wrong, 0u) << form.filename();
    }
}

/// The error loading `asset` gives (fails the test when it loads).
Error loadError(const fs::path& asset) {
    try {
        loadScene(asset);
    } catch (const Error& e) {
        return e;
    }
    ADD_FAILURE() << asset << " was accepted";
    return Error(ErrorKind::Internal, "accepted");
}

TEST(GltfBuffers, ABufferFileShorterOrLongerThanItsByteLengthIsRefused) {
    // Such a file is left to tinygltf, which reads it; Glint names what is wrong, as before.
    GltfBuilder b;
    b.scene({b.node({{"mesh", b.quad()}})});
    test::TempDir dir("gltf_buffers_short");
    json doc = b.doc;
    doc["buffers"] = json::array({{{"byteLength", b.bin.size()}, {"uri", "asset.bin"}}});
    const fs::path asset = dir.write("asset.gltf", doc.dump());
    for (const long delta : {-8L, 4L}) {
        std::vector<unsigned char> bin = b.bin;
        bin.resize(std::size_t(long(bin.size()) + delta));
        writeBytes(dir.path() / "asset.bin", bin);
        const Error e = loadError(asset);
        EXPECT_EQ(e.file(), asset.string());
        EXPECT_EQ(e.where(), "buffers") << e.what();
        EXPECT_NE(e.message().find("has " + std::to_string(bin.size()) +
                                   " bytes, its byteLength says " + std::to_string(b.bin.size())),
                  std::string::npos)
            << e.what();
    }
}

TEST(GltfBuffers, ABufferViewOrAccessorPastTheEndOfABufferFileIsRefused) {
    GltfBuilder b;
    b.scene({b.node({{"mesh", b.quad()}})});
    test::TempDir dir("gltf_buffers_bounds");
    writeBytes(dir.path() / "asset.bin", b.bin);
    struct Case {
        const char* what;
        json doc;
        std::string place, message;
    };
    std::vector<Case> cases;
    json views = b.doc;
    views["bufferViews"][0]["byteLength"] = 100000;
    cases.push_back({"view", views, "bufferViews[0]",
                     "go past the end of buffer 0 (" + std::to_string(b.bin.size()) + " bytes)"});
    json accessor = b.doc;
    accessor["accessors"][0]["count"] = 1000;
    cases.push_back({"accessor", accessor, "accessors[0]", "go past the end of its bufferView"});
    for (Case& c : cases) {
        // As a .glb (its BIN chunk read from the file) and as a .gltf with the .bin file.
        GltfBuilder g = b;
        g.doc = c.doc;
        c.doc["buffers"] = json::array({{{"byteLength", b.bin.size()}, {"uri", "asset.bin"}}});
        const std::string name = c.what;
        for (const fs::path& asset : {writeBytes(dir.path() / (name + ".glb"), g.glb()),
                                      dir.write(name + ".gltf", c.doc.dump())}) {
            const Error e = loadError(asset);
            EXPECT_EQ(e.file(), asset.string());
            EXPECT_EQ(e.where(), c.place) << e.what();
            EXPECT_NE(e.message().find(c.message), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace glint::render
