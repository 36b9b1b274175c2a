// Sampling patterns over a square pixel window: Poisson-disk (Bridson 2007) and, for comparison,
// regular, uniform random and stratified-jitter patterns. Used by "bilateral-mc".
#pragma once

#include <cstdint>
#include <vector>

#include "filters/bilateral_kernel.h"
#include "glint/image/random.h"

namespace glint::denoise::detail {

using glint::SplitMix64;  // the deterministic generator of glint/image/random.h

/// Bridson 2007, "Fast Poisson disk sampling in arbitrary dimensions", on the integer lattice:
/// offsets in [-radius, radius]^2, pairwise distance >= minDistance, grown from (0, 0) with
/// `attempts` candidates per active point drawn uniformly among the lattice points of the
/// annulus [minDistance, 2 minDistance]; stops when every active point is exhausted.
std::vector<Offset> bridsonPoissonDisk(int radius, double minDistance, SplitMix64& rng,
                                       int attempts = 30);

/// How a window subset is chosen.
enum class PatternKind : int { Poisson = 0, Regular = 1, Random = 2, Stratified = 3 };

/// A pattern of about `count` distinct offsets in the (2 radius + 1)^2 window, always holding the
/// centre (0, 0); the full window when count >= (2 radius + 1)^2.
///  Poisson:    Bridson with the disk radius set for ~count points, trimmed to count at random.
///  Regular:    centred g x g grid, g = round(sqrt(count)) (the same for every pattern index).
///  Random:     count distinct lattice points uniformly without replacement.
///  Stratified: ceil(sqrt(count))^2 strata with one jittered point each, trimmed to count.
BilateralPattern makeWindowPattern(PatternKind kind, int radius, int count, std::uint64_t seed);

}  // namespace glint::denoise::detail
