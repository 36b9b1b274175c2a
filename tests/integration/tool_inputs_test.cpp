// Every command-line tool against the inputs other programs write and the outputs a user can
// mistype (docs/reliability.md): each reads tiled and multi-part EXRs wherever it reads a layered
// EXR, and each refuses an output that is one of its inputs — spelled differently, through a
// symlink or a hard link — with exit 2 and the input untouched.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "glint/render/asset_formats.h"

namespace fs = std::filesystem;

namespace {

/// Runs the tools built beside the test (build/bin) in a fresh folder.
class ToolInputs : public glint::testing::CliFixture {
  protected:
    ToolInputs() : CliFixture("glint-render") {}

    void SetUp() override {
        CliFixture::SetUp();
        bin = m_binary.parent_path();
        scene = std::string(GLINT_SOURCE_DIR) + "/tests/embed/tiny_cornell.json";
        // A 48 × 48 render with every layer, the input of every command below.
        const auto r = tool("glint-render", scene + " --spp 2 --out " + path("in.exr"));
        ASSERT_EQ(r.exitCode, 0) << r.err;
    }

    glint::testing::RunResult tool(const std::string& name, const std::string& args) const {
        const fs::path out = m_dir / "stdout.txt", err = m_dir / "stderr.txt";
        const std::string cmd = "cd " + m_dir.string() + " && QT_QPA_PLATFORM=offscreen " +
                                (bin / name).string() + " " + args + " >" + out.string() + " 2>" +
                                err.string() + " </dev/null";
        const int status = std::system(cmd.c_str());
        glint::testing::RunResult r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = glint::testing::slurp(out);
        r.err = glint::testing::slurp(err);
        return r;
    }

    fs::path bin;
    std::string scene;
};

/// Every channel and attribute of `from`, rewritten by OpenImageIO as another tool would: tiled
/// 16 × 16 (tile > 0), or one part per layer with bare channel names (tile == 0).
void rewrite(const std::string& from, const std::string& to, int tile) {
    auto in = OIIO::ImageInput::open(from);
    ASSERT_TRUE(in);
    const OIIO::ImageSpec spec = in->spec();
    std::vector<float> px(std::size_t(spec.image_pixels()) * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, px.data()));
    in->close();
    auto out = OIIO::ImageOutput::create(to);
    if (tile > 0) {
        OIIO::ImageSpec tiled = spec;
        tiled.tile_width = tiled.tile_height = tile;
        ASSERT_TRUE(out->open(to, tiled));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
        ASSERT_TRUE(out->close());
        return;
    }
    // Parts by layer: "albedo.R" goes to part "albedo" as "R"; the root R, G, B to part "rgba".
    std::vector<std::string> layers;
    std::vector<std::vector<int>> channels;
    for (int c = 0; c < spec.nchannels; ++c) {
        const std::string& name = spec.channelnames[std::size_t(c)];
        const auto dot = name.rfind('.');
        const std::string layer = dot == std::string::npos ? "rgba" : name.substr(0, dot);
        const auto it = std::find(layers.begin(), layers.end(), layer);
        if (it == layers.end()) layers.push_back(layer), channels.emplace_back();
        channels[std::size_t(std::find(layers.begin(), layers.end(), layer) - layers.begin())]
            .push_back(c);
    }
    std::vector<OIIO::ImageSpec> specs;
    for (std::size_t p = 0; p < layers.size(); ++p) {
        OIIO::ImageSpec part = spec;  // keeps the glint:* attributes
        part.nchannels = int(channels[p].size());
        part.channelnames.clear();
        part.channelformats.clear();
        for (int c : channels[p]) {
            const std::string& name = spec.channelnames[std::size_t(c)];
            part.channelnames.push_back(name.substr(name.rfind('.') + 1));
        }
        part.attribute("oiio:subimagename", layers[p]);
        specs.push_back(part);
    }
    ASSERT_TRUE(out->open(to, int(specs.size()), specs.data())) << out->geterror();
    for (std::size_t p = 0; p < specs.size(); ++p) {
        if (p > 0) {
            ASSERT_TRUE(out->open(to, specs[p], OIIO::ImageOutput::AppendSubimage));
        }
        std::vector<float> part(std::size_t(spec.image_pixels()) * channels[p].size());
        for (std::size_t i = 0; i < std::size_t(spec.image_pixels()); ++i)
            for (std::size_t k = 0; k < channels[p].size(); ++k)
                part[i * channels[p].size() + k] =
                    px[i * std::size_t(spec.nchannels) + std::size_t(channels[p][k])];
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, part.data())) << out->geterror();
    }
    ASSERT_TRUE(out->close());
}

}  // namespace

