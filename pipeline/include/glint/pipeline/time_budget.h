// How a final render shares its time limit (docs/final-render.md, "Targets"): the render runs
// while the time left exceeds the reserve for the final auto (a margin over its predicted time),
// and auto's refreshes during the render take at most a share of the limit. Auto's time is
// predicted by a cost model calibrated in the run (AutoCost: a probe on a crop of the first pass,
// then each refresh), and the final auto's plan (its quality, or a smaller bank) is chosen among
// those that fit its share by the error it leaves with the render's time (choosePlan). Times are
// seconds since the render started, read from any clock (tests use a fake one).
#pragma once

#include <string>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/image/frame_buffers.h"

namespace glint::pipeline {

/// The reserve for a final auto of cheapestPlan(), nothing cheaper behind it: this many times its
/// predicted seconds. The prediction is right on average; with its spread (a probe is one moment
/// of a shared machine) 92 % of bench_final_budget's runs took at most 1.3 × it, and glint-final's
/// at 2 s up to 1.33 × (there the 10 % the CLI keeps is all start-up and writing); 1.5 × costs
/// the render 0.03 s at 256² (docs/lab/race.md, "Keeping the time limit").
inline constexpr double kFinalAutoMargin = 1.5;
/// The margin of any other plan: the final auto stops at a deadline that leaves cheapestPlan()
/// its reserve, which then denoises the frame (renderFinal), so the margin covers the usual
/// spread, not the tail: glint-final's balanced took at most 1.10 × its prediction in 17 of 18
/// tuning runs at load 2–4 (1.5 × once: a load that came after the probe; since then the whole
/// frame is probed again late, kLateProbeShare).
inline constexpr double kBackedMargin = 1.2;
/// What a pixel of a whole frame costs auto against a pixel of a probe's crop (the crop stays in
/// the caches): 1.21 on 4 scenes at 256² and 540² (bench_final_budget).
inline constexpr double kFramePixelCost = 1.21;
/// What the final auto's pixel costs against the whole-frame probe's in glint-final (the probe,
/// the process's first auto on a frame-sized buffer, on the frame of the second pass, costs more
/// than the same run later): 0.87, the median of 18 tuning runs (docs/lab/race.md).
inline constexpr double kFrameProbeCost = 0.87;

/// The schedule of one time-limited final render.
class TimeBudget {
  public:
    /// `limit` seconds in all (0: none, and everything fits); auto's refreshes take at most
    /// `refreshShare` of it; the final auto is expected to take `expectedFinal` seconds (0:
    /// unknown until the cost model predicts it: expectFinal).
    TimeBudget(double limit, double refreshShare, double expectedFinal);

    bool timed() const { return m_limit > 0.0; }
    double limit() const { return m_limit; }
    /// The seconds kept for the final auto (finalReserve; kFinalAutoMargin times its expected
    /// time unless expectFinal said otherwise).
    double reserve() const { return m_reserve; }
    /// Whether the render may go on at `now`: more than the reserve is left.
    bool renderMayContinue(double now) const;
    /// Whether a refresh at `now` expected to take `seconds` fits: the refreshes stay within
    /// their share and the reserve is still left after it.
    bool refreshFits(double now, double seconds) const;
    /// Records a refresh that took `seconds`.
    void refreshed(double seconds) { m_refreshes += seconds; }
    /// The final auto is now expected to take `seconds` (the cost model's prediction of its plan)
    /// and `reserve` seconds are kept for it (finalReserve).
    void expectFinal(double seconds, double reserve) {
        m_final = seconds;
        m_reserve = reserve;
    }
    /// expectFinal with kFinalAutoMargin times `seconds` kept.
    void expectFinal(double seconds) { expectFinal(seconds, kFinalAutoMargin * seconds); }
    /// What the final auto is expected to take (0: unknown).
    double expectedFinal() const { return m_final; }
    /// The refreshes' seconds so far.
    double refreshSeconds() const { return m_refreshes; }

