// The final render's loop (glint/pipeline/final_render.h): it stops at the error target with the
// frame auto last saw, the denoiser-steered loop gives the same bits on 1 and 2 threads, the
// output holds the denoised colour and the render's layers, the steering maps follow auto's
// error, and bad options are refused naming the option.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glint/denoise/denoised_frame.h"
#include "glint/image/error.h"
#include "glint/pipeline/final_render.h"
#include "glint/pipeline/steering.h"
#include "glint/pipeline/time_budget.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::pipeline {
namespace {

/// The Cornell box, side × side (24: every pixel noisy), maxDepth 4.
render::Scene cornell(int side = 24) {
    const std::string obj = std::string(GLINT_RENDER_TEST_DATA) + "/cornell_box.obj";
    return render::parseScene(R"({
      "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
      "film": {"width": )" + std::to_string(side) +
                                  R"(, "height": )" + std::to_string(side) + R"(},
      "shapes": [{"obj": ")" + obj +
                                  R"("}],
      "render": {"spp": 8, "maxDepth": 4}
    })",
                              std::string(GLINT_RENDER_TEST_DATA) + "/scene.json");
}

/// Adaptive from 8 spp up to 128, a threshold no pixel reaches at first, auto's fast quality.
FinalOptions smallOptions() {
    FinalOptions o;
    o.settings.spp = 128;
    o.settings.seed = 5;
    o.settings.maxDepth = 4;
    o.settings.threads = 2;
    o.settings.tileSize = 8;
    o.settings.adaptive = true;
    o.settings.minSpp = 8;
    o.settings.noiseThreshold = 0.002;
    o.quality = denoise::AutoQuality::Fast;
    return o;
}

/// smallOptions for a limit (no spp) with the balanced final auto, steered by the variance alone
/// (it runs no refresh, whose time on a fake clock would recalibrate auto's cost).
FinalOptions balancedUnderALimit() {
    FinalOptions o = smallOptions();
    o.steering = Steering::Variance;
    o.quality = denoise::AutoQuality::Balanced;
    o.settings.spp = 0;
    return o;
}

double meanSampleCount(const FrameBuffers& f) {
    double sum = 0.0;
    for (float n : f.layer(Layer::SampleCount).data()) sum += n;
    return sum / double(f.width() * f.height());
}

TEST(FinalRender, StopsAtTheErrorTargetWithTheFrameOfThatRefresh) {
    // Without a target the loop refreshes at 8, 16, 32 … spp a pixel; the estimate after the
    // second refresh, as the target, stops the loop at that refresh: fewer samples, the target
    // met, and the same denoised image as that refresh gave.
    render::Renderer renderer(cornell());
    std::vector<std::string> lines;
    FinalOptions o = smallOptions();
    o.log = [&](const std::string& line) { lines.push_back(line); };
    const FinalResult full = renderFinal(renderer, o);
    ASSERT_GE(full.refreshes, 2);
    EXPECT_FALSE(full.targetReached);

    // The second refresh's estimate, from its log line.
    const std::string& second = lines[1];
    const std::size_t at = second.find("relMSE ");
    ASSERT_NE(at, std::string::npos) << second;
    // Printed to 4 digits: a hair above it.
    const double target = std::stod(second.substr(at + 7)) * 1.001;
    o.targetError = target;
    const FinalResult stopped = renderFinal(renderer, o);
    EXPECT_TRUE(stopped.targetReached);
    EXPECT_EQ(stopped.refreshes, 2);
    EXPECT_LE(stopped.estimatedRelMse, target);
    EXPECT_LT(meanSampleCount(stopped.frame), meanSampleCount(full.frame));
    EXPECT_EQ(stopped.frame.metadata().extra.count("cancelled"), 0u);
}

TEST(FinalRender, TheDenoiserSteeredLoopGivesTheSameBitsOnOneAndTwoThreads) {
    render::Renderer renderer(cornell());
    FinalOptions o = smallOptions();
    o.settings.threads = 1;
    o.settings.tileSize = 16;
    const FinalResult one = renderFinal(renderer, o);
    EXPECT_GE(one.refreshes, 2);
    o.settings.threads = 2;
    o.settings.tileSize = 8;
    const FinalResult two = renderFinal(renderer, o);
    render::test::expectSameFrames(one.frame, two.frame);
    // The steering changed where the samples went: not every pixel took the same count.
    const auto counts = one.frame.layer(Layer::SampleCount).data();
    EXPECT_LT(*std::min_element(counts.begin(), counts.end()),
              *std::max_element(counts.begin(), counts.end()));
}