TEST_F(ToolInputs, EveryToolReadsTiledAndMultiPartExrsAsTheScanlineFile) {
    rewrite(path("in.exr"), path("tiled.exr"), 16);
    rewrite(path("in.exr"), path("parts.exr"), 0);
    // The same numbers from every shape: glint-image diff says the files are identical.
    for (const std::string file : {"tiled.exr", "parts.exr"}) {
        SCOPED_TRACE(file);
        auto r = tool("glint-image", "info " + file);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        EXPECT_NE(r.out.find("albedoVariance"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("sampleCount"), std::string::npos) << r.out;
        r = tool("glint-image", "diff " + file + " --reference in.exr --metric mse --json");
        EXPECT_EQ(r.exitCode, 0) << r.err;
        EXPECT_NE(r.out.find("\"value\":0.0"), std::string::npos) << r.out;
        r = tool("glint-image", "convert " + file + " out.png --layer albedo");
        EXPECT_EQ(r.exitCode, 0) << r.err;
        r = tool("glint-denoise", "apply " + file + " --filter cross-bilateral --out f.exr");
        EXPECT_EQ(r.exitCode, 0) << r.err;
        r = tool("glint-render", scene + " --spp 1 --out r.exr --reference " + file);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        r = tool("glint-denoise", "auto " + file + " --out a.exr");
        EXPECT_EQ(r.exitCode, 0) << r.err;
    }
}

TEST_F(ToolInputs, EveryCommandRefusesAnOutputThatIsOneOfItsInputs) {
    // The reference and a session to compose, made once.
    auto r = tool("glint-render", scene + " --spp 4 --seed 2 --out ref.exr");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    fs::copy_file(path("in.exr"), path("other.exr"));
    const std::string script = path("strokes.json");
    std::ofstream(script) << R"({"layers": [{"filter": "gaussian"}],
                                 "edits": [{"weights": {"layer": 0, "value": 1}}]})";
    r = tool("glint-denoise", "paint in.exr --script strokes.json --save s.glint-session.json");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    fs::create_symlink(path("ref.exr"), path("ref-link.exr"));
    fs::create_hard_link(path("in.exr"), path("in-hard.exr"));

    struct Case {
        const char* tool;
        std::string args;
        const char* input;  ///< the file the output names, which must stay untouched
    };
    // The scene's environment image is an input too: a scene lit by sky.exr.
    {
        OIIO::ImageSpec spec(8, 4, 3, OIIO::TypeFloat);
        const std::vector<float> sky(8 * 4 * 3, 0.5f);
        auto out = OIIO::ImageOutput::create(path("sky.exr"));
        ASSERT_TRUE(out->open(path("sky.exr"), spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeFloat, sky.data()));
        ASSERT_TRUE(out->close());
        fs::create_hard_link(path("sky.exr"), path("sky-hard.exr"));
    }
    std::ofstream(path("lit.json")) << R"({"camera": {"position": [0, 0, 0], "lookAt": [0, 0, 1]},
        "film": {"width": 8, "height": 8}, "environment": {"image": "sky.exr"}})";
    // So are its meshes, their MTL files and a .gltf's buffer files, reached here through hard
    // links whose names pass the .exr check.
    std::ofstream(path("mesh.obj"))
        << "mtllib m.mtl\nusemtl m\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 3\n";
    std::ofstream(path("m.mtl")) << "newmtl m\nKd 0.5 0.5 0.5\n";
    std::ofstream(path("obj.json")) << R"({"camera": {"position": [0, 0, 0], "lookAt": [0, 0, 1]},
        "film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj"}],
        "environment": {"color": [1, 1, 1]}})";
    {
        const float triangle[9] = {0, 0, 1, 1, 0, 1, 0, 1, 1};
        std::ofstream(path("tri.bin"), std::ios::binary)
            .write(reinterpret_cast<const char*>(triangle), sizeof triangle);
        std::ofstream(path("tri.gltf")) << R"({"asset": {"version": "2.0"},
            "buffers": [{"uri": "tri.bin", "byteLength": 36}],
            "bufferViews": [{"buffer": 0, "byteLength": 36}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                           "min": [0, 0, 1], "max": [1, 1, 1]}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
            "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})";
    }
    for (const char* file : {"mesh.obj", "m.mtl", "tri.bin", "obj.json"})
        fs::create_hard_link(path(file), path(std::string(file) + "-hard.exr"));
    const std::vector<Case> cases = {
        {"glint-render", "lit.json --spp 1 --out sky-hard.exr", "sky.exr"},
        {"glint-render", "obj.json --spp 1 --out mesh.obj-hard.exr", "mesh.obj"},
        {"glint-render", "obj.json --spp 1 --out m.mtl-hard.exr", "m.mtl"},
        {"glint-render", "obj.json --spp 1 --out obj.json-hard.exr", "obj.json"},
        {"glint-render", "tri.gltf --spp 1 --out tri.bin-hard.exr", "tri.bin"},
        {"glint-render", scene + " --spp 1 --out ./ref.exr --reference ref.exr", "ref.exr"},
        {"glint-render", scene + " --spp 1 --out ref-link.exr --reference ref.exr", "ref.exr"},
        {"glint-denoise", "apply in.exr --filter gaussian --out in-hard.exr", "in.exr"},
        {"glint-denoise", "apply in.exr --filter gaussian --reference ref.exr --out ./ref.exr",
         "ref.exr"},
        {"glint-denoise", "auto in.exr --out ../" + m_dir.filename().string() + "/in.exr",
         "in.exr"},
        {"glint-lab", "auto in.exr --reference ref.exr --out ref-link.exr", "ref.exr"},
        {"glint-denoise", "composite s.glint-session.json --input other.exr --out other.exr",
         "other.exr"},
        {"glint-denoise",
         "paint in.exr --script strokes.json --save s2.glint-session.json "
         "--out in-hard.exr",
         "in.exr"},
        {"glint-image", "merge in.exr --out ./in.exr", "in.exr"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.tool) + " " + c.args);
        const std::string before = glint::testing::slurp(path(c.input));
        r = tool(c.tool, c.args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find("same file"), std::string::npos) << r.err;
        // One line, after glint-render's "loading" line where the scene must be read first.
        const auto lines = std::count(r.err.begin(), r.err.end(), '\n');
        EXPECT_EQ(lines, r.err.find(": loading ") == std::string::npos ? 1 : 2) << r.err;
        EXPECT_TRUE(glint::testing::slurp(path(c.input)) == before) << c.input << " changed";
    }
}

