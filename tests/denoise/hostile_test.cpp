// Bad input to the denoise library, by class (docs/reliability.md): paint scripts and session
// files with unknown keys, numbers JSON cannot hold, folders and devices; a bank opened without
// writing; stale temporary files of an interrupted bank build.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "bank/bank_cache.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/paint_script.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

class Hostile : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() /
                ("glint_denoise_hostile_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }

    fs::path write(const std::string& name, const std::string& text) const {
        std::ofstream(m_dir / name) << text;
        return m_dir / name;
    }

    fs::path m_dir;
};

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `load` must throw one glint::Error that is not Internal, names `file` and holds `mentions`.
template <class Load>
void expectRefused(Load&& load, const fs::path& file, const std::vector<const char*>& mentions) {
    try {
        load();
        ADD_FAILURE() << file << " was accepted";
    } catch (const Error& e) {
        EXPECT_NE(e.kind(), ErrorKind::Internal) << e.what();
        EXPECT_EQ(e.file(), file.string()) << e.what();
        const std::string what = e.what();
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        for (const char* m : mentions) EXPECT_NE(what.find(m), std::string::npos) << what;
    }
}

TEST_F(Hostile, PaintScriptsRefuseUnknownKeysAtEveryLevelWithTheirPointer) {
    const std::string layers = R"("layers": [{"filter": "gaussian"}])";
    const std::map<std::string, std::vector<const char*>> cases{
        // "edit" for "edits": used to save a session with no edits and exit 0.
        {"{" + layers + R"(, "edit": [{"weights": {"layer": 0, "value": 1}}]})",
         {"/edit", "unknown key 'edit'", "edits"}},
        // "parms" for "params": used to use the defaults silently.
        {R"({"layers": [{"filter": "gaussian", "parms": {"sigma": 3}}]})",
         {"/layers/0/parms", "unknown key 'parms'"}},
        {R"({"layers": [{"filter": "gaussian", "params": {"sigmaa": 3}}]})",
         {"/layers/0/params/sigmaa", "unknown parameter 'sigmaa'"}},
        {"{" + layers + R"(, "edits": [{"stroke": {"layer": 0, "sise": 4, "points": [[1, 1]]}}]})",
         {"/edits/0/stroke/sise", "unknown key"}},
        {"{" + layers + R"(, "edits": [{"fill": {"layer": 0, "wand": {"seed": [1, 1],
           "colour": 1}}}]})",
         {"/edits/0/fill/wand/colour", "unknown key"}},
        {"{" + layers + R"(, "edits": [{"diffuse": {"layers": [0], "iterations": 9}}]})",
         {"/edits/0/diffuse/iterations", "unknown key"}},
        {"{" + layers + R"(, "edits": [{"weights": {"layer": 0, "value": 1, "mode": "add"}}]})",
         {"/edits/0/weights/mode", "unknown key"}},
        // Values: integers, ranges, finite numbers.
        {"{" + layers + R"(, "edits": [{"weights": {"layer": 0.5, "value": 1}}]})",
         {"/edits/0/weights/layer", "integer"}},
        {"{" + layers + R"(, "edits": [{"weights": {"layer": 0, "value": 1.5}}]})",
         {"/edits/0/weights/value", "[0, 1]"}},
        {"{" + layers + R"(, "edits": [{"stroke": {"layer": 0, "size": 0, "points": [[1, 1]]}}]})",
         {"/edits/0/stroke/size", "(0, 1e5]"}},
        {"{" + layers +
             R"(, "edits": [{"stroke": {"layer": 0, "size": 4, "points": [[1, 1e300]]}}]})",
         {"/edits/0/stroke/points/0/1"}},
        {R"({"layers": [], "edits": [{"weights": {"layer": 0, "value": 1}}]})", {"no layers"}},
    };
    int i = 0;
    for (const auto& [text, mentions] : cases) {
        const fs::path file = write("s" + std::to_string(i++) + ".json", text);
        try {
            PaintScript::read(file);
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
            EXPECT_EQ(e.file(), file.string());
            for (const char* m : mentions)
                EXPECT_NE(std::string(e.what()).find(m), std::string::npos) << e.what();
        }
    }
}

TEST_F(Hostile, NumbersJsonCannotHoldGiveTheLineAndColumn) {
    // A paint script: nlohmann's text used to name no place.
    const fs::path script = write("big.json",
                                  "{\"layers\": [{\"filter\": \"gaussian\",\n"
                                  "  \"params\": {\"sigma\": 1e400}}]}");
    expectRefused([&] { PaintScript::read(script); }, script,
                  {"line 2, column 23", "number overflow", "1e400"});
    // A session file.
    Session s(testing::syntheticFrame(24, 20));
    s.addLayer("gaussian", {});
    s.save(m_dir / "a.glint-session.json");
    std::string text = slurp(m_dir / "a.glint-session.json");
    text.replace(text.find("\"width\": 24"), 11, "\"width\": -1e400");
    std::ofstream(m_dir / "a.glint-session.json") << text;
    const fs::path session = m_dir / "a.glint-session.json";
    expectRefused([&] { Session::load(session); }, session, {"line", "column", "number overflow"});
}

