// The time a running render has left, estimated from what it has done so far. No widgets here.
#pragma once

#include <optional>

#include <QString>

namespace glint::studio {

/// Seconds left of a render that did `fraction` of its work in `seconds` of render time (the
/// time paused not counted), once it has an estimate: a pass done (`passesDone` > 0) and some
/// work left; nullopt before.
std::optional<double> remainingSeconds(double fraction, int passesDone, double seconds);

/// "~12 s left", "~4 min left", "~2 h left".
QString formatRemaining(double seconds);

}  // namespace glint::studio
