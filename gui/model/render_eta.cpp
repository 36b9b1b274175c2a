#include "model/render_eta.h"

#include <QCoreApplication>

#include <algorithm>
#include <cmath>

namespace glint::studio {

std::optional<double> remainingSeconds(double fraction, int passesDone, double seconds) {
    // The first pass includes the start-up: no estimate before it is done.
    if (passesDone <= 0 || !(fraction > 0.0) || fraction >= 1.0 || !(seconds > 0.0))
        return std::nullopt;
    // Render time grows linearly with the work done (passes have the same cost).
    return seconds * (1.0 - fraction) / fraction;
}

QString formatRemaining(double seconds) {
    const auto tr = [](const char* s) { return QCoreApplication::translate("RenderBar", s); };
    if (seconds < 90.0) return tr("~%1 s left").arg(std::max(1, int(std::lround(seconds))));
    if (seconds < 90.0 * 60.0) return tr("~%1 min left").arg(int(std::lround(seconds / 60.0)));
    return tr("~%1 h left").arg(seconds / 3600.0, 0, 'f', 1);
}

}  // namespace glint::studio
