// The asset formats as kinds (scene/asset_format.h): a format registered here, in the test, is
// loaded as a bare asset and as a scene.json shape, listed in the public list, checked against
// the memory limit by its own prediction and named in the shape messages, with no change to
// the loader; no source outside a format's own files names it, but its registration line. And the
// scene's bounding box, computed once when loading ends.
#include <cctype>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/render/asset_formats.h"
#include "glint/render/scene.h"
#include "scene/asset_format.h"
#include "scene/scene_access.h"
#include "scene/scene_data.h"
#include "source_text.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

/// The toy format's import: a ".tri" file is nine numbers, one triangle, of material "toy".
void importToyTriangle(detail::ImportContext& loader, const detail::AssetShape& shape) {
    std::ifstream in(shape.file);
    detail::Mesh mesh;
    mesh.name = shape.file.filename().string();
    for (int v = 0; v < 3; ++v) {
        Vec3 p;
        if (!(in >> p.x >> p.y >> p.z))
            throw Error(ErrorKind::Format, "expected nine numbers", shape.file.string());
        mesh.positions.push_back(p);
    }
    mesh.indices = {0, 1, 2};
    int material = loader.materialIndex("toy");
    if (material < 0) {
        detail::Material m;
        m.name = "toy";
        material = loader.addMaterial(std::move(m));
    }
    mesh.materials = {std::uint32_t(material)};
    detail::SceneData& scene = loader.scene();
    scene.meshes.push_back(std::move(mesh));
    loader.placeMesh(std::uint32_t(scene.meshes.size() - 1), shape);
}

/// A prediction of 1 GB for every toy file, so that a memory limit refuses it.
detail::LoadPrediction predictToyLoad(const fs::path&) {
    detail::LoadPrediction p;
    p.bytes = std::uint64_t(1) << 30;
    p.counted = "one toy triangle";
    p.advice = "toys are small";
    return p;
}

detail::AssetFormat toyFormat() {
    detail::AssetFormat f;
    f.name = "Toy triangle";
    f.key = "tri";
    f.shapeDescription = "a toy triangle file";
    f.fileWord = "toy";
    f.expected = "a .tri file";
    f.extensions = {".tri"};
    f.predictLoad = predictToyLoad;
    f.import = importToyTriangle;
    return f;
}

TEST(AssetFormats, AFormatRegisteredInTheTestIsListedAndLoadsAsABareAsset) {
    const detail::AssetFormat toy = toyFormat();
    const detail::ScopedAssetFormat registered(toy);
    EXPECT_EQ(assetExtensions().back(), ".tri");
    EXPECT_EQ(assetFormats().back().name, "Toy triangle");
    EXPECT_TRUE(isAssetFile("A.TRI"));
    test::TempDir dir("toy_bare");
    const fs::path asset = dir.write("one.tri", "0 0 0  1 0 0  0 1 0\n");
    const Scene scene = loadScene(asset);
    EXPECT_EQ(scene.triangleCount(), 1u);
    EXPECT_TRUE(scene.hasEnvironment());  // no light of its own: the constant sky
    EXPECT_EQ(scene.width(), 640);
    // The framing camera looks at the centre of the box.
    const detail::SceneData& data = detail::sceneData(scene);
    EXPECT_EQ(data.camera.lookAt.x, 0.5f);
    EXPECT_EQ(data.camera.lookAt.y, 0.5f);
    // Saved as the scene.json it stands for, with the format's key.
    EXPECT_NE(data.sourceJson.find("\"tri\": \"one.tri\""), std::string::npos) << data.sourceJson;
}

