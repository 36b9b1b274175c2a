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

void RemainingTime::reset() {
    *this = RemainingTime();
}

std::optional<double> RemainingTime::update(int passesDone, double fraction, double seconds) {
    const std::optional<double> overall = remainingSeconds(fraction, passesDone, seconds);
    if (!overall) return std::nullopt;  // before the first pass is done, or all done
    if (!m_haveBase) {
        m_haveBase = true;
        m_baseFraction = fraction;
        m_baseSeconds = seconds;
    }
    // The rate since the first pass ended, once some work was measured after it.
    double estimate = *overall;
    const double measured = fraction - m_baseFraction;
    if (measured > 1e-9 && seconds > m_baseSeconds)
        estimate = (seconds - m_baseSeconds) / measured * (1.0 - fraction);
    // Never up: a user reads a rising time left as the render going wrong.
    if (m_shown) estimate = std::min(estimate, *m_shown);
    m_shown = estimate;
    return m_shown;
}

QString formatRemaining(double seconds) {
    const auto tr = [](const char* s) { return QCoreApplication::translate("RenderBar", s); };
    if (seconds < 90.0) return tr("~%1 s left").arg(std::max(1, int(std::lround(seconds))));
    if (seconds < 90.0 * 60.0) return tr("~%1 min left").arg(int(std::lround(seconds / 60.0)));
    return tr("~%1 h left").arg(seconds / 3600.0, 0, 'f', 1);
}

QString formatSamplesLeft(int spp, int totalSpp, double secondsLeft) {
    const QString samples =
        QCoreApplication::translate("RenderBar", "%1 / %2 spp").arg(spp).arg(totalSpp);
    return secondsLeft >= 0.0 ? samples + QStringLiteral(" · ") + formatRemaining(secondsLeft)
                              : samples;
}

}  // namespace glint::studio