TEST_F(ToolInputs, EveryToolExitsTwoOnAnUnknownOption) {
    // The studio too (Qt's own parser used to exit 1), on Qt's offscreen platform here.
    std::vector<std::pair<std::string, std::string>> runs{
        {"glint-render", scene + " --out x.exr --no-such-option"},
        {"glint-image", "info in.exr --no-such-option"},
        {"glint-denoise", "list --no-such-option"}};
#ifdef GLINT_STUDIO_BUILT
    runs.push_back({"glint-studio", "--no-such-option"});
#endif
    for (const auto& [name, args] : runs) {
        SCOPED_TRACE(name);
        const auto r = tool(name, args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        // One line of the tool's own (Qt may add its own notes about the environment).
        std::istringstream lines(r.err);
        int own = 0;
        for (std::string line; std::getline(lines, line);)
            if (line.rfind(name + ": ", 0) == 0) {
                ++own;
                EXPECT_NE(line.find("no-such-option"), std::string::npos) << line;
            }
        EXPECT_EQ(own, 1) << r.err;
    }
}

#ifdef GLINT_STUDIO_BUILT
TEST_F(ToolInputs, TheStudiosHelpNamesEveryRegisteredAssetFormat) {
    const auto r = tool("glint-studio", "--help");
    EXPECT_EQ(r.exitCode, 0) << r.err;
    for (const auto& format : glint::render::assetFormats())
        EXPECT_NE(r.out.find(format.name), std::string::npos) << format.name << "\n" << r.out;
}
#endif
