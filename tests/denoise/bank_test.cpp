// The filter bank: Latin-hypercube design, parameter mapping, members, parallel build, region
// builds, the disk cache (hits, invalidation, damaged entries), bad options, cancellation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include <unistd.h>

#include "bank/bank_cache.h"
#include "bank/bank_detail.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;

class TempFolder {
  public:
    TempFolder() {
        static int counter = 0;
        m_path = fs::temp_directory_path() /
                 ("glint_bank_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(m_path);
    }
    ~TempFolder() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    const fs::path& path() const { return m_path; }

  private:
    fs::path m_path;
};

TEST(LatinHypercube, ExactlyOnePointPerStratumInEveryDimension) {
    for (int n : {1, 7, 64, 100}) {
        const auto points = detail::latinHypercube(n, 5, 42);
        ASSERT_EQ(points.size(), std::size_t(n));
        for (int d = 0; d < 5; ++d) {
            std::vector<int> count(std::size_t(n), 0);
            for (const auto& p : points) {
                ASSERT_GE(p[std::size_t(d)], 0.0);
                ASSERT_LT(p[std::size_t(d)], 1.0);
                ++count[std::size_t(p[std::size_t(d)] * n)];
            }
            for (int c : count) EXPECT_EQ(c, 1) << "n " << n << " dim " << d;
        }
    }
    EXPECT_EQ(detail::latinHypercube(16, 3, 1), detail::latinHypercube(16, 3, 1));
    EXPECT_NE(detail::latinHypercube(16, 3, 1), detail::latinHypercube(16, 3, 2));
}

TEST(MapParam, LinearLogIntegerAndChoice) {
    ParamSpec lin("a", "a", 0, 100, 1, ParamScale::Linear, false, "");
    lin = lin.soft(10, 20);
    EXPECT_DOUBLE_EQ(detail::mapParam(lin, 0.0), 10.0);
    EXPECT_DOUBLE_EQ(detail::mapParam(lin, 0.5), 15.0);
    EXPECT_DOUBLE_EQ(detail::mapParam(lin, 1.0), 20.0);
    const ParamSpec lg =
        ParamSpec("b", "b", 1e-6, 1e6, 1, ParamScale::Log, false, "").soft(0.01, 100);
    EXPECT_NEAR(detail::mapParam(lg, 0.0), 0.01, 1e-12);
    EXPECT_NEAR(detail::mapParam(lg, 0.5), 1.0, 1e-12);  // the geometric middle
    EXPECT_NEAR(detail::mapParam(lg, 0.75), 10.0, 1e-9);
    // Integers: each of the n values gets 1/n of [0, 1].
    const ParamSpec in = ParamSpec("c", "c", 0, 10, 3, ParamScale::Linear, true, "").soft(1, 4);
    std::vector<int> hits(5, 0);
    for (int i = 0; i < 400; ++i) ++hits[std::size_t(detail::mapParam(in, (i + 0.5) / 400.0))];
    EXPECT_EQ(hits[0], 0);
    for (int v = 1; v <= 4; ++v) EXPECT_EQ(hits[std::size_t(v)], 100) << v;
    const ParamSpec ch = ParamSpec::choice("d", "d", {"x", "y", "z"}, 0, "");
    EXPECT_EQ(detail::mapParam(ch, 0.1), 0.0);
    EXPECT_EQ(detail::mapParam(ch, 0.5), 1.0);
    EXPECT_EQ(detail::mapParam(ch, 0.99), 2.0);
    // A collapsed soft range keeps the value.
    const ParamSpec fixed = ParamSpec("e", "e", 0, 100, 0, ParamScale::Linear, true, "").soft(0, 0);
    EXPECT_EQ(detail::mapParam(fixed, 0.7), 0.0);
}

// True when some parameter of `f` has a soft range to explore.
bool explorable(const Filter& f) {
    return std::any_of(f.params().begin(), f.params().end(),
                       [](const ParamSpec& s) { return s.softMin != s.softMax; });
}

TEST(SampleBank, AFilterWhoseParametersAreAllFixedIsItsDefaultOnly) {
    const Filter& fixed = findFilter("external");  // its command is a fixed parameter
    ASSERT_FALSE(explorable(fixed));
    const Filter& open = findFilter("gaussian");
    const std::vector<BankMember> members = detail::sampleBank({&open, &fixed}, 40, 3);
    const auto fixedMembers = std::count_if(
        members.begin(), members.end(), [](const BankMember& m) { return m.filter == "external"; });
    EXPECT_EQ(fixedMembers, 1);
    EXPECT_TRUE(members[1].isDefault);
    EXPECT_EQ(members[1].filter, "external");
    // It takes no stratum of the design: gaussian takes them all (and the sampled members of a
    // bank stay as they were when a fixed filter joins it:
    // UNetMember.AFixedFilterTakesNoStratumSoTheOtherMembersStayAsTheyWere).
    const auto gaussians = std::count_if(
        members.begin(), members.end(), [](const BankMember& m) { return m.filter == "gaussian"; });
    EXPECT_EQ(gaussians, 1 + 40);
}

TEST(SampleBank, DefaultsFirstThenValidMembersOfEveryFilter) {
    // The runnable filters with a parameter to explore (one whose parameters are all fixed is its
    // default member only: SampleBank.AFilterWhoseParametersAreAllFixedIsItsDefaultOnly).
    std::vector<const Filter*> filters;
    for (const Filter* f : testing::runnableFilters())
        if (explorable(*f)) filters.push_back(f);
    const int perFilter = 10;
    const int size = perFilter * int(filters.size());
    const std::vector<BankMember> members = detail::sampleBank(filters, size, 3);
    ASSERT_EQ(members.size(), filters.size() + std::size_t(size));
    std::set<std::string> seen;
    for (std::size_t i = 0; i < members.size(); ++i) {
        const Filter& f = findFilter(members[i].filter);
        EXPECT_EQ(members[i].isDefault, i < filters.size());
        if (i < filters.size()) {
            EXPECT_EQ(members[i].params, resolveParams(f, {}));
        }
        EXPECT_NO_THROW(resolveParams(f, members[i].params));
        // Every explored value lies in the soft range.
        for (const ParamSpec& s : f.params()) {
            const double v = members[i].params.at(s.name);
            if (!members[i].isDefault) {
                EXPECT_GE(v, s.softMin) << s.name;
                EXPECT_LE(v, s.softMax) << s.name;
            }
        }
        if (!members[i].isDefault) seen.insert(members[i].filter);
    }
    // The filter dimension is stratified: 10 members per filter gives each exactly 10.
    EXPECT_EQ(seen.size(), filters.size());
    for (const Filter* f : filters) {
        int count = 0;
        for (std::size_t i = filters.size(); i < members.size(); ++i)
            count += members[i].filter == f->name();
        EXPECT_EQ(count, perFilter) << f->name();
    }
}

BankOptions smallBank(int size = 8) {
    BankOptions o;
    o.size = size;
    o.seed = 5;
    return o;
}

TEST(Bank, MembersEqualTheirFiltersAndTheBuildIsDeterministic) {
    const FrameBuffers frame = testing::syntheticFrame(48, 40);
    const FilterBank bank = buildBank(frame, smallBank());
    ASSERT_EQ(bank.size(), defaultBankFilters().size() + 8);
    EXPECT_EQ(bank.region(), (Rect{0, 48, 0, 40}));
    for (std::size_t i = 0; i < bank.size(); ++i) {
        const BankMember& m = bank.members()[i];
        const Image direct = applyFilter(findFilter(m.filter), frame, m.params);
        EXPECT_EQ(testing::maxAbsDiff(bank.result(i), direct), 0.0) << m.filter;
    }
    const FilterBank again = buildBank(frame, smallBank());
    for (std::size_t i = 0; i < bank.size(); ++i)
        EXPECT_EQ(testing::maxAbsDiff(bank.result(i), again.result(i)), 0.0);
}

TEST(Bank, ARegionBankEqualsTheCropOfTheFullBank) {
    const FrameBuffers frame = testing::syntheticFrame(64, 48);
    const FilterBank full = buildBank(frame, smallBank());
    BankOptions o = smallBank();
    o.region = Rect{10, 40, 8, 30};
    const FilterBank part = buildBank(frame, o);
    ASSERT_EQ(part.size(), full.size());
    for (std::size_t i = 0; i < part.size(); ++i) {
        ASSERT_EQ(part.result(i).width(), 30);
        EXPECT_LT(testing::maxAbsDiff(part.result(i), full.result(i).crop(Rect{10, 40, 8, 30})),
                  1e-5)
            << part.members()[i].filter;
    }
}

TEST(Bank, FiltersWhoseLayersAreMissingAreLeftOut) {
    FrameBuffers bare(32, 32);
    bare.color() = testing::syntheticFrame(32, 32).color();
    const FilterBank bank = buildBank(bare, smallBank(30));
    for (const BankMember& m : bank.members()) {
        EXPECT_NE(m.filter, "cross-bilateral");
        if (m.filter == "guided") {
            EXPECT_EQ(m.params.at("guide"), 0.0);
        }
    }
    BankOptions only = smallBank();
    only.filters = {"cross-bilateral"};
    EXPECT_THROW(buildBank(bare, only), Error);
}

TEST(BankCache, ReopeningIsACacheHitAndAChangedInputIsNot) {
    TempFolder dir;
    const FrameBuffers frame = testing::syntheticFrame(40, 32);
    BankOptions o = smallBank();
    o.cacheDir = dir.path();
    fs::create_directories(dir.path());
    const FilterBank first = buildBank(frame, o);
    EXPECT_EQ(first.cacheHits(), 0u);
    EXPECT_TRUE(fs::exists(dir.path() / "index.json"));
    const FilterBank second = buildBank(frame, o);
    EXPECT_EQ(second.cacheHits(), second.size());
    for (std::size_t i = 0; i < first.size(); ++i)
        EXPECT_EQ(testing::maxAbsDiff(first.result(i), second.result(i)), 0.0);
    // openBank reads the options from the folder.
    const FilterBank opened = openBank(frame, dir.path());
    EXPECT_EQ(opened.cacheHits(), opened.size());
    EXPECT_EQ(opened.members().size(), first.members().size());

    // One changed pixel: a new input, nothing reused, and openBank refuses the folder's bank.
    FrameBuffers changed = frame;
    changed.color()(3, 3, 1) += 0.25f;
    EXPECT_NE(hashFrame(changed), hashFrame(frame));
    try {
        openBank(changed, dir.path());
        ADD_FAILURE() << "a bank of another image was opened";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format);
        EXPECT_NE(std::string(e.what()).find("another image"), std::string::npos) << e.what();
    }
    const FilterBank rebuilt = buildBank(changed, o);
    EXPECT_EQ(rebuilt.cacheHits(), 0u);
    // The old members' files are gone: the folder holds one bank.
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir.path()))
        files += entry.path().extension() == ".exr";
    EXPECT_EQ(files, int(rebuilt.size()));
}

