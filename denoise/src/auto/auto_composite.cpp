// The automatic selection (autoComposite, sure.h): its stages in the order docs/auto.md, "Stages",
// describes them, each in its own file of this folder and each through one WorkContext, so that
// progress and cancellation cover all of it.
#include <memory>
#include <numeric>

#include "blend.h"
#include "choice.h"
#include "display_weights.h"
#include "estimator.h"
#include "feathering.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"
#include "halves_estimator.h"
#include "median.h"
#include "options.h"
#include "shortlist.h"
#include "stacking.h"
#include "sure_estimator.h"

namespace glint::denoise {

namespace {

// The progress's work units: one row of one pass over the region; applying a member counts as
// kFilterPasses passes (with the bank's usual members, a filter costs a few times the passes of
// the stages after it).
constexpr std::int64_t kFilterPasses = 4;

// The units the stages below count, for the progress fraction (about: a stage that counts more
// makes the fraction wait at 0.999 until finish()).
std::int64_t expectedWork(const detail::AutoSettings& s, std::size_t n, std::int64_t h) {
    const auto shortlist = std::int64_t(s.shortlisted ? s.shortlist : 0);
    const auto members = std::int64_t(n);
    std::int64_t passes = (members + shortlist) * kFilterPasses;
    if (s.secant || s.tangent) passes += s.secant ? 2 : 1;  // median, D(median)
    if (s.temperature > 0.0) passes += 3;                   // noise, its box average
    const std::int64_t finalCandidates = s.shortlisted ? shortlist : members;
    passes += (s.shortlisted ? members + 1 : 0) + finalCandidates * (1 + s.finer) + 1;
    if (s.feather > 0) passes += finalCandidates + 2;
    passes += 1;                                                                  // blend
    if (s.stack > 0) passes += 1 + (s.stackAlbedo || s.stackNormal ? 6 : 0) + 4;  // stacking
    return passes * h;
}

// The pipeline, with its work counted by `work`.
AutoResult runStages(const FilterBank& bank, const FrameBuffers& frame,
                     const detail::AutoSettings& s, WorkContext& work) {
    const Rect& region = bank.region();
    const std::size_t n = bank.size();
    const std::int64_t memberUnits = kFilterPasses * region.height();

    // The display linearisation around the bank's median: SURE and DisplayTangent by the slope
    // there (weight), the halves' Display by the secant to each output (secant). The tangent
    // weights also scale the temperature's noise unit in both display spaces.
    const Image median = s.secant || s.tangent ? detail::bankMedian(bank, work) : Image{};
    const std::vector<double> displayMedian =
        s.secant ? detail::displayOf(median, s.exposure, &work) : std::vector<double>{};
    const Image weight =
        s.secant || s.tangent ? detail::tangentWeights(median, s.exposure) : Image{};
    const Image* weightPtr = s.tangent ? &weight : nullptr;

    // Error estimation: SURE from the variance layer, or cross-validation on the halves (which
    // keep each member's results on them for the stacking).
    const bool stacking = s.stack > 0;
    std::unique_ptr<detail::ErrorEstimator> estimator;
    detail::HalvesEstimator* halves = nullptr;
    if (s.halves) {
        auto h = std::make_unique<detail::HalvesEstimator>(bank, frame, s, s.bothHalves, stacking,
                                                           &median, &displayMedian, weightPtr);
        halves = h.get();
        estimator = std::move(h);
    } else {
        estimator = std::make_unique<detail::SureEstimator>(bank, frame, s, weightPtr);
    }
    detail::Estimates estimates = detail::estimateMembers(*estimator, n, work, memberUnits);

    // Per-pixel choice, among all the members or, with a shortlist, first among all by their
    // one-sided maps and then among the shortlist filtered on B too.
    const Image noise = s.temperature > 0.0
                            ? detail::noiseLevel(*estimator, region, weight, s.window, work)
                            : Image{};
    std::vector<std::size_t> candidates(n);
    std::iota(candidates.begin(), candidates.end(), std::size_t(0));
    detail::Choice chosen = detail::choose(estimates, candidates, !s.shortlisted, s, noise, work);
    if (s.shortlisted) {
        candidates = detail::shortlistOf(chosen, std::size_t(s.shortlist));
        detail::filterShortlistOnB(*halves, candidates, stacking, estimates, work, memberUnits);
        chosen = detail::choose(estimates, candidates, true, s, noise, work);
    }

    // Feathering.
    std::vector<Image>& planes = chosen.planes;
    if (s.feather > 0)
        detail::featherWeights(planes, bank, s.feather, s.featherGate, s.exposure, work);

    // Blend.
    detail::Blend blend = detail::blend(planes, bank, work);
    AutoResult result;
    result.composite = std::move(blend.composite);
    result.choice = std::move(blend.choice);
    result.estimatedMse = estimates.estimatedMse;
    std::size_t best = candidates.front();
    for (std::size_t m : candidates)
        if (estimates.estimatedMse[m] < estimates.estimatedMse[best]) best = m;
    result.bestMember = int(best);
    for (char a : estimates.analytic) result.analytic.push_back(a != 0);
    result.estimator = s.estimator;

    // Stacking.
    if (stacking) {
        detail::Stacked stacked =
            detail::stack(result.composite, planes, blend.order, bank, frame, *halves, s, work);
        result.composite = std::move(stacked.composite);
        result.stacked = stacked.members;
        result.stackFeatures = stacked.features;
    }
    for (int m : blend.order) result.layers.push_back({m, std::move(planes[std::size_t(m)])});
    return result;
}

}  // namespace

AutoResult autoComposite(const FilterBank& bank, const FrameBuffers& frame,
                         const AutoOptions& options) {
    const detail::AutoSettings settings = detail::resolveSettings(bank, frame, options);
    WorkContext work(options.progress);
    work.expectWork(expectedWork(settings, bank.size(), bank.region().height()));
    try {
        work.addWork(0);  // the first report, at 0: a callback can stop before any work
        AutoResult result = runStages(bank, frame, settings, work);
        work.throwIfCancelled();
        work.finish();
        return result;
    } catch (const Error& e) {
        if (e.kind() == ErrorKind::Cancelled)
            throw Error(ErrorKind::Cancelled, "auto composite cancelled");
        throw;
    }
}

}  // namespace glint::denoise
