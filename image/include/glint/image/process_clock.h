// How long this process has run: from its start (exec), which a clock read in main() misses
// (loading the shared libraries, their static constructors). A time limit that covers
// "everything" counts from here (glint-final, docs/final-render.md).
#pragma once

#include <optional>

namespace glint {

/// Seconds since the kernel started this process (Linux: /proc/self/stat's start time against
/// the boot clock, in steps of the clock tick, 10 ms on most systems). nullopt where it cannot
/// be read (another system, no /proc) or reads as negative.
std::optional<double> processAgeSeconds();

}  // namespace glint