TEST(FinalRender, TheFrameIsTheDenoisedColourWithTheRendersLayers) {
    render::Renderer renderer(cornell());
    FinalOptions o = smallOptions();
    o.settings.spp = 16;
    const FinalResult r = renderFinal(renderer, o);
    for (Layer l : {Layer::Variance, Layer::HalfColor, Layer::HalfVariance, Layer::SampleCount,
                    Layer::Albedo, Layer::Normal, Layer::Depth})
        EXPECT_TRUE(r.frame.has(l)) << layerDisplayName(l);
    EXPECT_EQ(r.frame.metadata().extra.at("denoiseFilter"), "auto");
    // The raw render of the same settings differs from the denoised colour, and its other
    // layers are the output's.
    render::Settings s = o.settings;
    s.halfBuffers = true;
    render::Callbacks none;
    const FrameBuffers raw = renderer.render(s, none).frame;
    EXPECT_FALSE(render::test::sameLayer(raw, r.frame, Layer::Color));
    EXPECT_TRUE(render::test::sameLayer(raw, r.frame, Layer::HalfColor));
    EXPECT_GT(r.estimatedRelMse, 0.0);
    // The result keeps the render's own colour as its noisy layer, bit for bit, and renderOf
    // gives the render back.
    ASSERT_TRUE(r.frame.has(Layer::Noisy));
    EXPECT_TRUE(std::equal(r.frame.layer(Layer::Noisy).data().begin(),
                           r.frame.layer(Layer::Noisy).data().end(), raw.color().data().begin()));
    const FrameBuffers back = denoise::renderOf(r.frame);
    EXPECT_TRUE(render::test::sameLayer(raw, back, Layer::Color));
    EXPECT_FALSE(back.has(Layer::Noisy));
    EXPECT_EQ(back.metadata().extra.count("denoiseFilter"), 0u);
}

/// A fake clock: every read advances it by `tick` seconds (time counts the loop's polls: about
/// one a tile), so that a time limit is a property of the schedule, not of the machine.
std::function<double()> fakeClock(double tick) {
    auto reads = std::make_shared<std::atomic<long>>(0);
    return [reads, tick] { return tick * double(reads->fetch_add(1)); };
}

/// The final auto's plan as chosen: the one stopped at its deadline when it was (on a fake clock
/// the deadline's own clock reads take time too).
std::string chosenPlan(const FinalResult& r) {
    return r.finalStopped.empty() ? r.finalPlan : r.finalStopped;
}

TEST(FinalRender, UnderATimeLimitConvergenceHalvesTheThresholdAndTheBudgetIsUsed) {
    // A threshold every pixel meets early: with spp alone the render ends converged, far below
    // spp. With a time limit (on the fake clock) every steering halves the threshold at
    // convergence and goes on, and the render stops when the time left is the final auto's
    // reserve: the whole, the final auto included, ends within the limit (plus the few reads
    // of one step) after using all but the reserve.
    render::Renderer renderer(cornell());
    for (Steering steering : {Steering::Fixed, Steering::Variance, Steering::Denoiser}) {
        FinalOptions o = smallOptions();
        o.steering = steering;
        o.settings.spp = 4096;
        o.settings.noiseThreshold = 0.05;
        const FinalResult converged = renderFinal(renderer, o);
        EXPECT_EQ(converged.thresholdHalvings, 0);
        EXPECT_LT(meanSampleCount(converged.frame), 4096.0 / 4.0) << steeringName(steering);

        o.timeLimit = 8.0;
        o.expectedAutoSeconds = 0.5;  // the reserve until a refresh measures the final auto
        o.clock = fakeClock(0.01);
        const FinalResult timed = renderFinal(renderer, o);
        EXPECT_GT(timed.thresholdHalvings, 0) << steeringName(steering);
        EXPECT_GT(meanSampleCount(timed.frame), 2.0 * meanSampleCount(converged.frame))
            << steeringName(steering);
        EXPECT_TRUE(timed.render.cancelled) << steeringName(steering);
        EXPECT_LE(timed.seconds, o.timeLimit + 0.05) << steeringName(steering);
        EXPECT_GE(timed.seconds, o.timeLimit - kFinalAutoMargin * 0.5 - 0.05)
            << steeringName(steering);
    }
}