TEST_F(Hostile, AFolderOrADeviceIsSaidToBeOneNotMalformedOrMissing) {
    fs::create_directories(m_dir / "folder.json");
    expectRefused([&] { PaintScript::read(m_dir / "folder.json"); }, m_dir / "folder.json",
                  {"is a folder"});
    expectRefused([&] { Session::load(m_dir / "folder.json"); }, m_dir / "folder.json",
                  {"is a folder"});
    expectRefused([&] { PaintScript::read("/dev/zero"); }, "/dev/zero", {"not a regular file"});
    expectRefused([&] { Session::load("/dev/null.json"); }, "/dev/null.json", {"not found"});
    expectRefused([&] { PaintScript::read(m_dir / "none.json"); }, m_dir / "none.json",
                  {"not found"});
}

TEST_F(Hostile, SessionFilesRefuseUnknownKeysAndARegionOutsideTheImage) {
    Session s(testing::syntheticFrame(24, 20));
    s.addLayer("gaussian", {});
    s.region = Rect{2, 10, 3, 9};
    s.save(m_dir / "good.glint-session.json");
    const std::string text = slurp(m_dir / "good.glint-session.json");
    ASSERT_TRUE(Session::load(m_dir / "good.glint-session.json").region.has_value());
    struct Case {
        std::string from, to;
        std::vector<const char*> mentions;
    };
    const Case cases[] = {
        {"\"layers\":", "\"layer\": [], \"layers\":", {"/layer", "unknown key 'layer'"}},
        {"\"weights\":", "\"weight\": 1, \"weights\":", {"/layers/0/weight", "unknown key"}},
        {"\"sigma\":", "\"sigmaa\": 1, \"sigma\":", {"/layers/0/params", "sigmaa"}},
        {"\"region\": [\n    2,\n    10,",
         "\"region\": [\n    2,\n    30,",
         {"/region", "not inside the 24x20 image"}},
        {"\"region\": [\n    2,\n    10,", "\"region\": [\n    12,\n    10,", {"/region", "empty"}},
        {"\"width\": 24", "\"width\": 24.5", {"/width", "integer"}},
        {"\"prefilter\": false", "\"prefilter\": 0", {"/prefilter", "true or false"}},
        {"\"format\": 1", "\"format\": 1e10", {"/format", "integer"}},
    };
    int i = 0;
    for (const Case& c : cases) {
        std::string bad = text;
        const auto at = bad.find(c.from);
        ASSERT_NE(at, std::string::npos) << c.from << "\n" << text;
        bad.replace(at, c.from.size(), c.to);
        const std::string name = "bad" + std::to_string(i++) + ".glint-session";
        std::ofstream(m_dir / (name + ".json")) << bad;
        fs::copy(m_dir / "good.glint-session", m_dir / name);
        const fs::path file = m_dir / (name + ".json");
        expectRefused([&] { Session::load(file); }, file, c.mentions);
    }
}

// Every file of a folder: its name → (inode, modification time, size).
std::map<std::string, std::tuple<ino_t, long, long>> snapshot(const fs::path& dir) {
    std::map<std::string, std::tuple<ino_t, long, long>> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        struct stat st {};
        ::stat(entry.path().c_str(), &st);
        files[entry.path().filename().string()] = {st.st_ino, long(st.st_mtim.tv_sec),
                                                   long(st.st_size)};
    }
    return files;
}

// Sets every file's modification time an hour back, so that any rewrite shows.
void ageFiles(const fs::path& dir) {
    for (const auto& entry : fs::directory_iterator(dir))
        fs::last_write_time(entry.path(),
                            fs::last_write_time(entry.path()) - std::chrono::hours(1));
}

TEST_F(Hostile, OpeningABankWritesNothingInItsFolder) {
    const FrameBuffers frame = testing::syntheticFrame(32, 24);
    BankOptions o;
    o.size = 4;
    o.filters = {"gaussian", "bilateral"};
    o.cacheDir = m_dir / "bank";
    fs::create_directories(o.cacheDir);
    const FilterBank built = buildBank(frame, o);
    ageFiles(o.cacheDir);
    const auto before = snapshot(o.cacheDir);
    // An intact bank (the oracle's, navigate's and auto --bank's path) used to rewrite index.json.
    const FilterBank opened = openBank(frame, o.cacheDir);
    EXPECT_EQ(opened.cacheHits(), opened.size());
    EXPECT_EQ(snapshot(o.cacheDir), before);
    // A damaged member is recomputed in memory, the same result, and the folder stays as it is.
    fs::path member;
    for (const auto& entry : fs::directory_iterator(o.cacheDir))
        if (entry.path().extension() == ".exr") member = entry.path();
    fs::resize_file(member, fs::file_size(member) / 2);
    ageFiles(o.cacheDir);
    const auto damaged = snapshot(o.cacheDir);
    const FilterBank repaired = openBank(frame, o.cacheDir);
    EXPECT_EQ(repaired.cacheHits(), repaired.size() - 1);
    for (std::size_t i = 0; i < built.size(); ++i)
        EXPECT_EQ(testing::maxAbsDiff(built.result(i), repaired.result(i)), 0.0);
    EXPECT_EQ(snapshot(o.cacheDir), damaged);
    // A build (not an open) repairs it.
    EXPECT_EQ(buildBank(frame, o).cacheHits(), built.size() - 1);
    EXPECT_EQ(buildBank(frame, o).cacheHits(), built.size());
}