TEST(BankCache, AChangedFilterVersionOrParameterChangesTheKey) {
    const ParamValues p{{"sigma", 2.0}};
    const Rect r{0, 8, 0, 8};
    const std::uint64_t k1 = detail::memberKey(7, "gaussian", "1", p, "raw", r);
    EXPECT_EQ(k1, detail::memberKey(7, "gaussian", "1", p, "raw", r));
    EXPECT_NE(k1, detail::memberKey(7, "gaussian", "2", p, "raw", r));
    EXPECT_NE(k1, detail::memberKey(8, "gaussian", "1", p, "raw", r));
    EXPECT_NE(k1, detail::memberKey(7, "gaussian", "1", {{"sigma", 2.0000001}}, "raw", r));
    EXPECT_NE(k1, detail::memberKey(7, "gaussian", "1", p, "prefilter", r));
    EXPECT_NE(k1, detail::memberKey(7, "gaussian", "1", p, "raw", Rect{0, 8, 0, 9}));
}

TEST(BankCache, ADamagedEntryIsRecomputedNeverTrusted) {
    TempFolder dir;
    const FrameBuffers frame = testing::syntheticFrame(40, 32);
    BankOptions o = smallBank();
    o.cacheDir = dir.path();
    fs::create_directories(dir.path());
    const FilterBank first = buildBank(frame, o);
    // Truncate one member file and flip a pixel of another (its checksum no longer matches).
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir.path()))
        if (entry.path().extension() == ".exr") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    ASSERT_GE(files.size(), 2u);
    fs::resize_file(files[0], fs::file_size(files[0]) / 2);
    {
        FrameBuffers f = readExr(files[1]);
        f.color()(0, 0, 0) += 1.0f;
        writeExr(f, files[1]);
    }
    const FilterBank second = buildBank(frame, o);
    EXPECT_EQ(second.cacheHits(), second.size() - 2);
    for (std::size_t i = 0; i < first.size(); ++i)
        EXPECT_EQ(testing::maxAbsDiff(first.result(i), second.result(i)), 0.0);
    // A damaged index is ignored: everything is recomputed.
    std::ofstream(dir.path() / "index.json") << "{ \"format\": 1, \"members\": [";
    EXPECT_EQ(buildBank(frame, o).cacheHits(), 0u);
}