TEST(FinalRender, ARefreshExpectedToExceedItsShareOfTheTimeLimitIsNotRun) {
    // With the final auto's time known, a refresh is expected to take as long: one of 0.5 s
    // fits in 20 % of 8 s, one of 2 s does not (the render then steers by the threshold alone).
    render::Renderer renderer(cornell());
    FinalOptions o = smallOptions();
    o.settings.spp = 4096;
    o.timeLimit = 8.0;
    o.refreshShare = 0.2;
    o.expectedAutoSeconds = 0.5;
    o.clock = fakeClock(0.01);
    EXPECT_GE(renderFinal(renderer, o).refreshes, 1);
    o.expectedAutoSeconds = 2.0;
    o.clock = fakeClock(0.01);
    const FinalResult r = renderFinal(renderer, o);
    EXPECT_EQ(r.refreshes, 0);
    EXPECT_LE(r.seconds, o.timeLimit + 0.05);
}

TEST(FinalRender, ATimeLimitTooSmallForTheFinalAutoGetsACheaperPlanChosenBeforeTheRenderStops) {
    // The final auto at its quality is expected to take 5 s; under a limit of 2 s (fake clock)
    // the plan is chosen at the first frames from the time left (fast, fewer members, or one
    // member of one filter), the render stops leaving its reserve, and the whole keeps the
    // limit. Under 40 s the quality asked for fits its share but would take an eighth of the
    // limit from the render, more than it gains over a smaller bank (choosePlan): a cheaper plan
    // still. Expected at 1 s it costs the render little and is kept. (The variance schedule runs
    // no refresh, whose time on the fake clock would recalibrate the cost to almost nothing.)
    render::Renderer renderer(cornell());
    FinalOptions o = balancedUnderALimit();
    o.expectedAutoSeconds = 5.0;
    o.timeLimit = 2.0;
    o.clock = fakeClock(0.01);
    const FinalResult small = renderFinal(renderer, o);
    EXPECT_NE(small.finalPlan, "balanced");
    EXPECT_GT(small.predictedFinalSeconds, 0.0);
    EXPECT_LE(kFinalAutoMargin * small.predictedFinalSeconds, o.finalShare * o.timeLimit);
    EXPECT_LE(small.seconds, o.timeLimit + 0.05);
    EXPECT_FALSE(small.overTime);
    o.timeLimit = 40.0;
    o.clock = fakeClock(0.01);
    const FinalResult costly = renderFinal(renderer, o);
    EXPECT_LT(kBackedMargin * 5.0, o.finalShare * o.timeLimit);  // balanced fits its share
    EXPECT_NE(costly.finalPlan, "balanced");
    EXPECT_NE(costly.finalPlan, describe(cheapestPlan()));
    EXPECT_LE(costly.seconds, o.timeLimit + 0.05);
    o.expectedAutoSeconds = 1.0;
    o.clock = fakeClock(0.01);
    const FinalResult large = renderFinal(renderer, o);
    EXPECT_EQ(large.finalPlan, "balanced");
    EXPECT_LE(large.seconds, o.timeLimit + 0.05);
}

TEST(FinalRender, ARenderThatEndsAtItsSppEarlyGetsTheBestPlanThatFitsTheTimeLeft) {
    // While the render goes on, balanced (expected 5 s of 40) costs more samples than it gains
    // and a cheaper plan is planned (above). Bounded by its spp, the render ends long before the
    // limit: its time is spent, so the final auto is the best plan that fits what is left.
    render::Renderer renderer(cornell());
    FinalOptions o = balancedUnderALimit();
    o.expectedAutoSeconds = 5.0;
    o.timeLimit = 40.0;
    o.settings.spp = 16;
    std::vector<std::string> planned;
    o.log = [&](const std::string& line) {
        if (line.rfind("final auto planned: ", 0) == 0) planned.push_back(line);
    };
    o.clock = fakeClock(0.01);
    const FinalResult r = renderFinal(renderer, o);
    ASSERT_EQ(planned.size(), 1u);
    EXPECT_EQ(planned[0].find("final auto planned: balanced"), std::string::npos) << planned[0];
    EXPECT_LT(r.seconds, o.timeLimit / 2.0);
    EXPECT_EQ(r.finalPlan, "balanced");
}

