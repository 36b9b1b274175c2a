// The time limit's schedule (glint/pipeline/time_budget.h): the render stops when the time left
// is the final auto's reserve, the refreshes stay within their share and leave the reserve, and
// a loop run on a fake clock by the schedule uses its budget and ends, the final auto included,
// within the limit whenever that auto takes at most the margin over its measure.
#include <algorithm>

#include <gtest/gtest.h>

#include "glint/pipeline/time_budget.h"

namespace glint::pipeline {
namespace {

TEST(TimeBudget, TheRenderStopsWhenTheTimeLeftIsTheFinalAutosReserve) {
    TimeBudget b(10.0, 0.2, 2.0);
    EXPECT_DOUBLE_EQ(b.reserve(), kFinalAutoMargin * 2.0);
    EXPECT_TRUE(b.renderMayContinue(10.0 - b.reserve() - 0.01));
    EXPECT_FALSE(b.renderMayContinue(10.0 - b.reserve()));
    // A refresh at the final quality measures the final auto: the reserve follows it; one at
    // another quality does not move it.
    b.refreshed(1.0, true);
    EXPECT_DOUBLE_EQ(b.reserve(), kFinalAutoMargin * 1.0);
    b.refreshed(0.2, false);
    EXPECT_DOUBLE_EQ(b.reserve(), kFinalAutoMargin * 1.0);
    EXPECT_DOUBLE_EQ(b.refreshSeconds(), 1.2);
    // No time limit: nothing stops the render, every refresh fits.
    const TimeBudget none(0.0, 0.2, 5.0);
    EXPECT_TRUE(none.renderMayContinue(1e9));
    EXPECT_TRUE(none.refreshFits(1e9, 1e9));
}

TEST(TimeBudget, RefreshesStayWithinTheirShareAndLeaveTheReserve) {
    TimeBudget b(10.0, 0.2, 0.5);  // 2 s of refreshes at most
    EXPECT_TRUE(b.refreshFits(0.0, 0.5));
    b.refreshed(0.5, true);
    b.refreshed(0.5, false);
    b.refreshed(0.5, false);
    EXPECT_TRUE(b.refreshFits(1.0, 0.5));   // 2.0 of 2.0
    EXPECT_FALSE(b.refreshFits(1.0, 0.6));  // 2.1 of 2.0
    // Near the end a refresh that fits the share still must leave the final auto's reserve.
    const TimeBudget late(10.0, 1.0, 1.0);
    EXPECT_TRUE(late.refreshFits(8.0, 0.7));   // 8 + 0.7 + 1.25 < 10
    EXPECT_FALSE(late.refreshFits(8.0, 0.8));  // 8 + 0.8 + 1.25 ≥ 10
}

TEST(TimeBudget, ALoopOnAFakeClockUsesItsBudgetAndEndsWithinTheLimit) {
    // A loop as renderFinal runs it: steps of `step` seconds (a tile), a refresh due every 40
    // steps costing `refresh` (the first at the final quality costs `final`), then the final
    // auto, which takes up to kFinalAutoMargin times its measure. For every combination the
    // whole ends within the limit plus one step, after using all but the reserve and a step.
    const double limit = 30.0;
    for (double step : {0.01, 0.1})
        for (double final : {0.5, 2.0, 5.0})
            for (double share : {0.1, 0.3})
                for (double slower : {1.0, kFinalAutoMargin}) {
                    const double refresh = final / 3.0;
                    TimeBudget b(limit, share, 0.0);
                    double t = 0.0;
                    int steps = 0;
                    bool first = true;
                    while (b.renderMayContinue(t)) {
                        t += step;
                        if (++steps % 40 != 0) continue;
                        const double cost = first ? final : refresh;
                        if (!b.refreshFits(t, first ? b.expectedFinal() : refresh)) continue;
                        t += cost;
                        b.refreshed(cost, first);
                        first = false;
                    }
                    const double renderEnd = t;
                    t += slower * b.expectedFinal();
                    const std::string what = "step " + std::to_string(step) + ", final " +
                                             std::to_string(final) + ", share " +
                                             std::to_string(share);
                    EXPECT_LE(t, limit + step) << what;
                    EXPECT_GE(renderEnd, limit - b.reserve() - step) << what;
                    // The refreshes after the first (whose cost was unknown) keep the share.
                    EXPECT_LE(b.refreshSeconds() - final, std::max(share * limit - final, 0.0))
                        << what;
                }
}

}  // namespace
}  // namespace glint::pipeline