TEST(BankTemporaries, OnlyGlintsOwnTemporaryNamesAreRecognised) {
    EXPECT_EQ(detail::bankTemporaryOwner(".m-0123456789abcdef.tmp-42.exr"), 42);
    EXPECT_EQ(detail::bankTemporaryOwner(".index.tmp-7.json"), 7);
    EXPECT_EQ(detail::bankTemporaryOwner(".index.members-0-16.tmp-99.json"), 99);
    for (const char* other :
         {"m-0123456789abcdef.exr", "m-0123456789abcdef.tmp-42.exr",
          ".m-0123456789abcdef.tmp-42.json", ".m-0123456789ABCDEF.tmp-42.exr", ".m-0123.tmp-42.exr",
          ".index.tmp-x7.json", ".index.tmp-+7.json", ".index.tmp-.json", ".index.tmp-7.exr",
          ".notes.tmp-7.json", ".index.members-a-b.tmp-9.json", ".tmp-1.exr", "index.json",
          ".index.tmp-0.json"})
        EXPECT_EQ(detail::bankTemporaryOwner(other), 0) << other;
}

TEST_F(Hostile, ABuildRemovesTheStaleTemporariesOfAnInterruptedBuildOnly) {
    const FrameBuffers frame = testing::syntheticFrame(32, 24);
    BankOptions o;
    o.size = 3;
    o.filters = {"gaussian"};
    o.cacheDir = m_dir / "bank";
    fs::create_directories(o.cacheDir);
    buildBank(frame, o);
    // A process id no machine hands out (above the kernel's 2^22 limit) has ended.
    const std::string ended = "999999999", alive = std::to_string(::getpid());
    const auto old = fs::file_time_type::clock::now() - std::chrono::minutes(5);
    auto temporary = [&](const std::string& name, bool aged) {
        std::ofstream(o.cacheDir / name) << std::string(30, 'x');
        if (aged) fs::last_write_time(o.cacheDir / name, old);
        return name;
    };
    const std::string stale[] = {
        temporary(".m-0123456789abcdef.tmp-" + ended + ".exr", true),
        temporary(".index.tmp-" + ended + ".json", true),
        temporary(".index.members-0-2.tmp-" + ended + ".json", true),
    };
    const std::string kept[] = {
        temporary(".m-0123456789abcdef.tmp-" + alive + ".exr", true),       // its process runs
        temporary(".m-fedcba9876543210.tmp-" + ended + ".exr", false),      // just written
        temporary(".notes.tmp-" + ended + ".txt", true),                    // not Glint's
        temporary(".m-0123456789abcdef.tmp-" + ended + ".exr.part", true),  // not Glint's
    };
    EXPECT_EQ(buildBank(frame, o).cacheHits(), 4u);
    for (const std::string& name : stale) EXPECT_FALSE(fs::exists(o.cacheDir / name)) << name;
    for (const std::string& name : kept) EXPECT_TRUE(fs::exists(o.cacheDir / name)) << name;
    // Opening the bank removes nothing (it writes nothing).
    temporary(stale[0], true);
    openBank(frame, o.cacheDir);
    EXPECT_TRUE(fs::exists(o.cacheDir / stale[0]));
}

TEST_F(Hostile, ABankIndexWithBadValuesIsAFormatErrorWithItsPointer) {
    const FrameBuffers frame = testing::syntheticFrame(32, 24);
    BankOptions o;
    o.size = 2;
    o.filters = {"gaussian"};
    o.cacheDir = m_dir / "bank";
    fs::create_directories(o.cacheDir);
    buildBank(frame, o);
    const fs::path index = o.cacheDir / "index.json";
    const std::string text = slurp(index);
    const std::pair<std::string, std::string> cases[] = {
        {"\"size\": 2", "\"size\": 1e10"},  // used to be cast to int: undefined behaviour
        {"\"size\": 2", "\"size\": 5000"},  // beyond the bank limit
        {"\"seed\": 1", "\"seed\": -1"},
        {"\"seed\": 1", "\"seed\": 1e400"},  // number overflow
        {"\"prefilter\": false", "\"prefilter\": \"no\""},
    };
    for (const auto& [from, to] : cases) {
        std::string bad = text;
        ASSERT_NE(bad.find(from), std::string::npos) << from;
        bad.replace(bad.find(from), from.size(), to);
        std::ofstream(index) << bad;
        expectRefused([&] { readBankOptions(o.cacheDir); }, index, {});
        expectRefused([&] { openBank(frame, o.cacheDir); }, index, {});
    }
}

}  // namespace
}  // namespace glint::denoise
