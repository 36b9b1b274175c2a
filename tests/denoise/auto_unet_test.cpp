// The learned filter unet as a member of the default bank and of auto (docs/auto.md, "The
// learned member"): in the default bank when its weights are present and left out, said once,
// when they are missing or corrupt; one member (its parameters are fixed) that takes no stratum
// of the design and takes the clean-feature weights on prefiltered features; filtered on each half
// by the halves estimator; auto with it bit-identical for one and two threads.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "auto/estimator.h"
#include "auto/halves_estimator.h"
#include "bank/bank_detail.h"
#include "cli_fixture.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/io.h"
#include "halves_frames.h"
#include "synthetic_frames.h"
#include "unet_weights_dir.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using testing::UNetWeightsDir;

bool holdsUNet(const std::vector<const Filter*>& filters) {
    return std::any_of(filters.begin(), filters.end(),
                       [](const Filter* f) { return f->name() == "unet"; });
}

// A folder holding the shipped weights with one byte of `file` flipped.
fs::path corruptWeights(const std::string& file) {
    const fs::path dir = fs::temp_directory_path() /
                         ("glint_unet_bank_corrupt_" + file + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& entry : fs::directory_iterator(testing::shippedUNetWeights()))
        fs::copy_file(entry.path(), dir / entry.path().filename());
    std::fstream f(dir / file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(1000);
    const char c = char(f.get());
    f.seekp(1000);
    f.put(char(c ^ 1));
    return dir;
}

TEST(UNetMember, TheDefaultBankHoldsUNetWhenItsWeightsArePresent) {
    std::vector<LeftOutFilter> leftOut;
    const std::vector<const Filter*> filters = defaultBankFilters(&leftOut);
    EXPECT_TRUE(holdsUNet(filters));
    EXPECT_TRUE(leftOut.empty());
    // nfor and external stay opt-in.
    for (const Filter* f : filters) {
        EXPECT_NE(f->name(), "nfor");
        EXPECT_NE(f->name(), "external");
    }
    // One member: its parameters are fixed, so it is its default only.
    const FrameBuffers frame = testing::syntheticFrame(40, 32);
    BankOptions o;
    o.size = 12;
    o.seed = 3;
    const FilterBank bank = buildBank(frame, o);
    EXPECT_EQ(std::count_if(bank.members().begin(), bank.members().end(),
                            [](const BankMember& m) { return m.filter == "unet"; }),
              1);
}

TEST(UNetMember, TheDefaultBankGoesOnWithoutUNetWhenItsWeightsAreMissingOrCorrupt) {
    const FrameBuffers frame = testing::syntheticFrame(40, 32);
    BankOptions o;
    o.size = 6;
    const fs::path empty =
        fs::temp_directory_path() / ("glint_unet_bank_empty_" + std::to_string(::getpid()));
    fs::remove_all(empty);
    fs::create_directories(empty);
    const fs::path corrupt = corruptWeights("rt_hdr_calb_cnrm.tza");
    struct Case {
        fs::path dir;
        std::string says;
    };
    for (const Case& c : {Case{empty, "rt_hdr_alb_nrm.tza"}, Case{corrupt, "weights corrupt"}}) {
        const UNetWeightsDir scope(c.dir);
        std::vector<LeftOutFilter> leftOut;
        EXPECT_FALSE(holdsUNet(defaultBankFilters(&leftOut))) << c.dir;
        ASSERT_EQ(leftOut.size(), 1u) << c.dir;
        EXPECT_EQ(leftOut[0].name, "unet");
        EXPECT_NE(leftOut[0].reason.find(c.says), std::string::npos) << leftOut[0].reason;
        EXPECT_NE(leftOut[0].reason.find("expected sha256"), std::string::npos);
        EXPECT_EQ(leftOut[0].reason.find('\n'), std::string::npos);
        const FilterBank bank = buildBank(frame, o);
        for (const BankMember& m : bank.members()) EXPECT_NE(m.filter, "unet");
        EXPECT_EQ(bank.size(), defaultBankFilters().size() + 6);
    }
    fs::remove_all(empty);
    fs::remove_all(corrupt);
}

TEST(UNetMember, AReopenedBankFolderGoesOnWithoutUNetWhenItsWeightsWentMissing) {
    const FrameBuffers frame = testing::syntheticFrame(40, 32);
    const fs::path dir =
        fs::temp_directory_path() / ("glint_unet_bank_reopened_" + std::to_string(::getpid()));
    const fs::path empty = dir.string() + "_noweights";
    fs::remove_all(dir);
    fs::remove_all(empty);
    fs::create_directories(dir);
    fs::create_directories(empty);
    // A default bank with a fixed parameter of unet, built while its weights are there.
    BankOptions o;
    o.size = 6;
    o.filterParams["unet"] = {{"quality", 0}};
    o.cacheDir = dir;
    const FilterBank built = buildBank(frame, o);
    ASSERT_EQ(std::count_if(built.members().begin(), built.members().end(),
                            [](const BankMember& m) { return m.filter == "unet"; }),
              1);
    {
        // The weights went missing: the folder's options are still valid, and the bank opens
        // without unet, every other member read from the folder as it was built.
        const UNetWeightsDir scope(empty);
        const BankOptions stored = readBankOptions(dir);
        EXPECT_EQ(stored.filterParams.at("unet").at("quality"), 0.0);
        EXPECT_NO_THROW(validate(stored));
        const FilterBank opened = openBank(frame, dir);
        ASSERT_EQ(opened.size(), built.size() - 1);
        EXPECT_EQ(opened.cacheHits(), opened.size());
        std::size_t j = 0;
        for (std::size_t i = 0; i < built.size(); ++i) {
            if (built.members()[i].filter == "unet") continue;
            EXPECT_EQ(opened.members()[j].filter, built.members()[i].filter) << i;
            EXPECT_EQ(opened.members()[j].params, built.members()[i].params) << i;
            EXPECT_EQ(testing::maxAbsDiff(opened.result(j), built.result(i)), 0.0) << i;
            ++j;
        }
    }
    fs::remove_all(dir);
    fs::remove_all(empty);
}

TEST(UNetMember, ItTakesTheCleanFeatureWeightsOnAPrefilteredFrame) {
    const FrameBuffers frame = testing::syntheticFrame(40, 32, 0.1f);
    const FrameBuffers prefiltered = prefilterFeatures(frame);
    EXPECT_EQ(frame.metadata().extra.count(kFeaturesPrefilteredKey), 0u);
    EXPECT_EQ(prefiltered.metadata().extra.count(kFeaturesPrefilteredKey), 1u);
    const Filter& unet = findFilter("unet");
    const ParamValues noisy{{"aux", 0}}, clean{{"aux", 1}};
    // The default (aux = auto): the clean weights on the prefiltered frame, the noisy ones else.
    const Image autoOnPrefiltered = applyFilter(unet, prefiltered, {});
    EXPECT_EQ(testing::maxAbsDiff(autoOnPrefiltered, applyFilter(unet, prefiltered, clean)), 0.0);
    EXPECT_GT(testing::maxAbsDiff(autoOnPrefiltered, applyFilter(unet, prefiltered, noisy)), 1e-4);
    EXPECT_EQ(testing::maxAbsDiff(applyFilter(unet, frame, {}), applyFilter(unet, frame, noisy)),
              0.0);
}

TEST(UNetMember, AFixedFilterTakesNoStratumSoTheOtherMembersStayAsTheyWere) {
    std::vector<const Filter*> classical, withUNet;
    for (const Filter* f : defaultBankFilters())
        if (f->name() != "unet") classical.push_back(f);
    withUNet = classical;
    withUNet.push_back(&findFilter("unet"));
    const std::vector<BankMember> a = detail::sampleBank(classical, 30, 1);
    const std::vector<BankMember> b = detail::sampleBank(withUNet, 30, 1);
    ASSERT_EQ(b.size(), a.size() + 1);
    // The defaults first (unet's after the others'), then the same sampled members.
    const std::size_t defaults = classical.size();
    for (std::size_t i = 0; i < defaults; ++i) EXPECT_EQ(a[i].params, b[i].params);
    EXPECT_EQ(b[defaults].filter, "unet");
    EXPECT_TRUE(b[defaults].isDefault);
    for (std::size_t i = defaults; i < a.size(); ++i) {
        EXPECT_EQ(a[i].filter, b[i + 1].filter) << i;
        EXPECT_EQ(a[i].params, b[i + 1].params) << i;
    }
}

// A bank of unet and two Gaussians over a frame with half buffers.
FilterBank unetBank(const FrameBuffers& f) {
    BankOptions o;
    o.filters = {"gaussian", "unet"};
    o.size = 2;
    o.seed = 4;
    return buildBank(f, o);
}

std::size_t unetIndex(const FilterBank& bank) {
    for (std::size_t i = 0; i < bank.size(); ++i)
        if (bank.members()[i].filter == "unet") return i;
    ADD_FAILURE() << "no unet member";
    return 0;
}

TEST(UNetMember, TheHalvesEstimatorFiltersItOnEachHalf) {
    using namespace halves_test;
    const FrameBuffers f = halvesFrame(cleanImage(64, 48), 0.08, Noise::Gaussian, 21);
    const FilterBank bank = unetBank(f);
    const std::size_t u = unetIndex(bank);
    AutoOptions o;
    o.estimator = AutoEstimator::Halves;
    o.tuning["space"] = 3;  // linear: the plain cross-validation map
    o.tuning["shortlist"] = 0;
    o.tuning["stack"] = 0;
    const AutoResult r = autoComposite(bank, f, o);
    // The same estimate by hand: unet on A and on B, each compared with the other half.
    const auto [a, b] = splitHalves(f);
    const Rect region{0, 64, 0, 48};
    const Filter& unet = findFilter("unet");
    const Image onA = applyFilter(unet, a, {}), onB = applyFilter(unet, b, {});
    const double byHand =
        detail::meanPerChannel(detail::crossValidationMap(a.color(), b.color(), onA, &onB, region));
    EXPECT_DOUBLE_EQ(r.estimatedMse[u], byHand);
    // With the bank's result on all the samples in place of the halves' it would differ.
    const double fromTheBank = detail::meanPerChannel(
        detail::crossValidationMap(a.color(), b.color(), bank.result(u), &bank.result(u), region));
    EXPECT_GT(std::fabs(fromTheBank - byHand), 0.05 * std::fabs(byHand));
}

TEST(UNetMember, AutoWithItGivesTheSameBitsOnOneAndTwoThreads) {
    using namespace halves_test;
    const FrameBuffers f = halvesFrame(cleanImage(64, 48), 0.08, Noise::Skewed, 22);
    const std::size_t u = unetIndex(unetBank(f));
    for (const auto estimator : {AutoEstimator::Halves, AutoEstimator::Sure}) {
        AutoOptions o;
        o.estimator = estimator;
        AutoResult one, two;
        for (int threads : {1, 2}) {
            tbb::task_arena arena(threads);
            arena.execute([&] {
                const FilterBank bank = unetBank(f);
                (threads == 1 ? one : two) = autoComposite(bank, f, o);
            });
        }
        ASSERT_EQ(one.composite.data().size(), two.composite.data().size());
        EXPECT_TRUE(std::equal(one.composite.data().begin(), one.composite.data().end(),
                               two.composite.data().begin()));
        EXPECT_EQ(one.estimatedMse, two.estimatedMse);
        // SURE estimates unet's divergence by Monte Carlo (it gives none).
        EXPECT_FALSE(one.analytic[u]);
    }
}

class UNetMemberCli : public glint::testing::CliFixture {
  protected:
    UNetMemberCli() : CliFixture("glint-denoise") {}
};

TEST_F(UNetMemberCli, WithoutWeightsBankAndAutoSayOnceThatTheyGoOnWithoutIt) {
    writeExr(testing::syntheticFrame(40, 32, 0.1f), m_dir / "noisy.exr");
    fs::create_directories(m_dir / "noweights");
    const std::string env = "GLINT_UNET_WEIGHTS_DIR=" + path("noweights");
    for (const std::string& cmd :
         {"bank " + path("noisy.exr") + " --out " + path("bank") + " --size 4 --json",
          "auto " + path("noisy.exr") + " --out " + path("a.exr") + " --size 4 --json"}) {
        const glint::testing::RunResult r = runEither(env, cmd);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const std::string says = "goes on without 'unet'";
        const auto first = r.err.find(says);
        ASSERT_NE(first, std::string::npos) << r.err;
        EXPECT_EQ(r.err.find(says, first + 1), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("rt_hdr_alb_nrm.tza"), std::string::npos) << r.err;
        const nlohmann::json j = nlohmann::json::parse(r.out);
        ASSERT_EQ(j["leftOut"].size(), 1u);
        EXPECT_EQ(j["leftOut"][0]["filter"], "unet");
    }
    // Named, it is refused: one line naming the file and the expected digest, exit 2.
    const glint::testing::RunResult r =
        run(env, "apply " + path("noisy.exr") + " --filter unet" + " --out " + path("u.exr"));
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("rt_hdr_alb_nrm.tza"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("expected sha256 e586ef2f"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("u.exr")));
}

TEST_F(UNetMemberCli, ABankFolderReopenedWithoutWeightsSaysOnceThatItGoesOnWithoutIt) {
    writeExr(testing::syntheticFrame(40, 32, 0.1f), m_dir / "noisy.exr");
    fs::create_directories(m_dir / "noweights");
    // Two folders made while the weights are there: the default bank, and the default bank
    // with a fixed parameter of unet (its small weights).
    for (const std::string& extra :
         {std::string(), std::string(" --filter-param unet.quality=fast")}) {
        const std::string bank = path(extra.empty() ? "bank" : "bankfast");
        const glint::testing::RunResult built =
            run("bank " + path("noisy.exr") + " --out " + bank + " --size 4" + extra);
        ASSERT_EQ(built.exitCode, 0) << built.err;
        // Reopened after the weights went missing: exit 0, one line, and leftOut.
        const std::string env = "GLINT_UNET_WEIGHTS_DIR=" + path("noweights");
        for (const std::string& cmd : {"auto " + path("noisy.exr") + " --bank " + bank + " --out " +
                                           path("a.exr") + " --json",
                                       "oracle " + path("noisy.exr") + " --bank " + bank +
                                           " --reference " + path("noisy.exr") + " --json"}) {
            const glint::testing::RunResult r = runEither(env, cmd);
            ASSERT_EQ(r.exitCode, 0) << cmd << "\n" << r.err;
            const std::string says = "goes on without 'unet'";
            const auto first = r.err.find(says);
            ASSERT_NE(first, std::string::npos) << cmd << "\n" << r.err;
            EXPECT_EQ(r.err.find(says, first + 1), std::string::npos) << r.err;
            EXPECT_NE(r.err.find("rt_hdr_alb_nrm.tza"), std::string::npos) << r.err;
            const nlohmann::json j = nlohmann::json::parse(r.out);
            ASSERT_EQ(j["leftOut"].size(), 1u) << cmd;
            EXPECT_EQ(j["leftOut"][0]["filter"], "unet");
            EXPECT_EQ(j.count("unavailable"), 0u) << cmd;
        }
    }
}

}  // namespace
}  // namespace glint::denoise