TEST(AssetFormats, AFormatRegisteredInTheTestIsAShapeWithItsKeyAndItsMessages) {
    const detail::AssetFormat toy = toyFormat();
    const detail::ScopedAssetFormat registered(toy);
    test::TempDir dir("toy_shape");
    dir.write("one.tri", "0 0 0  1 0 0  0 1 0\n");
    dir.write("quad.obj", test::quadObj());
    const Scene scene =
        loadScene(dir.write("scene.json",
                            R"({"film": {"width": 4, "height": 4}, "shapes": [{"tri": "one.tri"},
             {"tri": "one.tri", "transform": {"translate": [0, 0, 5]}}, {"obj": "quad.obj"}]})"));
    EXPECT_EQ(scene.triangleCount(), 4u);
    auto error = [&](const std::string& shape, std::uint64_t limit = 0) {
        try {
            loadScene(dir.write("bad.json", R"({"film": {"width": 4, "height": 4}, "shapes": [)" +
                                                shape + "]}"),
                      limit);
        } catch (const Error& e) {
            return e;
        }
        ADD_FAILURE() << "no error for " << shape;
        return Error(ErrorKind::Internal, "none");
    };
    const Error none = error(R"({"material": "x"})");
    EXPECT_EQ(none.where(), "/shapes/0");
    EXPECT_NE(none.message().find("or 'tri' (a toy triangle file)"), std::string::npos)
        << none.what();
    const Error unknown = error(R"({"tri": "one.tri", "size": 2})");
    EXPECT_NE(unknown.message().find("expected one of: obj, gltf, tri, material"),
              std::string::npos)
        << unknown.what();
    const Error edits = error(R"({"tri": "one.tri", "edits": {}})");
    EXPECT_EQ(edits.where(), "/shapes/0/edits");
    EXPECT_NE(edits.message().find("'edits' does not apply to a toy triangle file"),
              std::string::npos)
        << edits.what();
    // A format's own reason for another format's key, as the OBJ format gives it.
    const Error objEdits = error(R"({"obj": "quad.obj", "edits": {}})");
    EXPECT_EQ(objEdits.where(), "/shapes/0/edits");
    EXPECT_EQ(objEdits.message(),
              "'edits' changes a glTF asset's material factors; an OBJ shape's materials are "
              "edited as JSON materials of the same name");
    const Error objMaterials = error(R"({"obj": "quad.obj", "materials": {}, "edits": {}})");
    EXPECT_EQ(objMaterials.where(), "/shapes/0/materials");
    const Error missing = error(R"({"tri": "none.tri"})");
    EXPECT_EQ(missing.where(), "/shapes/0/tri");
    EXPECT_NE(missing.message().find("toy file"), std::string::npos) << missing.what();
    // The memory limit asks the format's own prediction, and says its advice.
    const Error memory = error(R"({"tri": "one.tri"})", std::uint64_t(1) << 20);
    EXPECT_EQ(memory.kind(), ErrorKind::OutOfMemory);
    EXPECT_NE(memory.message().find("one toy triangle"), std::string::npos) << memory.what();
    EXPECT_NE(memory.message().find("; toys are small"), std::string::npos) << memory.what();
}

TEST(AssetFormats, WithoutTheRegistrationTheExtensionIsNoAsset) {
    {
        const detail::AssetFormat toy = toyFormat();
        const detail::ScopedAssetFormat registered(toy);
        EXPECT_TRUE(isAssetFile("one.tri"));
    }
    EXPECT_FALSE(isAssetFile("one.tri"));
    for (const std::string& ext : assetExtensions()) EXPECT_NE(ext, ".tri");
}

TEST(AssetFormats, TheBuiltInFormatsListTheirExtensionsInLowerCase) {
    std::vector<std::string> keys;
    for (const AssetFormatInfo& f : assetFormats()) {
        keys.push_back(f.key);
        for (const std::string& ext : f.extensions) {
            EXPECT_EQ(ext.front(), '.');
            for (char c : ext) EXPECT_FALSE(std::isupper(static_cast<unsigned char>(c))) << ext;
            EXPECT_TRUE(isAssetFile("MODEL" + ext));
        }
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"obj", "gltf"}));
    EXPECT_EQ(assetExtensions(), (std::vector<std::string>{".obj", ".gltf", ".glb"}));
    EXPECT_FALSE(isAssetFile("scene.json"));
}

/// The lower-case parts of an identifier: "importObjMesh" → import, obj, mesh; "kGlbChunkBin" →
/// k, glb, chunk, bin; "obj_import" → obj, import.
std::vector<std::string> identifierParts(const std::string& identifier) {
    std::vector<std::string> parts;
    std::string part;
    auto flush = [&] {
        if (!part.empty()) parts.push_back(part);
        part.clear();
    };
    for (std::size_t i = 0; i < identifier.size(); ++i) {
        const auto c = static_cast<unsigned char>(identifier[i]);
        const auto next =
            i + 1 < identifier.size() ? static_cast<unsigned char>(identifier[i + 1]) : '\0';
        if (c == '_') {
            flush();
            continue;
        }
        // A part starts at an upper-case letter after a lower-case one or a digit, and at the last
        // capital of a run followed by a lower-case letter ("GLBFile" → glb, file).
        const auto previous = static_cast<unsigned char>(identifier[i - (i > 0)]);
        if (std::isupper(c) && !part.empty() && (!std::isupper(previous) || std::islower(next)))
            flush();
        part += char(std::tolower(c));
    }
    flush();
    return parts;
}

