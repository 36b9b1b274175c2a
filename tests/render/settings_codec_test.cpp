// The render-settings codec (glint/render/settings_codec.h): one table of names, and every
// encoding — the text values of sessions and journals, scene.json's render block, a frame's EXR
// metadata — gives back the settings it was given.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "glint/render/settings_codec.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// Path-traced settings with every named field away from its default.
Settings pathSettings() {
    Settings s;
    s.spp = 37;
    s.seed = (std::uint64_t(1) << 40) + 3;
    s.mis = MisHeuristic::None;
    s.strategy = Strategy::Light;
    s.sampler = SamplerKind::Independent;
    s.maxDepth = 7;
    s.rrDepth = 2;
    s.halfBuffers = true;
    s.textureCacheMb = 77;
    s.accel = Accel::Clusters;
    s.mlt.largeStep = 0.3;
    s.mlt.smallStep = 0.1;
    s.mlt.lens = 0.0;
    s.mlt.light = 1.0 / 3.0;
    s.mlt.bootstrap = 12345;
    s.mlt.chains = 64;
    s.mlt.groups = 8;
    s.mlt.featureSpp = 2;
    return s;
}

/// The same for Metropolis.
Settings mltSettings() {
    Settings s = pathSettings();
    s.integrator = Integrator::Mlt;
    s.halfBuffers = false;
    s.mis = MisHeuristic::Balance;
    return s;
}

/// The named fields of `a` and `b` are equal (`names`: those compared; all when empty).
void expectSameSettings(const Settings& a, const Settings& b,
                        const std::vector<std::string>& names = {}) {
    EXPECT_EQ(encodeSettings(a, names), encodeSettings(b, names));
    // And field by field, not only through the codec's own text.
    auto named = [&](const char* name) {
        return names.empty() || std::find(names.begin(), names.end(), name) != names.end();
    };
    if (named("spp")) {
        EXPECT_EQ(a.spp, b.spp);
    }
    if (named("seed")) {
        EXPECT_EQ(a.seed, b.seed);
    }
    if (named("integrator")) {
        EXPECT_EQ(a.integrator, b.integrator);
    }
    if (named("mis")) {
        EXPECT_EQ(a.mis, b.mis);
    }
    if (named("halfBuffers")) {
        EXPECT_EQ(a.halfBuffers, b.halfBuffers);
    }
    if (named("maxDepth")) {
        EXPECT_EQ(a.maxDepth, b.maxDepth);
    }
    if (named("mltLight")) {
        EXPECT_EQ(a.mlt.light, b.mlt.light);
    }
    if (named("mltBootstrap")) {
        EXPECT_EQ(a.mlt.bootstrap, b.mlt.bootstrap);
    }
}

/// The names recordSettings writes for `s` (besides spp, seed and integrator).
std::vector<std::string> recordedNames(const Settings& s) {
    FrameMetadata md;
    recordSettings(s, md);
    std::vector<std::string> names = {"spp", "seed", "integrator"};
    for (const auto& [key, value] : md.extra) names.push_back(key);
    return names;
}

TEST(SettingsCodec, EachNameIsSpeltOnceAndMapsToItsFlag) {
    std::set<std::string> names;
    for (const SettingSpec& spec : settingSpecs()) {
        EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
        ASSERT_NE(findSetting(spec.name), nullptr) << spec.name;
        EXPECT_EQ(findSetting(spec.name)->kind, spec.kind);
    }
    // The spellings of the old encodings that differed are gone.
    EXPECT_EQ(findSetting("halves"), nullptr);
    EXPECT_TRUE(names.count("halfBuffers"));
    EXPECT_EQ(settingFlag(*findSetting("maxDepth")), "--max-depth");
    EXPECT_EQ(settingFlag(*findSetting("halfBuffers")), "--half-buffers");
    EXPECT_EQ(settingFlag(*findSetting("mltFeatureSpp")), "--mlt-feature-spp");
    EXPECT_EQ(settingFlag(*findSetting("textureCacheMb")), "--texture-cache-mb");
}

TEST(SettingsCodec, TheSetHelpNamesItsKeysAndThePageListingThemAll) {
    const std::string help = settingAssignmentsHelp("spp, seed");
    EXPECT_EQ(help.find("a render setting name=value (repeatable)"), 0u) << help;
    EXPECT_NE(help.find("render keys: spp, seed, …"), std::string::npos) << help;
    EXPECT_NE(help.find("docs/scene-format.md"), std::string::npos) << help;
}