TEST(FinalRender, AProbeRunSlowedByTheMachinesLoadDoesNotChangeTheFinalAutosPlan) {
    // The probe that calibrates auto's cost (no expectedAutoSeconds) runs kProbeRuns times and
    // the fastest counts. On the fake clock each probe run takes one tick, and balanced is chosen
    // at 30 s (not at 20 s: there its guessed cold start, kColdStartPixels, 6 s on this frame,
    // would cost the render more than balanced gains); when the clock jumps 1 s inside the first
    // run (a load spike: the first progress report of the first auto) the plan stays balanced,
    // where one timed run would make every plan a hundred times slower and choose the cheapest.
    // (The variance schedule runs no refresh, which would recalibrate the cost.)
    render::Renderer renderer(cornell());
    FinalOptions o = balancedUnderALimit();
    o.timeLimit = 30.0;
    auto planWith = [&](long spikeTicks) {
        auto reads = std::make_shared<std::atomic<long>>(0);
        auto jumped = std::make_shared<std::atomic<long>>(0);
        o.clock = [reads, jumped] { return 0.01 * double(reads->fetch_add(1) + jumped->load()); };
        o.autoOptions.progress = [jumped, spikeTicks](double) {
            long none = 0;
            jumped->compare_exchange_strong(none, spikeTicks);
            return true;
        };
        const FinalResult r = renderFinal(renderer, o);
        EXPECT_EQ(jumped->load(), spikeTicks);  // the spike came (in the first probe run)
        EXPECT_LE(r.seconds, o.timeLimit + 0.05 + 0.01 * double(spikeTicks));
        return chosenPlan(r);
    };
    const std::string quiet = planWith(0);
    EXPECT_EQ(quiet, "balanced");
    EXPECT_EQ(planWith(100), quiet);
}

TEST(FinalRender, ATimeLimitShorterThanTheFirstPassSaysSoAndDenoisesItWithTheCheapestPlan) {
    // Every clock read takes 1 s: the first pass alone overruns a limit of 0.5 s.
    render::Renderer renderer(cornell());
    FinalOptions o = smallOptions();
    o.settings.spp = 0;
    o.timeLimit = 0.5;
    o.clock = fakeClock(1.0);
    const FinalResult r = renderFinal(renderer, o);
    EXPECT_TRUE(r.overTime);
    EXPECT_EQ(r.finalPlan, describe(cheapestPlan()));
    EXPECT_EQ(r.frame.metadata().extra.at("denoiseFilter"), "auto");
}

TEST(FinalRender, WhereItFitsTheProbeRunsOnceMoreOnTheWholeFrameAndCalibratesTheCost) {
    // A 72² frame, larger than the probe's crop. On the fake clock every auto run takes one tick:
    // the crop's probe predicts the whole frame's run at kFramePixelCost × 72² / 64² ticks, within
    // kFrameProbeShare of a 2-s limit, so it runs, and its tick calibrates the cost: the final
    // auto's prediction is that of a frame whose cheapest plan takes one tick (the crop's alone
    // would predict it 1.5 × longer), warm (the default bank's cold start paid by the warm-up).
    // Under a limit of 0.02 s (a tick's 1.5 is more than its share; the first pass alone overruns
    // it) the whole frame is not probed.
    render::Renderer renderer(cornell(72));
    FinalOptions o = balancedUnderALimit();
    std::vector<std::string> lines;
    o.log = [&](const std::string& line) { lines.push_back(line); };
    auto probedWhole = [&] {
        for (const std::string& line : lines)
            if (line.find("probe of the whole frame") != std::string::npos) return true;
        return false;
    };
    const double tick = 0.001;
    o.timeLimit = 2.0;
    o.clock = fakeClock(tick);
    const FinalResult r = renderFinal(renderer, o);
    EXPECT_TRUE(probedWhole());
    ASSERT_EQ(chosenPlan(r), "balanced");
    AutoCost whole;
    whole.probedFrame(72.0 * 72.0, tick);
    whole.ran(warmupPlan());
    EXPECT_NEAR(r.predictedFinalSeconds,
                whole.seconds({denoise::AutoQuality::Balanced, 0, {}}, 72.0 * 72.0), 1e-9);
    lines.clear();
    o.timeLimit = 0.02;
    o.clock = fakeClock(tick);
    renderFinal(renderer, o);
    EXPECT_FALSE(probedWhole());
}

