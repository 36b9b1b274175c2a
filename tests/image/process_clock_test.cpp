// processAgeSeconds: a process's age counts from its start, before main and its static
// constructors, and grows with the clock.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "glint/image/process_clock.h"

namespace glint {
namespace {

using Clock = std::chrono::steady_clock;

// Read while this binary's static constructors run: after the process started.
const Clock::time_point kConstructed = Clock::now();

double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

TEST(ProcessClock, TheAgeCountsFromBeforeMainAndGrowsWithTheClock) {
#if defined(__linux__)
    // Each clock is read before and after the other, so that a preemption anywhere widens the
    // bounds instead of breaking them.
    const double constructedAgo = since(kConstructed);
    const Clock::time_point beforeFirst = Clock::now();
    const std::optional<double> first = processAgeSeconds();
    const Clock::time_point afterFirst = Clock::now();
    ASSERT_TRUE(first.has_value());
    // The start time comes in clock ticks (10 ms on most systems; 1 ms on some): the age is at
    // least the time since the constructors ran, less one tick…
    EXPECT_GE(*first, constructedAgo - 0.011);
    // … and the start is before the constructors by the shared libraries' loading alone (well
    // under a minute, even under a sanitizer), not the system's boot or another process's start.
    EXPECT_LT(*first - since(kConstructed), 60.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    const Clock::time_point beforeSecond = Clock::now();
    const std::optional<double> second = processAgeSeconds();
    const Clock::time_point afterSecond = Clock::now();
    ASSERT_TRUE(second.has_value());
    // The start time is fixed, so the age moves by what the clock moved between the two reads
    // (the boot clock against the steady one: they differ only over a suspend; 1 ms for rounding),
    // whatever the machine's speed.
    const auto seconds = [](Clock::duration d) { return std::chrono::duration<double>(d).count(); };
    EXPECT_GE(*second - *first, seconds(beforeSecond - afterFirst) - 0.001);
    EXPECT_LE(*second - *first, seconds(afterSecond - beforeFirst) + 0.001);
#else
    EXPECT_FALSE(processAgeSeconds().has_value());
#endif
}

}  // namespace
}  // namespace glint