TEST(SettingsCodec, SettingsRoundTripThroughTheirText) {
    for (const Settings& s : {pathSettings(), mltSettings(), Settings{}}) {
        const SettingValues text = encodeSettings(s);
        EXPECT_EQ(text.size(), settingSpecs().size());
        expectSameSettings(decodeSettings(text, Settings{}), s);
    }
    // A subset carries only its names; the rest keep the base's values.
    const SettingValues some = encodeSettings(pathSettings(), {"spp", "halfBuffers"});
    EXPECT_EQ(some, (SettingValues{{"halfBuffers", "true"}, {"spp", "37"}}));
    const Settings back = decodeSettings(some, Settings{});
    EXPECT_EQ(back.spp, 37);
    EXPECT_TRUE(back.halfBuffers);
    EXPECT_EQ(back.maxDepth, Settings{}.maxDepth);
}

TEST(SettingsCodec, SettingsRoundTripThroughSceneJsonsRenderBlock) {
    test::TempDir dir("settings_codec");
    dir.write("quad.obj", test::quadObj());
    for (const Settings& s : {pathSettings(), mltSettings()}) {
        const std::string json = R"({"film": {"width": 4, "height": 4},
            "shapes": [{"obj": "quad.obj"}], "render": )" +
                                 renderBlockJson(s) + "}";
        const Scene scene = loadScene(dir.write("scene.json", json));
        expectSameSettings(scene.settings(), s);
    }
}

TEST(SettingsCodec, SettingsThatChangeThePixelsRoundTripThroughAnExr) {
    test::TempDir dir("settings_codec_exr");
    for (const Settings& s : {pathSettings(), mltSettings()}) {
        FrameBuffers frame(2, 2);
        recordSettings(s, frame.metadata());
        const auto path = dir.path() / "frame.exr";
        writeExr(frame, path);
        const Settings back = recordedSettings(readExr(path).metadata(), Settings{}, path.string());
        expectSameSettings(back, s, recordedNames(s));
    }
    // Neither the texture cache nor the BVH's kind is recorded: shards that differ in them merge.
    const std::vector<std::string> names = recordedNames(pathSettings());
    EXPECT_EQ(std::count(names.begin(), names.end(), "textureCacheMb"), 0);
    EXPECT_EQ(std::count(names.begin(), names.end(), "accel"), 0);
    // The strategy only with mis none, the Metropolis settings only with mlt.
    EXPECT_EQ(std::count(names.begin(), names.end(), "mltChains"), 0);
    const std::vector<std::string> mlt = recordedNames(mltSettings());
    EXPECT_EQ(std::count(mlt.begin(), mlt.end(), "strategy"), 0);
    EXPECT_EQ(std::count(mlt.begin(), mlt.end(), "mltChains"), 1);
}

TEST(SettingsCodec, ARenderRecordsItsSettingsInItsFrame) {
    test::TempDir dir("settings_codec_render");
    dir.write("quad.obj", test::quadObj());
    Settings s;
    s.spp = 2;
    s.maxDepth = 5;
    s.sampler = SamplerKind::Independent;
    s.halfBuffers = true;
    Scene scene = loadScene(dir.write(
        "scene.json", R"({"film": {"width": 4, "height": 4}, "shapes": [{"obj": "quad.obj"}]})"));
    const RenderResult r = Renderer(std::move(scene)).render(s);
    expectSameSettings(recordedSettings(r.frame.metadata()), s, recordedNames(s));
}

TEST(SettingsCodec, ABadValueIsOneErrorNamingTheFileAndPlace) {
    auto refusal = [](const SettingValues& values) {
        try {
            decodeSettings(values, Settings{}, "look.glint-session.json", "/view/");
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format);
            EXPECT_EQ(e.file(), "look.glint-session.json");
            return e.where() + ": " + e.message();
        }
        return std::string();
    };
    EXPECT_EQ(refusal({{"spp", "1e12"}}),
              "/view/spp: expected an integer in [1, 16777216], got \"1e12\"");
    EXPECT_EQ(refusal({{"seed", "-1"}}),
              "/view/seed: expected an integer in [0, 9223372036854775807], got \"-1\"");
    EXPECT_EQ(refusal({{"halfBuffers", "1"}}),
              "/view/halfBuffers: expected true or false, got \"1\"");
    EXPECT_EQ(refusal({{"sampler", "halton"}}),
              "/view/sampler: unknown sampler 'halton' (expected stratified, independent, sobol "
              "or zsobol)");
    EXPECT_NE(refusal({{"mltLarge", "nan"}}), "");
    EXPECT_NE(refusal({{"mltLarge", "0.5 "}}), "");
    EXPECT_NE(refusal({{"maxDepth", ""}}), "");
    // Keys that name no setting belong to the map's other owners.
    EXPECT_EQ(refusal({{"exposure", "2"}, {"halves", "1"}}), "");
}

}  // namespace
}  // namespace glint::render