TEST(FinalRender, AFinalAutoOnTheDefaultBankHasItsColdStartPaidByAWarmUpBeforeTheRenderStops) {
    // Probed (no expectedAutoSeconds) on the fake clock, where every auto run takes a tick or
    // two: under 20 s balanced is planned, so the default bank's smallest plan runs once on the
    // probe's crop first (the warm-up, its cold start measured there) and the final auto is
    // predicted warm: exactly its weight times the probe's rate. Under a limit whose share only
    // the cheapest plan fits (one member of one filter: no default bank) no warm-up runs.
    render::Renderer renderer(cornell());
    FinalOptions o = balancedUnderALimit();
    std::vector<std::string> lines;
    o.log = [&](const std::string& line) { lines.push_back(line); };
    auto warmedUp = [&] {
        for (const std::string& line : lines)
            if (line.rfind("warm-up:", 0) == 0) return true;
        return false;
    };
    o.timeLimit = 20.0;
    o.clock = fakeClock(0.01);
    const FinalResult r = renderFinal(renderer, o);
    EXPECT_TRUE(warmedUp());
    ASSERT_EQ(chosenPlan(r), "balanced");
    AutoCost cold, warm;  // as the probe's run of one tick calibrated it (the crop: the frame)
    for (AutoCost* c : {&cold, &warm}) c->probed(24.0 * 24.0, 0.01);
    warm.ran(warmupPlan());
    const AutoPlan balanced{denoise::AutoQuality::Balanced, 0, {}};
    const double px = 24.0 * 24.0;
    EXPECT_NEAR(r.predictedFinalSeconds, warm.seconds(balanced, px), 1e-6);
    EXPECT_LT(r.predictedFinalSeconds, 0.5 * cold.seconds(balanced, px));
    lines.clear();
    o.timeLimit = 0.3;
    o.clock = fakeClock(0.01);
    const FinalResult small = renderFinal(renderer, o);
    EXPECT_EQ(small.finalPlan, describe(cheapestPlan()));
    EXPECT_FALSE(warmedUp());
}

TEST(FinalRender, AFinalAutoPastItsDeadlineIsStoppedAndTheCheapestPlanDenoisesTheFrame) {
    // The final auto at balanced is expected to take 2 s (its reserve 2.56 s of a 20-s limit:
    // kBackedMargin × 2 and the cheapest plan's 1.3 × 0.125); on the fake clock the machine then
    // slows: its first progress report comes 2.45 s late and each later one 0.05 s. It is stopped
    // where only the cheapest plan's reserve is left, the cheapest plan (not slowed) denoises the
    // frame, and the whole keeps the limit. (Without the deadline the final auto ran to its end,
    // past the limit.)
    render::Renderer renderer(cornell());
    FinalOptions o = balancedUnderALimit();
    o.timeLimit = 20.0;
    o.expectedAutoSeconds = 2.0;
    auto reads = std::make_shared<std::atomic<long>>(0);
    auto slowed = std::make_shared<std::atomic<long>>(0);
    o.clock = [reads, slowed] { return 0.01 * double(reads->fetch_add(1) + slowed->load()); };
    // The first auto run (the final one: no probe, no refresh) is slowed; each run reports 0
    // first, then rising fractions.
    auto reports = std::make_shared<int>(0);
    auto first = std::make_shared<bool>(true);
    o.autoOptions.progress = [slowed, reports, first](double fraction) {
        if (fraction == 0.0 && ++*reports > 1) *first = false;
        if (*first) slowed->fetch_add(*reports == 1 && fraction == 0.0 ? 245 : 5);
        return true;
    };
    const FinalResult r = renderFinal(renderer, o);
    EXPECT_EQ(r.finalStopped, "balanced");
    EXPECT_EQ(r.finalPlan, describe(cheapestPlan()));
    EXPECT_NEAR(r.predictedFinalSeconds, 2.0, 1e-9);
    EXPECT_LE(r.seconds, o.timeLimit + 0.05);
    EXPECT_GE(r.seconds, o.timeLimit - kFinalAutoMargin * 2.0);
    EXPECT_EQ(r.frame.metadata().extra.at("denoiseFilter"), "auto");
    EXPECT_GT(r.estimatedRelMse, 0.0);
    // Not slowed, balanced runs to its end well within its reserve.
    o.autoOptions.progress = {};
    o.clock = fakeClock(0.01);
    const FinalResult quiet = renderFinal(renderer, o);
    EXPECT_EQ(quiet.finalPlan, "balanced");
    EXPECT_TRUE(quiet.finalStopped.empty());
    EXPECT_LE(quiet.seconds, o.timeLimit + 0.05);
}

