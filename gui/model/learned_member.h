// The learned filter in the studio: `unet`, Open Image Denoise's network run natively
// (docs/learned.md). Whether it can run here — its weights present and intact — is asked once per
// process, on a worker started early, so that the first render's denoise and the studio's banks
// (Navigate pins its preview) know without stalling the UI thread. No widgets here.
#pragma once

#include <string>
#include <vector>

namespace glint::studio {

/// The registry name of the learned filter.
inline constexpr const char* kLearnedFilter = "unet";

/// Starts finding out whether the learned filter runs here, on a worker (a no-op once started).
void probeLearnedFilter();
/// Empty when the learned filter runs here, else why not (the missing or corrupt weights, as the
/// filter says it in one line). Probes on the first call (a 16×16 frame with and without albedo
/// and normal, so both sets of weights are read and checked) and remembers the answer; waits for
/// a probe probeLearnedFilter() started. Thread-safe.
const std::string& learnedFilterUnavailable();
/// True when learnedFilterUnavailable() is empty.
bool learnedFilterAvailable();

/// The filters of the studio's banks (Navigate and Auto Start share one bank, so they name the
/// same): empty — the default bank — when it holds the learned filter or the learned filter does
/// not run here; else the default bank's filters and the learned filter (its one member).
std::vector<std::string> studioBankFilters();

}  // namespace glint::studio