/// `code` (comments blanked) with the text of its string and character literals blanked, but
/// for the paths of its #include lines: what it names as code.
std::string withoutLiterals(std::string code) {
    for (std::size_t i = 0; i < code.size(); ++i) {
        const bool lineStart = i == 0 || code[i - 1] == '\n';
        if (lineStart) {
            const std::size_t first = code.find_first_not_of(" \t", i);
            if (first != std::string::npos && code.compare(first, 8, "#include") == 0) {
                i = code.find('\n', first);
                if (i == std::string::npos) break;
                continue;
            }
        }
        const char quote = code[i];
        if (quote != '"' && quote != '\'') continue;
        // A digit separator (1'000) is no literal.
        if (quote == '\'' && i > 0 && std::isalnum(static_cast<unsigned char>(code[i - 1])))
            continue;
        std::size_t end = std::string::npos;
        if (quote == '"' && i > 0 && code[i - 1] == 'R') {
            // A raw string: R"delimiter( … )delimiter".
            const std::size_t open = code.find('(', i);
            if (open != std::string::npos)
                end = code.find(")" + code.substr(i + 1, open - i - 1) + "\"", open);
            if (end != std::string::npos) end += open - i + 1;
        } else {
            for (std::size_t j = i + 1; j < code.size() && code[j] != '\n'; ++j) {
                if (code[j] == '\\') {
                    ++j;
                } else if (code[j] == quote) {
                    end = j;
                    break;
                }
            }
        }
        if (end == std::string::npos) continue;
        for (std::size_t j = i + 1; j < end; ++j)
            if (code[j] != '\n') code[j] = ' ';
        i = end;
    }
    return code;
}

/// The lines of `code` (comments blanked) that name one of `names` in an identifier or an
/// #include path, as "line N: identifier".
std::vector<std::string> linesNaming(const std::string& code, const std::set<std::string>& names) {
    std::vector<std::string> hits;
    std::istringstream lines(withoutLiterals(code));
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
        for (std::size_t i = 0; i < line.size();) {
            const auto identifierChar = [&](std::size_t k) {
                return std::isalnum(static_cast<unsigned char>(line[k])) || line[k] == '_';
            };
            if (!identifierChar(i)) {
                ++i;
                continue;
            }
            std::size_t end = i;
            while (end < line.size() && identifierChar(end)) ++end;
            const std::string identifier = line.substr(i, end - i);
            for (const std::string& part : identifierParts(identifier))
                if (names.count(part)) {
                    hits.push_back("line " + std::to_string(number) + ": " + identifier);
                    break;
                }
            i = end;
        }
    }
    return hits;
}

TEST(AssetFormats, TheFormatCheckFindsAFormatNamedInCodeButNotInWords) {
    const std::string code = R"(#include "scene/obj_import.h"
std::uint32_t n = loader.importObj(path);
const char* text = "an OBJ file, 'obj'";
GltfOverrides overrides; int object = 0, glbx = 1'000;
)";
    const std::vector<std::string> hits = linesNaming(code, {"obj", "gltf", "glb"});
    EXPECT_EQ(hits, (std::vector<std::string>{"line 1: obj_import", "line 2: importObj",
                                              "line 4: GltfOverrides"}));
    EXPECT_EQ(identifierParts("kGlbChunkBin"),
              (std::vector<std::string>{"k", "glb", "chunk", "bin"}));
    EXPECT_EQ(identifierParts("GLBFile_obj2"), (std::vector<std::string>{"glb", "file", "obj2"}));
}