TEST(FinalRender, TheWholeFrameIsProbedOnceMoreBeforeTheRenderStopsAndThatRunCalibratesTheCost) {
    // As above (a 72² frame, a 2-s limit, every auto run a tick on the fake clock), but the
    // machine slows late: the sixth auto run (after the crop's three, the whole frame's and the
    // warm-up) takes three ticks. That run is the late probe, made when the time left is within
    // kLateProbeShare of the limit past the reserve, and it calibrates the final auto's
    // prediction: three times the first probe's. When the first probe of the whole frame was the
    // slow one, the slower still counts.
    render::Renderer renderer(cornell(72));
    FinalOptions o = balancedUnderALimit();
    std::vector<std::string> lines;
    o.log = [&](const std::string& line) { lines.push_back(line); };
    const double tick = 0.001;
    o.timeLimit = 2.0;
    auto reads = std::make_shared<std::atomic<long>>(0);
    auto slowed = std::make_shared<std::atomic<long>>(0);
    o.clock = [reads, slowed, tick] { return tick * double(reads->fetch_add(1) + slowed->load()); };
    auto runs = std::make_shared<int>(0);
    auto slowRun = std::make_shared<int>(6);
    o.autoOptions.progress = [slowed, runs, slowRun](double fraction) {
        if (fraction == 0.0 && ++*runs == *slowRun) slowed->fetch_add(2);
        return true;
    };
    const FinalResult r = renderFinal(renderer, o);
    int late = 0;
    for (const std::string& line : lines)
        late += line.rfind("late probe of the whole frame: auto 0.003 s", 0) == 0;
    EXPECT_EQ(late, 1);
    ASSERT_EQ(chosenPlan(r), "balanced");
    AutoCost early, slow;
    early.probedFrame(72.0 * 72.0, tick);
    slow.probedFrame(72.0 * 72.0, 3.0 * tick);
    for (AutoCost* c : {&early, &slow}) c->ran(warmupPlan());
    const AutoPlan balanced{denoise::AutoQuality::Balanced, 0, {}};
    EXPECT_NEAR(r.predictedFinalSeconds, slow.seconds(balanced, 72.0 * 72.0), 1e-9);
    EXPECT_NEAR(r.predictedFinalSeconds, 3.0 * early.seconds(balanced, 72.0 * 72.0), 1e-9);
    EXPECT_LE(r.seconds, o.timeLimit + 0.05);
    // The first probe of the whole frame (the fourth run) slow, the late one not.
    lines.clear();
    reads->store(0);
    slowed->store(0);
    *runs = 0;
    *slowRun = 4;
    const FinalResult firstSlow = renderFinal(renderer, o);
    late = 0;
    for (const std::string& line : lines)
        late += line.rfind("late probe of the whole frame: auto 0.001 s", 0) == 0;
    EXPECT_EQ(late, 1);
    ASSERT_EQ(chosenPlan(firstSlow), "balanced");
    EXPECT_NEAR(firstSlow.predictedFinalSeconds, slow.seconds(balanced, 72.0 * 72.0), 1e-9);
}

