// The automatic selection's shortlist (docs/auto.md, "Shortlist").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "auto/stacking.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/metrics.h"
#include "halves_frames.h"
#include "synthetic_frames.h"

#include <tbb/task_arena.h>

namespace glint::denoise {
namespace {

using namespace halves_test;

TEST(AutoShortlist, AShortlistFiltersOnlyItsMembersOnBothHalvesAndChoosesAmongThem) {
    const Image clean = cleanImage(96, 64);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 13);
    const FilterBank bank = gaussianBank(f, {0.3, 0.6, 1.0, 1.5, 2.5, 4.0});
    AutoOptions all, oneSided, two;
    all.tuning["shortlist"] = 0;
    oneSided.tuning["oneSided"] = 1;
    two.tuning["shortlist"] = 2;
    const AutoResult full = autoComposite(bank, f, all);
    const AutoResult first = autoComposite(bank, f, oneSided);
    AutoResult one, twoThreads;
    {
        tbb::task_arena arena(1);
        arena.execute([&] { one = autoComposite(bank, f, two); });
    }
    {
        tbb::task_arena arena(2);
        arena.execute([&] { twoThreads = autoComposite(bank, f, two); });
    }
    // At most the two shortlisted members carry weight, and the best member is one of them.
    ASSERT_GE(one.layers.size(), 1u);
    ASSERT_LE(one.layers.size(), 2u);
    std::vector<int> listed;
    for (std::size_t m = 0; m < bank.size(); ++m) {
        // Shortlisted members have the symmetric estimate (up to float rounding of the two
        // sides' maps), the others keep their one-sided one.
        const double sym = full.estimatedMse[m], single = first.estimatedMse[m];
        if (std::abs(one.estimatedMse[m] - sym) <= 1e-5 * std::abs(sym) &&
            one.estimatedMse[m] != single)
            listed.push_back(int(m));
        else
            EXPECT_EQ(one.estimatedMse[m], single) << "member " << m;
    }
    EXPECT_EQ(listed.size(), 2u);
    for (const AutoLayer& layer : one.layers)
        EXPECT_NE(std::find(listed.begin(), listed.end(), layer.member), listed.end());
    EXPECT_NE(std::find(listed.begin(), listed.end(), one.bestMember), listed.end());
    // Deterministic for any thread count; a shortlist as large as the bank is the full form.
    for (std::size_t i = 0; i < one.composite.data().size(); ++i)
        ASSERT_EQ(one.composite.data()[i], twoThreads.composite.data()[i]);
    AutoOptions everyone;
    everyone.tuning["shortlist"] = int(bank.size());
    EXPECT_EQ(autoComposite(bank, f, everyone).estimatedMse, full.estimatedMse);
    AutoOptions bad;
    bad.tuning["shortlist"] = -1;
    EXPECT_THROW(autoComposite(bank, f, bad), Error);
}

TEST(AutoShortlist, OneSidedTheFinalChoiceIsMadeAgainAmongTheMembersThatWinTheMostPixels) {
    // Fast's form (the halves filtered on A only): the first choice over every member, then the
    // final one among the shortlist's, on the same maps, so a member that wins a few pixels (one
    // that smears a small light into its neighbours, docs/auto.md "Shortlist") is no candidate.
    const Image clean = cleanImage(96, 64);
    const FrameBuffers f = halvesFrame(clean, 0.08, Noise::Skewed, 13);
    const FilterBank bank = gaussianBank(f, {0.3, 0.6, 1.0, 1.5, 2.5, 4.0});
    AutoOptions every, two;
    every.tuning["oneSided"] = 1;
    every.tuning["shortlist"] = 0;
    every.tuning["temperature"] = 0.0;  // a hard choice: the planes count the pixels won
    every.tuning["feather"] = 0;
    two.tuning = every.tuning;
    two.tuning["shortlist"] = 2;
    const AutoResult first = autoComposite(bank, f, every);
    const AutoResult narrowed = autoComposite(bank, f, two);
    ASSERT_GT(first.layers.size(), 2u);  // else the shortlist would change nothing
    // The two members that won the most pixels in the first choice.
    std::vector<std::pair<long, int>> wins;
    for (const AutoLayer& layer : first.layers) {
        long won = 0;
        for (int y = 0; y < first.choice.height(); ++y)
            for (int x = 0; x < first.choice.width(); ++x)
                won += int(first.choice(x, y, 0)) == layer.member;
        wins.emplace_back(-won, layer.member);
    }
    std::sort(wins.begin(), wins.end());
    ASSERT_LE(narrowed.layers.size(), 2u);
    for (const AutoLayer& layer : narrowed.layers)
        EXPECT_TRUE(layer.member == wins[0].second || layer.member == wins[1].second)
            << "member " << layer.member;
    // The same maps: every member's estimate as in the first choice.
    EXPECT_EQ(narrowed.estimatedMse, first.estimatedMse);
}

}  // namespace
}  // namespace glint::denoise