TEST(AssetFormats, NoSourceOutsideAFormatsOwnFilesNamesItButItsRegistrationLine) {
    // docs/architecture.md, "Adding an asset format": a format is its own files
    // (renderer/src/scene/<name>_*.{h,cpp}), one line in asset_formats.cpp and a row of the
    // docs. So no other source of the renderer, its CLI, the studio or the Python module names
    // one in code (an identifier or an #include; words in comments and messages are free),
    // and asset_formats.cpp names each on its line X(<key>) only.
    std::vector<std::pair<std::string, std::set<std::string>>> formatNames;  // key, its names
    std::set<std::string> allNames;
    for (const AssetFormatInfo& format : assetFormats()) {
        std::set<std::string> names{format.key};
        for (const std::string& ext : format.extensions) names.insert(ext.substr(1));
        formatNames.push_back({format.key, names});
        allNames.insert(names.begin(), names.end());
    }
    const fs::path root(GLINT_SOURCE_DIR);
    const fs::path scene = root / "renderer/src/scene";
    auto ownFile = [&](const fs::path& file) {
        if (file.parent_path() != scene) return false;
        const std::string name = file.filename().string();
        for (const std::string& n : allNames)
            if (name.rfind(n + "_", 0) == 0) return true;
        return false;
    };
    int files = 0;
    for (const char* dir :
         {"renderer/src", "renderer/include", "renderer/cli", "gui", "python/src"}) {
        ASSERT_TRUE(fs::is_directory(root / dir)) << dir;
        for (const fs::directory_entry& entry : fs::recursive_directory_iterator(root / dir)) {
            const std::string ext = entry.path().extension().string();
            if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
            if (ownFile(entry.path())) continue;
            ++files;
            const std::string code = test::codeOf(entry.path());
            const bool registry = entry.path() == scene / "asset_formats.cpp";
            for (const auto& [key, names] : formatNames) {
                const std::vector<std::string> hits = linesNaming(code, names);
                if (!registry) {
                    EXPECT_TRUE(hits.empty())
                        << entry.path().lexically_relative(root).string() << " names the format "
                        << key << " (" << hits.front()
                        << "): what a format needs from the loader goes through ImportContext, "
                           "what the loader needs from it through its AssetFormat";
                    continue;
                }
                ASSERT_EQ(hits.size(), 1u)
                    << "asset_formats.cpp names " << key << " on " << hits.size()
                    << " lines: one registration line, X(" << key << ")";
            }
        }
    }
    EXPECT_GT(files, 100);
    // The registry's lines are X(<key>), and each format's file is the one the docs name.
    const std::string registry = test::codeOf(scene / "asset_formats.cpp");
    std::ifstream in(root / "docs/architecture.md");
    std::stringstream docs;
    docs << in.rdbuf();
    const std::string section = docs.str().substr(docs.str().find("## Adding an asset format"));
    for (const char* listed : {"renderer/src/scene/<format>_import.cpp",
                               "renderer/src/scene/asset_formats.cpp", "docs/scene-format.md"})
        EXPECT_NE(section.find(listed), std::string::npos) << listed;
    for (const AssetFormatInfo& format : assetFormats()) {
        EXPECT_NE(registry.find("X(" + format.key + ")"), std::string::npos) << format.key;
        const std::string own = test::codeOf(scene / (format.key + "_import.cpp"));
        EXPECT_NE(own.find(format.key + "AssetFormat()"), std::string::npos) << format.key;
    }
}

TEST(SceneBounds, TheBoxIsTheShutterOpenPoseAndTheExtentEveryPose) {
    test::TempDir dir("bounds");
    dir.write("quad.obj", test::quadObj());
    const Scene scene = loadScene(dir.write("scene.json", R"({"film": {"width": 4, "height": 4},
        "shapes": [{"obj": "quad.obj", "transform": {"translate": [10, 0, 0]},
                    "motion": {"translate": [30, 0, 0]}}]})"));
    const detail::SceneData& data = detail::sceneData(scene);
    ASSERT_FALSE(data.bounds.empty());
    // test::quadObj() spans [-1, 1] in x; at shutter open it is moved by 10, at close by 30.
    EXPECT_EQ(data.bounds.lo.x, 9.0f);
    EXPECT_EQ(data.bounds.hi.x, 11.0f);
    EXPECT_EQ(data.extent, 22.0f);  // x from 9 to 31
}

TEST(SceneBounds, ASceneWithoutGeometryHasAnEmptyBox) {
    test::TempDir dir("bounds_empty");
    const Scene scene = loadScene(
        dir.write("scene.json",
                  R"({"film": {"width": 4, "height": 4}, "environment": {"color": [1, 1, 1]}})"));
    EXPECT_TRUE(detail::sceneData(scene).bounds.empty());
    EXPECT_EQ(detail::sceneData(scene).extent, 1.0f);
}

}  // namespace
}  // namespace glint::render