TEST(FinalRender, TheVarianceScheduleRunsNoAutoBeforeTheFinalOne) {
    // The variance-only map costs nothing to make: no refresh, one auto (the final one); the
    // denoiser-steered one refreshes at the refresh quality and counts their time apart.
    render::Renderer renderer(cornell());
    FinalOptions o = smallOptions();
    o.steering = Steering::Variance;
    const FinalResult variance = renderFinal(renderer, o);
    EXPECT_EQ(variance.refreshes, 0);
    EXPECT_EQ(variance.refreshSeconds, 0.0);
    o.steering = Steering::Denoiser;
    const FinalResult denoiser = renderFinal(renderer, o);
    EXPECT_GE(denoiser.refreshes, 2);
    EXPECT_GT(denoiser.refreshSeconds, 0.0);
    EXPECT_LT(denoiser.refreshSeconds, denoiser.autoSeconds);
}

TEST(FinalRender, TheImportanceFollowsTheRelativeErrorWithinItsRange) {
    Image relative(4, 1, 1);
    relative(0, 0, 0) = 0.0f;    // right already: 1/8 of the scale
    relative(1, 0, 0) = 1.0f;    // the mean: the scale
    relative(2, 0, 0) = 3.0f;    // sqrt(3) times
    relative(3, 0, 0) = 100.0f;  // clamped at 8 times
    // Mean (0 + 1 + 3 + 100) / 4 = 26: normalise to it.
    const Image w = importanceFromError(relative, 2.0);
    const double mean = 26.0;
    EXPECT_FLOAT_EQ(w(0, 0, 0), 2.0f / 8.0f);
    EXPECT_FLOAT_EQ(w(1, 0, 0), float(2.0 * std::max(std::sqrt(1.0 / mean), 1.0 / 8.0)));
    EXPECT_FLOAT_EQ(w(2, 0, 0), float(2.0 * std::sqrt(3.0 / mean)));
    EXPECT_FLOAT_EQ(w(3, 0, 0), float(2.0 * std::sqrt(100.0 / mean)));
    // The relative error divides by the display value's square plus 0.01: black is divided by
    // 0.01, white by 1.01.
    Image error(2, 1, 1, 0.01f), composite(2, 1, 3, 0.0f);
    for (int c = 0; c < 3; ++c) composite(1, 0, c) = 1.0f;
    const Image rel = relativeError(error, composite, 0.0f);
    EXPECT_NEAR(rel(0, 0, 0), 1.0, 1e-6);
    EXPECT_NEAR(rel(1, 0, 0), 0.01 / 1.01, 1e-6);
    EXPECT_NEAR(estimatedRelMse(rel), 0.5 * (1.0 + 0.01 / 1.01), 1e-6);
}

std::vector<float> values(const Image& image) {
    return {image.data().begin(), image.data().end()};
}

TEST(FinalRender, TheSamplesCapClosesThePixelsAtItsMultipleOfTheMean) {
    // Four pixels of 1, 1, 1 and 13 samples: a mean of 4. At twice the mean (8) the fourth is
    // closed (weight 0, the map's other weights kept); at four times (16) none is, and the map
    // comes back as it was, as it does with the cap off.
    FrameBuffers frame(4, 1);
    Image& count = frame.ensure(Layer::SampleCount);
    for (int x = 0; x < 4; ++x) count(x, 0, 0) = x == 3 ? 13.0f : 1.0f;
    auto map = std::make_shared<const Image>(4, 1, 1, 3.0f);
    bool capped = false;
    const auto two = capSamples(map, frame, 2.0, &capped);
    EXPECT_TRUE(capped);
    ASSERT_NE(two, map);
    EXPECT_EQ(values(*two), (std::vector<float>{3.0f, 3.0f, 3.0f, 0.0f}));
    EXPECT_EQ(values(*map), (std::vector<float>{3.0f, 3.0f, 3.0f, 3.0f}));
    EXPECT_EQ(capSamples(map, frame, 4.0, &capped), map);
    EXPECT_FALSE(capped);
    EXPECT_EQ(capSamples(map, frame, 0.0, &capped), map);
    EXPECT_FALSE(capped);
    // No map (the renderer's own weights, 1): the cap makes one.
    const auto ones = capSamples(nullptr, frame, 2.0);
    ASSERT_TRUE(ones);
    EXPECT_EQ(values(*ones), (std::vector<float>{1.0f, 1.0f, 1.0f, 0.0f}));
}

