// The simulated user of the navigation tree: at each level it picks the option closest to the
// reference (glint-lab navigate --simulate; docs/lab/navigation.md, "The simulated user"). A
// measure of how many choices the gallery needs, not something an artist runs.
#pragma once

#include <vector>

#include "glint/denoise/navigation.h"
#include "glint/image/image.h"

namespace glint::lab {

/// One step of the simulated user: the option picked, its member, and that member's SSIM
/// against the reference over the region.
struct SimulatedChoice {
    int option = -1;
    int member = -1;
    double ssim = 0.0;
};

/// A simulated user who at each level picks the option whose member is closest (SSIM of
/// display values) to `reference` (region-sized, 3 channels), until a member is picked.
/// `images` are the tree's images in full resolution (same order as when it was built).
std::vector<SimulatedChoice> simulateUser(const denoise::NavigationTree& tree,
                                          const std::vector<const Image*>& images,
                                          const Image& reference, float exposure = 0.0f);

}  // namespace glint::lab
