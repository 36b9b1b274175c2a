// glint::render::MltSettings — parameters of the Metropolis integrator (`--set integrator=mlt`).
#pragma once

#include <cstdint>

namespace glint::render {

/// Primary-sample-space Metropolis light transport (Kelemen et al. 2002) parameters. The
/// mutation probabilities are relative weights (normalised by their sum); the budget is
/// Settings::spp × pixels mutations, split evenly over the chains.
struct MltSettings {
    double largeStep = 0.25;  ///< weight of large steps (fresh uniform primary sample)
    double smallStep = 0.55;  ///< weight of small steps (perturb every coordinate)
    double lens = 0.10;       ///< weight of lens perturbations (film xy and lens uv only)
    double light = 0.10;      ///< weight of light perturbations (light-sampling numbers only)
    /// Kelemen's small-step sizes: perturbations log-uniform in [s1, s2] (unit interval).
    double s1 = 1.0 / 1024.0, s2 = 1.0 / 64.0;
    /// Lens perturbation sizes on the image plane, in pixels.
    double lensS1 = 0.5, lensS2 = 24.0;
    /// Light perturbation sizes of the light-selection and light-point numbers (unit interval).
    double lightS1 = 1.0 / 256.0, lightS2 = 1.0 / 8.0;
    std::int64_t bootstrap = 100000;  ///< uniform paths that estimate b and seed the chains
    int chains = 512;                 ///< independent Markov chains
    int groups = 16;     ///< batches of chains for the batch-means variance (divides chains)
    int featureSpp = 4;  ///< spp of the path-traced pass that provides the feature layers
};

/// Throws glint::Error(InvalidArgument) naming the first out-of-range Metropolis parameter.
void validateMlt(const MltSettings& mlt);

}  // namespace glint::render
