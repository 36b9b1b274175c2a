// The time limit's schedule and auto's cost model (time_budget.h).
#include "glint/pipeline/time_budget.h"

#include <algorithm>
#include <cmath>

#include "glint/denoise/registry.h"

namespace glint::pipeline {

namespace {

/// The cost model's constants, in units of the time of one fast member of cross-bilateral (its
/// two members; cheapestPlan() before it held the identity too) on the same frame: for the
/// default bank a fixed part (the selection, the halves, the error estimate) and a part per
/// member, each filter's defaults counted as members; for a bank of named filters each smoothing
/// member at half of that. Fitted to bench_final_budget's warm times on cornell,
/// fox, dof and glossy at 256² and 540², 8 and 64 spp (docs/lab/race.md, "Keeping the time
/// limit": fast with 1, 8 and 32 members 4.3, 6.1 and 12.3 × cheapestPlan, balanced 16.0).
constexpr double kFixedTwoSided = 7.29;  ///< balanced, best
constexpr double kFixedOneSided = 2.27;  ///< fast
constexpr double kMemberTwoSided = 0.122;
constexpr double kMemberOneSided = 0.256;
constexpr double kNamedMember = 0.5;
/// A named filter that does not smooth (the identity, FilterTraits::smooths) is its default
/// member only, and costs only its error map: cheapestPlan with it took 1.010, 1.032 and 1.020 ×
/// the time without it on cornell, fox and glossy at 512 spp (docs/lab/cheapest-plan.md).
constexpr double kPassMember = 0.03;
/// A process's first run of the default bank loads and prepares what later runs reuse (the
/// unet's weights and its plans): 0.7–1.7 s whatever the frame's size, about 4.5 ×
/// cheapestPlan's time on 256² pixels, in pixels at weight 1.
constexpr double kColdStartPixels = 4.5 * 65536.0;
/// The filter of cheapestPlan, and the member beside it that keeps the render where the filter
/// would only blur it (a converged frame: docs/lab/cheapest-plan.md).
constexpr const char* kCheapestFilter = "cross-bilateral";
constexpr const char* kRenderItself = "identity";
/// The bank sizes tried below fast's own.
constexpr int kSmallerBanks[] = {16, 8, 4, 2, 1};
/// planGain's measured gains (docs/lab/final-plan.md): fast with up to 4 members, and from there +
/// kGainPerBankDoubling for every doubling of the bank (16 members 1.50, fast's 32 1.54:
/// measured 1.49 and 1.54); balanced; best.
constexpr double kGainSmallBank = 1.42;
constexpr double kGainPerBankDoubling = 0.04;
constexpr double kGainBalanced = 1.62;
constexpr double kGainBest = 1.65;

}  // namespace

TimeBudget::TimeBudget(double limit, double refreshShare, double expectedFinal)
    : m_limit(limit),
      m_share(refreshShare),
      m_final(expectedFinal),
      m_reserve(kFinalAutoMargin * expectedFinal) {}

bool TimeBudget::renderMayContinue(double now) const {
    return !timed() || now + reserve() < m_limit;
}

bool TimeBudget::refreshFits(double now, double seconds) const {
    if (!timed()) return true;
    return m_refreshes + seconds <= m_share * m_limit && now + seconds + reserve() < m_limit;
}

std::string describe(const AutoPlan& plan) {
    std::string text = denoise::autoQualityName(plan.quality);
    if (plan.bankSize > 0)
        text += " with " + std::to_string(plan.bankSize) +
                (plan.bankSize == 1 ? " member" : " members");
    for (std::size_t i = 0; i < plan.filters.size(); ++i)
        text += (i == 0 ? " of " : ", ") + plan.filters[i];
    return text;
}

double planWeight(const AutoPlan& plan) {
    const bool oneSided = plan.quality == denoise::AutoQuality::Fast;
    const int members =
        plan.bankSize > 0 ? plan.bankSize : denoise::autoQualityBankSize(plan.quality);
    // Each filter's defaults come on top of the Latin-hypercube members, which go to the
    // filters that smooth.
    if (!plan.filters.empty()) {
        double weight = kNamedMember * double(members);
        for (const std::string& name : plan.filters)
            weight += denoise::findFilter(name).traits().smooths ? kNamedMember : kPassMember;
        return weight;
    }
    const int all = members + int(denoise::defaultBankFilters().size());
    return oneSided ? kFixedOneSided + kMemberOneSided * double(all)
                    : kFixedTwoSided + kMemberTwoSided * double(all);
}

void AutoCost::calibrate(const AutoPlan& plan, double pixels, double seconds) {
    const double cold = coldStart(plan) ? m_rate * kColdStartPixels : 0.0;
    if (pixels > 0.0 && seconds > cold) m_rate = (seconds - cold) / (pixels * planWeight(plan));
    ran(plan);
}

void AutoCost::probed(double pixels, double seconds) {
    // The crop's time as the same pixels of a whole frame would take.
    calibrate(cheapestPlan(), pixels, kFramePixelCost * seconds);
}

void AutoCost::probedFrame(double pixels, double seconds) {
    calibrate(cheapestPlan(), pixels, kFrameProbeCost * seconds);
}

void AutoCost::ran(const AutoPlan& plan) {
    if (plan.filters.empty()) m_warm = true;
}

bool AutoCost::coldStart(const AutoPlan& plan) const {
    return plan.filters.empty() && !m_warm;
}

double AutoCost::seconds(const AutoPlan& plan, double pixels) const {
    return m_rate * (pixels * planWeight(plan) + (coldStart(plan) ? kColdStartPixels : 0.0));
}

AutoPlan cheapestPlan() {
    return {denoise::AutoQuality::Fast, 1, {kCheapestFilter, kRenderItself}};
}

AutoPlan warmupPlan() {
    return {denoise::AutoQuality::Fast, 1, {}};
}

double finalReserve(const AutoCost& cost, const AutoPlan& plan, double pixels) {
    const double fallback = kFinalAutoMargin * cost.seconds(cheapestPlan(), pixels);
    if (describe(plan) == describe(cheapestPlan())) return fallback;
    return kBackedMargin * cost.seconds(plan, pixels) + fallback;
}

double planGain(const AutoPlan& plan) {
    if (describe(plan) == describe(cheapestPlan())) return 1.0;
    if (plan.quality == denoise::AutoQuality::Best && plan.bankSize == 0) return kGainBest;
    if (plan.quality == denoise::AutoQuality::Balanced && plan.bankSize == 0) return kGainBalanced;
    const int members =
        plan.bankSize > 0 ? plan.bankSize : denoise::autoQualityBankSize(plan.quality);
    return kGainSmallBank + kGainPerBankDoubling * std::max(0.0, std::log2(double(members)) - 2.0);
}

AutoPlan choosePlan(const AutoCost& cost, double pixels, double seconds, const AutoPlan& most,
                    const RenderTime& render) {
    if (!cost.calibrated()) return most;
    auto fits = [&](const AutoPlan& plan) { return finalReserve(cost, plan, pixels) <= seconds; };
    // The qualities from `most` down to fast, then fast with smaller banks.
    std::vector<AutoPlan> ladder{most};
    for (denoise::AutoQuality q :
         {denoise::AutoQuality::Best, denoise::AutoQuality::Balanced, denoise::AutoQuality::Fast})
        if (int(q) < int(most.quality)) ladder.push_back({q, 0, most.filters});
    for (int size : kSmallerBanks)
        ladder.push_back({denoise::AutoQuality::Fast, size, most.filters});
    if (render.ahead <= 0.0) {
        for (const AutoPlan& plan : ladder)
            if (fits(plan)) return plan;
        return cheapestPlan();
    }
    // The error after the render: ∝ 1 / (the plan's gain × the render's seconds with it).
    auto value = [&](const AutoPlan& plan) {
        const double renders =
            render.rendered + std::max(0.0, render.ahead - finalReserve(cost, plan, pixels));
        return planGain(plan) * renders;
    };
    AutoPlan best = cheapestPlan();
    double bestValue = value(best);
    for (const AutoPlan& plan : ladder)
        if (fits(plan) && value(plan) > bestValue) {
            best = plan;
            bestValue = value(plan);
        }
    return best;
}

FrameBuffers probeFrame(const FrameBuffers& frame, int side) {
    const int w = std::min(side, frame.width()), h = std::min(side, frame.height());
    const int x0 = (frame.width() - w) / 2, y0 = (frame.height() - h) / 2;
    const Rect rect{x0, x0 + w, y0, y0 + h};
    FrameBuffers probe(w, h);
    probe.metadata() = frame.metadata();
    for (int l = 0; l < kLayerCount; ++l)
        if (const Image* layer = frame.find(Layer(l))) probe.set(Layer(l), layer->crop(rect));
    return probe;
}

}  // namespace glint::pipeline
