// The time a running render has left, estimated from what it has done so far. No widgets here.
#pragma once

#include <optional>

#include <QString>

namespace glint::studio {

/// Seconds left of a render that did `fraction` of its work in `seconds` of render time (the
/// time paused not counted), once it has an estimate: a pass done (`passesDone` > 0) and some
/// work left; nullopt before.
std::optional<double> remainingSeconds(double fraction, int passesDone, double seconds);

/// The time left of one render as its progress reports come in: the rate is measured from the end
/// of its first pass on (the first pass carries the start-up, no measure of the rest), and the
/// estimate never goes up while the render runs (a slower stretch — a denoise sharing the cores as
/// the passes double — holds it where it was rather than raising it).
class RemainingTime {
  public:
    /// Forgets the previous render.
    void reset();
    /// The estimate after a report that `passesDone` passes and `fraction` of the work were done
    /// in `seconds` of render time; nullopt until the first pass is done, and once all is.
    std::optional<double> update(int passesDone, double fraction, double seconds);

  private:
    double m_baseFraction = 0.0, m_baseSeconds = 0.0;  // at the first report after pass 1
    bool m_haveBase = false;
    std::optional<double> m_shown;
};

/// "~12 s left", "~4 min left", "~2 h left".
QString formatRemaining(double seconds);

/// "64 / 1024 spp · ~40 s left" (the time left when `secondsLeft` ≥ 0).
QString formatSamplesLeft(int spp, int totalSpp, double secondsLeft);

}  // namespace glint::studio
