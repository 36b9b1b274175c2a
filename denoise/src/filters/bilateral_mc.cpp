// bilateral-mc — the fast bilateral filter of Banterle et al. 2012, "A Low-Memory,
// Straightforward and Fast Bilateral Filter Through Subsampling in Spatial Domain".
//
// The bilateral estimator of "bilateral" (same weights, same window) is evaluated on a subset of
// the N x N window (N = 2 radius + 1): 64 sampling patterns of k N offsets are precomputed per
// call, and each pixel uses one of them chosen by a hash of its position and the seed, so the
// result is deterministic and a region of interest matches the full frame. Patterns always hold
// the centre pixel; with k >= N the pattern is the whole window and the filter equals
// "bilateral". The paper uses Poisson-disk patterns (Bridson 2007); the other kinds are there
// to compare against (docs/denoise.md has the accuracy-versus-samples table).
//
// Parameters:
//   sigmaS          spatial standard deviation (px), 1e-6 … 1e6 (log)
//   sigmaR          range standard deviation, 1e-6 … 1e6 (log)
//   radius          window radius, 0 … 100; 0 = ceil(3 sigmaS)
//   samplesPerSide  k: samples per pixel = k N (the paper uses N … 3N), 1 … 256
//   pattern         0 = poisson (Bridson), 1 = regular grid, 2 = uniform random,
//                   3 = stratified jitter
//   seed            pattern generation and per-pixel choice, 0 … 1e9
#include "filters/bilateral_mc.h"

#include <algorithm>
#include <cmath>

#include "filters/bilateral.h"
#include "filters/bilateral_kernel.h"
#include "filters/factories.h"
#include "filters/filter_util.h"
#include "filters/poisson_disk.h"

namespace glint::denoise {

namespace {

constexpr std::string_view kDescription =
    "bilateral-mc: Monte Carlo bilateral (Banterle et al. 2012): each pixel evaluates the "
    "bilateral sum on one of 64 precomputed k*N-sample patterns of its N x N window (Poisson-disk "
    "by Bridson's algorithm; regular, random and stratified for comparison). k >= N is exact.";

}  // namespace

BilateralMcFilter::BilateralMcFilter() : m_params(bilateralParamSpecs()) {
    m_params[0] = m_params[0].soft(1.0, 12.0);  // sigmaS: the sampled window makes wide ones cheap
    m_params.push_back({"samplesPerSide", "samples per kernel side (k)", 1, 256, 3,
                        ParamScale::Linear, true,
                        "Samples per pixel are k N for an N x N window (N = 2 radius + 1)."});
    m_params.back() = m_params.back().soft(1, 4);
    m_params.push_back(ParamSpec::choice(
        "pattern", "pattern kind", {"poisson", "regular", "random", "stratified"}, 0,
        "Window subset: Poisson disk (Bridson), regular grid, uniform random, stratified."));
    m_params.push_back(ParamSpec{"seed", "seed", 0, 1e9, 1, ParamScale::Linear, true,
                                 "Seed of the patterns and of the per-pixel pattern choice."}
                           .soft(1, 1));
}

std::string_view BilateralMcFilter::description() const {
    return kDescription;
}

int BilateralMcFilter::margin(const ParamValues& params) const {
    return bilateralRadius(detail::paramValue(params, "sigmaS"),
                           detail::paramInt(params, "radius"));
}

Image BilateralMcFilter::apply(const FrameBuffers& frame, const ParamValues& params,
                               const Rect& roi, WorkContext& work) const {
    const int radius = margin(params);
    const int side = 2 * radius + 1;
    const auto kind = detail::PatternKind(detail::paramInt(params, "pattern"));
    const auto seed = std::uint64_t(detail::paramInt(params, "seed"));
    const int count = int(std::min<long long>(
        1LL * detail::paramInt(params, "samplesPerSide") * side, 1LL * side * side));
    // Precompute the patterns (Banterle et al. 2012, Sec. 3), in parallel.
    std::vector<detail::BilateralPattern> patterns(kBilateralMcPatterns);
    work.parallelFor(
        0, kBilateralMcPatterns,
        [&](int i) {
            patterns[std::size_t(i)] = detail::makeWindowPattern(
                kind, radius, count, seed * 1000003ull + std::uint64_t(i));
        },
        0);
    return detail::bilateralSampled(frame.color(), roi, radius,
                                    detail::paramValue(params, "sigmaS"),
                                    detail::paramValue(params, "sigmaR"), patterns, seed, work);
}

std::unique_ptr<Filter> makeBilateralMcFilter() {
    return std::make_unique<BilateralMcFilter>();
}

}  // namespace glint::denoise