TEST(Bank, BadOptionsAreRefusedNamingTheOption) {
    const FrameBuffers frame = testing::syntheticFrame(16, 16);
    struct Case {
        BankOptions options;
        std::string mention;
    };
    std::vector<Case> cases;
    BankOptions o = smallBank();
    o.size = 0;
    cases.push_back({o, "--size"});
    o.size = 4097;
    cases.push_back({o, "--size"});
    o = smallBank();
    o.filters = {"gausian"};
    cases.push_back({o, "bilateral-mc"});
    o = smallBank();
    o.region = Rect{10, 20, 0, 4};
    cases.push_back({o, "outside"});
    o.region = Rect{4, 4, 0, 4};
    cases.push_back({o, "empty"});
    for (const Case& c : cases) {
        try {
            buildBank(frame, c.options);
            ADD_FAILURE() << c.mention;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(c.mention), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(readBankOptions("/nonexistent/bank"), Error);
}

TEST(Bank, ProgressCountsMembersAndCanStopTheBuild) {
    const FrameBuffers frame = testing::syntheticFrame(64, 64);
    std::vector<double> seen;
    BankOptions o = smallBank();
    o.progress = [&](double f) {
        seen.push_back(f);
        return true;
    };
    const FilterBank bank = buildBank(frame, o);
    ASSERT_EQ(seen.size(), bank.size() + 1);  // 0, then once per member
    EXPECT_EQ(seen.front(), 0.0);
    EXPECT_EQ(seen.back(), 1.0);
    int calls = 0;
    o.progress = [&](double) { return ++calls < 3; };
    try {
        buildBank(frame, o);
        ADD_FAILURE() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled);
    }
}

TEST(Bank, ABankBiggerThanTheBudgetIsRefusedBeforeAnyMemberIsComputed) {
    // 4096 members (plus defaults) over 256×256: 4096 × 768 KiB ≈ 3 GiB of results, refused
    // under a 1 GiB budget without computing a member (progress is never asked).
    const FrameBuffers frame = testing::syntheticFrame(256, 256);
    BankOptions o;
    o.size = kMaxBankSize;
    o.memoryLimit = std::uint64_t(1) << 30;
    const std::uint64_t estimate = estimateMemory(frame, o);
    EXPECT_GT(estimate, std::uint64_t(kMaxBankSize) * 256 * 256 * 12);
    EXPECT_LT(estimate,
              std::uint64_t(kMaxBankSize + 64) * 256 * 256 * 12 + (std::uint64_t(1) << 30));
    bool progressed = false;
    o.progress = [&](double) { return progressed = true; };
    try {
        buildBank(frame, o);
        ADD_FAILURE() << "a 3 GiB bank fit in 1 GiB";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_NE(e.message().find("members over 256x256"), std::string::npos) << e.what();
        EXPECT_NE(e.message().find("memory limit"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(progressed);
    // A region bank needs only the region's results.
    o.region = Rect{0, 16, 0, 16};
    EXPECT_LT(estimateMemory(frame, o), estimate / 16);
}

}  // namespace
}  // namespace glint::denoise
