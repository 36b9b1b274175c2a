// Hostile input, by class (docs/reliability.md): every bad scene, mesh, texture or option gets
// one glint::Error naming the file and the place — through the library (the studio's path:
// never a crash, never a half-built scene) and through glint-render (exit 2, every stderr line
// one of glint-render's own, no output file, no temporary file left).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>

#include "cli_fixture.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "png_bytes.h"
#include "test_util.h"

namespace glint::render {
namespace {

namespace fs = std::filesystem;

const char* kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// A scene with one OBJ (`obj` text, as mesh.obj) under a constant environment.
std::string sceneWith(const std::string& extra = "",
                      const std::string& shape = R"({"obj": "mesh.obj"})") {
    return R"({"camera": {"position": [0.3, 0.3, 3], "lookAt": [0.3, 0.3, 0]},
      "film": {"width": 8, "height": 8}, "shapes": [)" +
           shape + R"(], "environment": {"color": [1, 1, 1]})" + extra + "}";
}

struct Case {
    const char* name;
    std::map<std::string, std::string> files;  // written into the case's folder
    std::string fileNamed;                     // the error names this file
    std::string mention;                       // and contains this (place or message)
};

std::vector<Case> hostileScenes() {
    const std::string lightMtl = "newmtl lamp\nKd 0 0 0\nKe 1 1 1\n";
    return {
        {"face index far past the vertices",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 100000000\n"},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 4"},
        {"face index just past the vertices",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 999\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 4"},
        {"negative face index before the first vertex",
         {{"mesh.obj", "v 0 0 0\nf -1 -2 -3\nv 1 0 0\nv 0 1 0\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 2"},
        {"normal index out of range",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n"},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 5"},
        {"texture index zero",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/0 2/1 3/1\n"},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 5"},
        {"face with two corners",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 3"},
        {"NaN vertex",
         {{"mesh.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 2"},
        {"NaN vertex of a light",
         {{"mesh.obj", "mtllib l.mtl\nusemtl lamp\nv 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n"},
          {"l.mtl", lightMtl},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 4"},
        {"infinite normal",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 inf\nf 1//1 2//1 3//1\n"},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 4"},
        {"text where a number belongs",
         {{"mesh.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 2"},
        {"1e30 vertex",
         {{"mesh.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 2"},
        {"scene scaled beyond the coordinate range",
         {{"mesh.obj", kTriangle},
          {"scene.json", sceneWith("", R"({"obj": "mesh.obj", "transform": {"scale": 1e12}})")}},
         "mesh.obj",
         "line 2"},
        {"motion leaving the coordinate range",
         {{"mesh.obj", kTriangle},
          {"scene.json",
           sceneWith("", R"({"obj": "mesh.obj", "motion": {"translate": [1e10, 0, 0]}})")}},
         "scene.json",
         "/shapes/0/"},
        {"missing mtllib",
         {{"mesh.obj", "mtllib nowhere.mtl\nusemtl a\n" + std::string(kTriangle)},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "nowhere.mtl"},
        {"MTL emission beyond the radiance limit",
         {{"mesh.obj", "mtllib l.mtl\nusemtl lamp\n" + std::string(kTriangle)},
          {"l.mtl", "newmtl lamp\nKd 0 0 0\nKe 1e30 1 1\n"},
          {"scene.json", sceneWith()}},
         "l.mtl",
         "line 3"},
        {"MTL dissolve beyond 1",
         {{"mesh.obj", "mtllib l.mtl\nusemtl m\n" + std::string(kTriangle)},
          {"l.mtl", "newmtl m\nd 1.5\n"},
          {"scene.json", sceneWith()}},
         "l.mtl",
         "line 2"},
        {"MTL texture missing",
         {{"mesh.obj", "mtllib l.mtl\nusemtl m\n" + std::string(kTriangle)},
          {"l.mtl", "newmtl m\nKd 1 1 1\nmap_Kd maps\\gone.jpg\n"},
          {"scene.json", sceneWith()}},
         "l.mtl",
         "line 3"},
        {"MTL NaN albedo",
         {{"mesh.obj", "mtllib l.mtl\nusemtl m\n" + std::string(kTriangle)},
          {"l.mtl", "newmtl m\nKd nan 0.5 0.5\n"},
          {"scene.json", sceneWith()}},
         "l.mtl",
         "line 2"},
        {"MTL text where a number belongs",
         {{"mesh.obj", "mtllib l.mtl\nusemtl m\n" + std::string(kTriangle)},
          {"l.mtl", "newmtl m\nKd 0.5 0.5 0.5\nNs high\n"},
          {"scene.json", sceneWith()}},
         "l.mtl",
         "line 3"},
        {"emission beyond the radiance limit",
         {{"mesh.obj", kTriangle},
          {"scene.json",
           sceneWith(R"(, "materials": {"m": {"type": "diffuse", "emission": [1e30, 1, 1]}})",
                     R"({"obj": "mesh.obj", "material": "m"})")}},
         "scene.json",
         "/materials/m/emission/0"},
        {"environment colour × scale beyond the radiance limit",
         {{"mesh.obj", kTriangle},
          {"scene.json", R"({"film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj"}],
             "environment": {"color": [1e17, 1, 1], "scale": 1e5}})"}},
         "scene.json",
         "/environment"},
        {"number too large for a double",
         {{"mesh.obj", kTriangle}, {"scene.json", sceneWith(R"(, "render": {"spp": -1e400})")}},
         "scene.json",
         "line 2, column"},
        {"spp above the limit",
         {{"mesh.obj", kTriangle}, {"scene.json", sceneWith(R"(, "render": {"spp": 16777217})")}},
         "scene.json",
         "/render/spp"},
        {"seed below zero",
         {{"mesh.obj", kTriangle}, {"scene.json", sceneWith(R"(, "render": {"seed": -1})")}},
         "scene.json",
         "/render/seed"},
        {"camera beyond the coordinate range",
         {{"mesh.obj", kTriangle},
          {"scene.json", R"({"camera": {"position": [0, 0, 1e20]}, "film": {"width": 8,
             "height": 8}, "shapes": [{"obj": "mesh.obj"}]})"}},
         "scene.json",
         "/camera/position/2"},
        {"zero scale",
         {{"mesh.obj", kTriangle},
          {"scene.json", sceneWith("", R"({"obj": "mesh.obj", "transform": {"scale": 1e-30}})")}},
         "scene.json",
         "/shapes/0/transform/scale"},
        {"OBJ path is a folder",
         {{"sub/x.txt", ""}, {"scene.json", sceneWith("", R"({"obj": "sub"})")}},
         "scene.json",
         "/shapes/0/obj"},
        {"face corner with a trailing slash",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/ 2/ 3/\n"}, {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 4: malformed face corner '1/'"},
        {"mtllib naming a folder",
         {{"mesh.obj", "mtllib sub\n" + std::string(kTriangle)},
          {"sub/x.txt", ""},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "line 1: mtllib 'sub' is a folder, expected an MTL file"},
        {"mtllib naming a device",
         {{"mesh.obj", "mtllib ../../../../../../../../dev/zero\n" + std::string(kTriangle)},
          {"scene.json", sceneWith()}},
         "mesh.obj",
         "is not a regular file"},
        {"seed beyond 64 bits reported as written",
         {{"mesh.obj", kTriangle},
          {"scene.json", sceneWith(R"(, "render": {"seed": 18446744073709551615})")}},
         "scene.json",
         "got 18446744073709551615"},
        {"lookAt differing from position at scale 1e-30",
         {{"mesh.obj", kTriangle},
          {"scene.json", R"({"camera": {"position": [0, 0, 0], "lookAt": [0, 0, 1e-30]},
             "film": {"width": 8, "height": 8}, "shapes": [{"obj": "mesh.obj"}]})"}},
         "scene.json",
         "lookAt is 1e-30 from position, too close"},
        {"map_Kd naming a device (was \"not found\")",
         {{"mesh.obj",
           "mtllib m.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"},
          {"m.mtl", "newmtl m\nmap_Kd /dev/zero\n"},
          {"scene.json", sceneWith()}},
         "m.mtl",
         "line 2: map_Kd '/dev/zero' of material 'm' is not a regular file (a device or a pipe)"},
        {"PNG texture of 0x0 pixels (libpng printed two lines)",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"},
          {"t.png", glint::test::pngOfSize(0, 0)},
          {"scene.json",
           sceneWith(R"(, "materials": {"m": {"type": "diffuse", "texture": "t.png"}})",
                     R"({"obj": "mesh.obj", "material": "m"})")}},
         "t.png",
         "a PNG is at least 1x1"},
        {"truncated PNG texture",
         {{"mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n"},
          {"scene.json",
           sceneWith(R"(, "materials": {"m": {"type": "diffuse", "texture": "t.png"}})",
                     R"({"obj": "mesh.obj", "material": "m"})")}},
         "t.png",
         "damaged PNG"},
    };
}

// Writes a case's files into `dir`; the truncated PNG is made from a real one.
void writeCase(const Case& c, const fs::path& dir) {
    for (const auto& [name, text] : c.files) {
        fs::create_directories((dir / name).parent_path());
        std::ofstream(dir / name, std::ios::binary) << text;
    }
    if (std::string(c.name) == "truncated PNG texture") {
        Image im(16, 16, 3, 0.5f);
        writeImage(im, dir / "full.png");
        const auto size = fs::file_size(dir / "full.png");
        fs::copy_file(dir / "full.png", dir / "t.png");
        fs::resize_file(dir / "t.png", size - 20);
    }
}

TEST(Hostile, TheLibraryThrowsOneErrorNamingTheFileAndPlace) {
    for (const Case& c : hostileScenes()) {
        test::TempDir dir("hostile");
        writeCase(c, dir.path());
        try {
            const Scene scene = loadScene(dir.path() / "scene.json");
            ADD_FAILURE() << c.name << ": loaded";
        } catch (const Error& e) {
            EXPECT_NE(e.kind(), ErrorKind::Internal) << c.name << ": " << e.what();
            EXPECT_EQ(fs::path(e.file()).filename(), fs::path(c.fileNamed).filename())
                << c.name << ": " << e.what();
            EXPECT_NE(std::string(e.what()).find(c.mention), std::string::npos)
                << c.name << ": " << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos)
                << c.name << ": more than one line: " << e.what();
        } catch (const std::exception& e) {
            ADD_FAILURE() << c.name << ": not a glint::Error: " << e.what();
        }
    }
}

using glint::testing::RunResult;

class HostileCli : public glint::testing::CliFixture {
  protected:
    HostileCli() : CliFixture("glint-render") {}

    // Exit 2; every stderr line is glint-render's own (no library chatter), the last names
    // `mention`; no output and no temporary file in `folder`.
    void expectRefused(const std::string& args, const std::string& mention, const fs::path& folder,
                       const std::string& what) {
        const RunResult r = run(args);
        EXPECT_EQ(r.exitCode, 2) << what << "\n" << r.err;
        std::istringstream lines(r.err);
        std::string line, last;
        while (std::getline(lines, line)) {
            EXPECT_EQ(line.rfind("glint-render: ", 0), 0u) << what << ": stray line: " << line;
            last = line;
        }
        EXPECT_NE(last.find(mention), std::string::npos) << what << "\n" << r.err;
        for (const auto& e : fs::directory_iterator(folder)) {
            const std::string name = e.path().filename().string();
            EXPECT_NE(name, "out.exr") << what;
            EXPECT_EQ(name.find(".tmp-"), std::string::npos) << what << ": left " << name;
        }
    }
};

TEST_F(HostileCli, EveryClassOfBadSceneExitsTwoWithOneClearLine) {
    const std::vector<Case> cases = hostileScenes();
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        const fs::path dir = m_dir / ("case" + std::to_string(i));
        fs::create_directories(dir);
        writeCase(c, dir);
        expectRefused((dir / "scene.json").string() + " --out " + (dir / "out.exr").string(),
                      fs::path(c.fileNamed).filename().string(), dir, c.name);
    }
}

TEST_F(HostileCli, OptionsHaveTheSceneFilesLimitsAndOutputsAreCheckedFirst) {
    std::ofstream(m_dir / "mesh.obj") << kTriangle;
    std::ofstream(m_dir / "scene.json") << sceneWith();
    // Russian roulette's depth is the scene's alone (glint-render lost --rr-depth): its limit
    // holds.
    std::ofstream(m_dir / "rr.json") << sceneWith(R"(, "render": {"rrDepth": 2000})");
    const std::string scene = path("scene.json"), out = " --out " + path("out.exr");
    struct Flag {
        std::string args, mention;
    };
    const Flag flags[] = {
        {scene + " --set maxDepth=100000" + out, "--set maxDepth"},
        {path("rr.json") + out, "rrDepth"},
        {scene + " --spp 16777217" + out, "--spp"},
        {scene + " --time-limit inf" + out, "--time-limit"},
        {scene + " --time-limit nan" + out, "--time-limit"},
        {scene + " --seed -1" + out, "--seed"},
        {scene + " --seed 9223372036854775808" + out, "--seed"},
        {scene + " --threads 5000" + out, "--threads"},
        {scene + " --out " + path("missing/out.exr"), "does not exist"},
        {scene + " --out " + m_dir.string(), "--out"},
        {scene + " --out " + path("out.png"), ".exr"},
        {scene + " --out " + path("out.txt"), ".exr"},
        {path("nowhere") + " --out " + path("x.exr"), "nowhere"},
        {m_dir.string() + " --out " + path("x.exr"), "folder"},
        // The reason given is the real one.
        {scene + " --shard 1/4 --time-limit 5" + out, "--shard: a shard needs a fixed spp"},
        {scene + " --memory-limit 0" + out, "--memory-limit: '0' is no memory at all"},
        {scene + " --memory-limit 0.5" + out, "--memory-limit: '0.5' is no memory at all"},
        {"/dev/zero --out " + path("x.exr"), "/dev/zero: is not a regular file"},
        {"'" + path("new\nline.json") + "' --out " + path("x.exr"), "new\\nline.json"},
    };
    for (const Flag& f : flags) expectRefused(f.args, f.mention, m_dir, f.args);
    // A tiny time limit still renders the first pass.
    const RunResult r = run(scene + " --time-limit 1e-9 --out " + path("tiny.exr"));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(readExr(path("tiny.exr")).metadata().spp, 1);
}

// Every file the scene was read from is an input --out must not name: the scene file, its OBJ,
// the OBJ's MTL, the MTL's texture, the environment image and a .gltf's buffer file (only the
// images were checked: --out onto the OBJ or the .bin replaced it by the render). Reached here
// through hard links whose names pass the .exr check; refused before any work, intact after.
TEST_F(HostileCli, AnOutputThatIsOneOfTheScenesFilesIsRefusedAndTheFileKept) {
    std::ofstream(m_dir / "mesh.obj") << "mtllib l.mtl\nusemtl m\nvt 0 0\n"
                                      << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n";
    std::ofstream(m_dir / "l.mtl") << "newmtl m\nKd 1 1 1\nmap_Kd t.png\n";
    writeImage(Image(4, 4, 3, 0.5f), m_dir / "t.png");
    writeImage(Image(8, 4, 3, 0.5f), m_dir / "sky.exr");
    std::ofstream(m_dir / "scene.json") << R"({"camera": {"position": [0.3, 0.3, 3],
        "lookAt": [0.3, 0.3, 0]}, "film": {"width": 8, "height": 8},
        "shapes": [{"obj": "mesh.obj"}, {"gltf": "tri.gltf"}],
        "environment": {"image": "sky.exr"}})";
    const float triangle[9] = {0, 0, -1, 1, 0, -1, 0, 1, -1};
    std::ofstream(m_dir / "tri.bin", std::ios::binary)
        .write(reinterpret_cast<const char*>(triangle), sizeof triangle);
    std::ofstream(m_dir / "tri.gltf") << R"({"asset": {"version": "2.0"},
        "buffers": [{"uri": "tri.bin", "byteLength": 36}],
        "bufferViews": [{"buffer": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "type": "VEC3", "count": 3,
                       "min": [0, 0, -1], "max": [1, 1, -1]}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0})";
    // The scene renders as it is.
    ASSERT_EQ(run(path("scene.json") + " --spp 1 --out " + path("ok.exr")).exitCode, 0);
    for (const char* file :
         {"scene.json", "mesh.obj", "l.mtl", "t.png", "sky.exr", "tri.gltf", "tri.bin"}) {
        const std::string link = path(std::string(file) + "-hard.exr");
        fs::create_hard_link(path(file), link);
        const std::string before = glint::testing::slurp(path(file));
        const RunResult r = run(path("scene.json") + " --spp 1 --out " + link);
        EXPECT_EQ(r.exitCode, 2) << file << "\n" << r.err;
        EXPECT_NE(r.err.find("--out: '" + link +
                             "' is the same file as the input given by the "
                             "scene"),
                  std::string::npos)
            << file << "\n"
            << r.err;
        EXPECT_TRUE(glint::testing::slurp(path(file)) == before) << file << " changed";
    }
}

// SIGTERM during the write of a large frame: no hidden temporary file is left beside the
// target and an older file there stays intact.
TEST_F(HostileCli, ASignalDuringTheWriteLeavesNoTemporaryFile) {
    std::ofstream(m_dir / "big.json")
        << R"({"camera": {"position": [0, 0, 0], "lookAt": [0, 0, -1]},
      "film": {"width": 1400, "height": 1400}, "environment": {"color": [0.5, 0.5, 0.5]},
      "render": {"spp": 1}})";
    FrameBuffers old(4, 4);
    old.color().fill(0.25f);
    writeExr(old, m_dir / "big.exr");
    const pid_t child = fork();
    if (child == 0) {
        const std::string out = (m_dir / "big.exr").string(), json = (m_dir / "big.json").string();
        std::freopen("/dev/null", "w", stderr);
        std::freopen("/dev/null", "w", stdout);
        execl(m_binary.c_str(), m_binary.c_str(), json.c_str(), "--out", out.c_str(),
              static_cast<char*>(nullptr));
        _exit(127);
    }
    ASSERT_GT(child, 0);
    // The temporary name is known in advance: wait for it to appear, then interrupt.
    const fs::path tmp = m_dir / (".big.tmp-" + std::to_string(child) + ".exr");
    bool seen = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    int status = 0;
    while (std::chrono::steady_clock::now() < deadline) {
        if (fs::exists(tmp)) {
            seen = true;
            kill(child, SIGTERM);
            break;
        }
        if (waitpid(child, &status, WNOHANG) == child) break;  // finished before we saw it
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (seen) waitpid(child, &status, 0);
    ASSERT_TRUE(seen) << "the write finished before the test could interrupt it";
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM);
    EXPECT_FALSE(fs::exists(tmp));
    const FrameBuffers kept = readExr(m_dir / "big.exr");
    EXPECT_EQ(kept.width(), 4);
    EXPECT_EQ(kept.color()(1, 1, 0), 0.25f);
}

}  // namespace
}  // namespace glint::render

namespace glint::render {
namespace {

// The largest radiance a scene may hold renders with a finite colour and a finite variance (its
// variance, about the square, still fits a float); 1e30 was accepted before and gave an Inf
// variance layer while the summary said 0 non-finite values.
TEST(Hostile, TheLargestRadianceKeepsTheVarianceFinite) {
    test::TempDir dir("radiance");
    dir.write("quad.obj", test::quadObj());
    const fs::path file = dir.write("scene.json", R"({
      "camera": {"position": [0, 3, 0.01], "lookAt": [0, 0, 0]},
      "film": {"width": 8, "height": 8},
      "materials": {"lamp": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5],
                              "emission": [1e18, 5e17, 1e17]}},
      "shapes": [{"obj": "quad.obj", "material": "lamp"}],
      "environment": {"color": [1e18, 1e18, 1e18]}})");
    Renderer renderer(loadScene(file));
    Settings s = renderer.scene().settings();
    s.spp = 8;
    const RenderResult r = renderer.render(s);
    EXPECT_EQ(r.frame.color().countNonFinite(), 0u);
    EXPECT_EQ(r.frame.layer(Layer::Variance).countNonFinite(), 0u);
    EXPECT_EQ(r.stats.nonFiniteSamples, 0);
    EXPECT_GT(r.frame.color()(4, 4, 0), 1e17f);
}

}  // namespace
}  // namespace glint::render