  private:
    double m_limit, m_share, m_final, m_reserve;
    double m_refreshes = 0.0;
};

/// How auto runs: a quality, its bank's Latin-hypercube members (0: the quality's) and filters
/// (empty: the default bank's). The cheaper plans of choosePlan are fast with fewer members.
struct AutoPlan {
    denoise::AutoQuality quality = denoise::AutoQuality::Balanced;
    int bankSize = 0;
    std::vector<std::string> filters;
};

/// "balanced", "fast with 8 members", "fast with 1 member of cross-bilateral", …
std::string describe(const AutoPlan& plan);

/// The plan's cost relative to balanced's on the same frame (balanced: 1). A linear model in the
/// bank's members, the defaults of each filter on top, fitted to bench_final_budget's
/// measurements (docs/lab/race.md, "Keeping the time limit").
double planWeight(const AutoPlan& plan);

/// Auto's cost model: seconds = rate × pixels × planWeight(plan), plus a cold start on the
/// process's first run of the default bank (what it loads once); the rate calibrated by a timed
/// run of any plan on a whole frame (a refresh, an expected time) or by a probe on a crop.
class AutoCost {
  public:
    /// Sets the rate from a run of `plan` on a whole frame of `pixels` pixels that took
    /// `seconds` (its cold start taken out), and records the run.
    void calibrate(const AutoPlan& plan, double pixels, double seconds);
    /// Sets the rate from a probe: cheapestPlan() on a crop of `pixels` pixels took `seconds`
    /// (a frame's pixel costs kFramePixelCost times a crop's).
    void probed(double pixels, double seconds);
    /// Sets the rate from glint-final's probe of the whole frame: cheapestPlan() on its `pixels`
    /// took `seconds` (the final auto's pixel costs kFrameProbeCost times the probe's).
    void probedFrame(double pixels, double seconds);
    /// Records a run of `plan` (a default bank's run warms the next).
    void ran(const AutoPlan& plan);
    bool calibrated() const { return m_rate > 0.0; }
    /// Whether a default bank has run (its cold start is paid: warmupPlan()).
    bool warm() const { return m_warm; }
    /// The predicted seconds of `plan` on `pixels` pixels (0 before any calibration).
    double seconds(const AutoPlan& plan, double pixels) const;

  private:
    bool coldStart(const AutoPlan& plan) const;
    double m_rate = 0.0;  ///< seconds per pixel at weight 1
    bool m_warm = false;  ///< a default bank has run
};

/// The cheapest plan: one fast member of one filter (with its defaults: two members), and the
/// render itself (the identity filter), which auto keeps where the filter would only blur a
/// converged frame: the fallback at a final auto's deadline is never much worse than the render.
AutoPlan cheapestPlan();

/// The default bank's smallest plan (fast with 1 member), which glint-final runs on the probe's
/// crop when the final auto is planned on the default bank: it pays the process's cold start
/// (0.1–1.1 s, longer under load) before the render stops, where it is measured, instead of
/// inside the reserve, where only a guess of it could be kept.
AutoPlan warmupPlan();

/// The seconds kept for a final auto of `plan` on `pixels` pixels: kFinalAutoMargin times the
/// prediction for cheapestPlan(); for any other plan kBackedMargin times its prediction plus
/// cheapestPlan()'s reserve (the fallback at its deadline).
double finalReserve(const AutoCost& cost, const AutoPlan& plan, double pixels);

/// What a plan's final auto gains over cheapestPlan() on the same frame: the cheapest plan's
/// relMSE ÷ the plan's (1 for cheapestPlan() itself). The geometric mean over six scenes at 32, 128
/// and 512 spp (uniform frames, seed 511): fast with 1 to 4 members 1.42, 16 members 1.49, fast
/// (32) 1.54, balanced 1.62, best balanced's × 1.02 (docs/lab/final-plan.md). A plan of named
/// filters counts as its bank size.
double planGain(const AutoPlan& plan);

/// The render's side of the final auto's plan: `rendered` seconds of the render so far and
/// `ahead` seconds from now to the time limit. A plan whose finalReserve is R leaves the render
/// rendered + max(0, ahead − R) seconds in all.
struct RenderTime {
    double rendered = 0.0;
    double ahead = 0.0;
};

/// The plan the final auto runs with `seconds` for it on `pixels` pixels. The plans tried: `most`
/// (balanced, say), the cheaper qualities down to fast, fast with 16, 8, 4, 2 and 1 members, and
/// cheapestPlan(); a plan fits when its finalReserve is at most `seconds`. Without `render`
/// (ahead 0): the first that fits. With it: of those that fit, the one whose error after the
/// render it leaves is least, planGain(plan) × the render's seconds with it — the error taken as
/// falling as 1 / spp (the noise's rate), so a plan is chosen only where it gains more than the
/// samples its time would have bought. cheapestPlan() when none fits; `most` itself when the
/// cost is not calibrated.
AutoPlan choosePlan(const AutoCost& cost, double pixels, double seconds, const AutoPlan& most,
                    const RenderTime& render = {});

/// The centred crop of `frame` of at most side × side pixels, every layer cropped (a probe of
/// auto's cost).
FrameBuffers probeFrame(const FrameBuffers& frame, int side);

}  // namespace glint::pipeline