TEST(FinalRender, UnderTheSamplesCapNoPixelPassesItsMultipleOfTheMeanByMoreThanAPass) {
    // The variance schedule under a time limit (fake clock) gives the pixels of largest relative
    // spread samples ∝ its square: on scenes/pool's white ball (a highlight beside a motion
    // streak's end, a 24 × 24 region) a few pixels take many times the mean. With the cap at
    // twice the mean, checked before every adaptive pass, a pixel ends at most one pass
    // (RenderLoop's largest step, 256) past twice the final mean of the region's pixels.
    render::Renderer renderer(
        render::loadScene(std::string(GLINT_SOURCE_DIR) + "/scenes/pool/scene.json"));
    FinalOptions o = balancedUnderALimit();
    o.settings.maxDepth = 8;
    o.settings.region = Rect{44, 68, 30, 54};
    o.settings.noiseThreshold = 0.01;  // glint-final's start (the scene's default)
    o.settings.minSpp = 16;
    o.quality = denoise::AutoQuality::Fast;
    o.timeLimit = 8.0;
    o.expectedAutoSeconds = 0.5;
    auto stats = [&](const FrameBuffers& f) {
        double sum = 0.0, most = 0.0;
        int n = 0;
        for (int y = 30; y < 54; ++y)
            for (int x = 44; x < 68; ++x) {
                const double c = f.layer(Layer::SampleCount)(x, y, 0);
                sum += c;
                most = std::max(most, c);
                ++n;
            }
        return std::pair{sum / n, most};
    };
    o.clock = fakeClock(0.01);
    o.sppCapRatio = 0.0;
    const auto [freeMean, freeMost] = stats(renderFinal(renderer, o).frame);
    o.clock = fakeClock(0.01);
    o.sppCapRatio = 2.0;
    const auto [cappedMean, cappedMost] = stats(renderFinal(renderer, o).frame);
    std::printf("[ cap ] off: mean %.1f most %.0f; 2x: mean %.1f most %.0f\n", freeMean, freeMost,
                cappedMean, cappedMost);
    EXPECT_GT(freeMost, 2.0 * freeMean + 256.0);
    EXPECT_LE(cappedMost, 2.0 * cappedMean + 256.0);
}

/// The message and place of the glint::Error validate(o) throws ("" when none).
std::string refusal(const FinalOptions& o) {
    try {
        validate(o);
    } catch (const Error& e) {
        return e.where() + ": " + e.message();
    }
    return "";
}

TEST(FinalRender, BadOptionsAreRefusedNamingTheOption) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (double t : {-1.0, nan, 2e7}) {
        FinalOptions o = smallOptions();
        o.timeLimit = t;
        EXPECT_EQ(refusal(o).rfind("timeLimit: the time limit must be", 0), 0u) << refusal(o);
    }
    for (double e : {-1.0, nan, 2e6}) {
        FinalOptions o = smallOptions();
        o.targetError = e;
        EXPECT_EQ(refusal(o).rfind("targetError: the error target must be", 0), 0u) << refusal(o);
    }
    FinalOptions o = smallOptions();
    o.refreshGrowth = 1.0;
    EXPECT_EQ(refusal(o).rfind("refreshGrowth:", 0), 0u) << refusal(o);
    for (double r : {-1.0, 0.5, nan, 2e6}) {
        o = smallOptions();
        o.sppCapRatio = r;
        EXPECT_EQ(refusal(o).rfind("sppCapRatio: the samples cap must be 0 (off) or a factor", 0),
                  0u)
            << refusal(o);
    }
    o = smallOptions();
    o.settings.spp = 0;
    o.targetError = 0.01;
    EXPECT_EQ(refusal(o).rfind("spp: an error target needs a time limit or a spp", 0), 0u)
        << refusal(o);
    // The render's own checks: a max spp below the start, a threshold out of range.
    o = smallOptions();
    o.settings.spp = 4;
    EXPECT_NE(refusal(o).find("minSpp"), std::string::npos) << refusal(o);
    o = smallOptions();
    o.settings.noiseThreshold = 0.0;
    EXPECT_NE(refusal(o).find("noiseThreshold must be a number in (0, 1e6]"), std::string::npos)
        << refusal(o);
}

}  // namespace
}  // namespace glint::pipeline
