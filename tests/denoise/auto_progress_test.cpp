// Progress and cancellation of the automatic selection through all its stages (docs/auto.md,
// "Stages"): after the members' filtering, the choice, feathering, blend and stacking still
// report progress and stop once the callback says so.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <functional>
#include <mutex>
#include <vector>

#include "auto/blend.h"
#include "auto/choice.h"
#include "auto/estimator.h"
#include "auto/feathering.h"
#include "auto/options.h"
#include "auto/stacking.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"
#include "halves_frames.h"

namespace glint::denoise {
namespace {

using namespace halves_test;

// A frame with half buffers, a four-member bank and options under which every stage runs: the
// halves on both sides (four members: no shortlist), soft weights, a finer window, feathering
// and stacking (of the members only: the frame has no features).
struct Case {
    FrameBuffers frame;
    FilterBank bank;
    AutoOptions options;
};

Case everyStage() {
    FrameBuffers f = halvesFrame(cleanImage(96, 64), 0.08, Noise::Skewed, 3);
    FilterBank bank = gaussianBank(f, {0.5, 1.0, 2.0, 4.0});
    AutoOptions o;
    o.estimator = AutoEstimator::Halves;
    o.tuning["feather"] = 3;
    o.tuning["stack"] = 2;
    return {std::move(f), std::move(bank), o};
}

void expectCancelled(const std::function<void()>& run) {
    try {
        run();
        FAIL() << "not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled) << e.what();
    }
}

TEST(AutoProgress, ReportsThroughTheStagesAfterTheMembersFiltering) {
    Case c = everyStage();
    std::mutex mutex;
    std::vector<double> fractions;
    c.options.progress = [&](double f) {
        const std::lock_guard<std::mutex> lock(mutex);
        fractions.push_back(f);
        return true;
    };
    // One thread: a report is skipped while another thread is inside the callback (WorkContext
    // never waits for it), so with more threads the count below depends on the scheduler (it
    // fell to 17 under ASan on a loaded machine).
    tbb::task_arena oneThread(1);
    AutoResult r;
    oneThread.execute([&] { r = autoComposite(c.bank, c.frame, c.options); });
    EXPECT_GT(r.stacked, 0);
    ASSERT_FALSE(fractions.empty());
    EXPECT_EQ(fractions.front(), 0.0);
    EXPECT_EQ(fractions.back(), 1.0);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
    // Filtering the four members on both halves is under half of the work counted here (the
    // median, four members' filtering, then the noise, the choice at two radii, the
    // feathering, the blend and the stacking): the later stages report the rest, where the
    // members' count alone (as before) reported nothing between the last member and the end.
    const auto later = std::count_if(fractions.begin(), fractions.end(),
                                     [](double f) { return f > 0.6 && f < 1.0; });
    EXPECT_GE(later, 20);
}

TEST(AutoProgress, CancellingInTheLaterStagesStopsThem) {
    Case c = everyStage();
    std::mutex mutex;
    bool stopped = false;
    double stoppedAt = 0.0;
    int callsAfter = 0;
    c.options.progress = [&](double f) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (stopped) {
            ++callsAfter;
            return false;
        }
        if (f > 0.6) {
            stopped = true;
            stoppedAt = f;
            return false;
        }
        return true;
    };
    expectCancelled([&] { autoComposite(c.bank, c.frame, c.options); });
    EXPECT_TRUE(stopped);
    EXPECT_LT(stoppedAt, 1.0);
    EXPECT_EQ(callsAfter, 0);  // nothing more is reported once stopped
}

TEST(AutoProgress, EachLaterStageStopsAtItsFirstReportWhenTheCallbackSaysStop) {
    const Case c = everyStage();
    const int w = c.frame.width(), h = c.frame.height();
    // A context whose callback stops the work at its first report, inside the stage's first loop.
    const auto stopping = [] { return ProgressFn([](double) { return false; }); };
    // Two members sharing every pixel.
    std::vector<Image> planes(c.bank.size());
    for (std::size_t m = 0; m < 2; ++m) {
        planes[m] = Image(w, h, 1);
        for (float& v : planes[m].data()) v = 0.5f;
    }
    const std::vector<std::size_t> used{0, 1};
    const std::vector<const Image*> results{&c.bank.result(0), &c.bank.result(1)};
    {
        WorkContext work(stopping());
        std::vector<Image> p = planes, feathered{planes[0], planes[1]};
        expectCancelled([&] {
            detail::featherRows(p, used, feathered, results, 0, h, 0.2, 0.0f, work);
            work.throwIfCancelled();
        });
    }
    {
        WorkContext work(stopping());
        Image out(w, h, 3);
        expectCancelled([&] {
            detail::blendRows(planes, used, results, 0, h, out, nullptr, work);
            work.throwIfCancelled();
        });
    }
    {
        detail::Estimates estimates;
        for (std::size_t m = 0; m < c.bank.size(); ++m) {
            Image map(w, h, 1);
            for (std::size_t p = 0; p < map.data().size(); ++p)
                map.data()[p] = float((p * (m + 3)) % 17) * 0.01f;
            estimates.mapMean.push_back(detail::meanPerChannel(map));
            estimates.maps.push_back(std::move(map));
        }
        detail::AutoSettings settings;
        settings.window = 4;
        settings.confidence = 1.0;
        WorkContext work(stopping());
        expectCancelled([&] {
            detail::choose(estimates, {0, 1, 2, 3}, true, settings, Image{}, work);
        });
    }
    {
        const Image& a = c.bank.result(0);
        const Image& b = c.bank.result(1);
        WorkContext work(stopping());
        expectCancelled([&] {
            detail::stackComposite(a, a, a, {{&b, &b, &b}}, a, b, Image{}, 4, 0.5, 0.1, 4, &work);
        });
    }
}

}  // namespace
}  // namespace glint::denoise
