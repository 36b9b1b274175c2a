// How a final render shares its time limit (docs/final-render.md, "Targets"): the render runs
// while the time left exceeds the reserve for the final auto (a margin over its measured time),
// and auto's refreshes during the render take at most a share of the limit. Times are seconds
// since the render started, read from any clock (tests use a fake one).
#pragma once

namespace glint::pipeline {

/// The reserve for the final auto: this many times its measured (or expected) seconds.
inline constexpr double kFinalAutoMargin = 1.25;

/// The schedule of one time-limited final render.
class TimeBudget {
  public:
    /// `limit` seconds in all (0: none, and everything fits); auto's refreshes take at most
    /// `refreshShare` of it; the final auto is expected to take `expectedFinal` seconds (0:
    /// unknown until a refresh at its quality measures it).
    TimeBudget(double limit, double refreshShare, double expectedFinal);

    bool timed() const { return m_limit > 0.0; }
    /// The seconds kept for the final auto: kFinalAutoMargin times its latest measure.
    double reserve() const { return kFinalAutoMargin * m_final; }
    /// Whether the render may go on at `now`: more than the reserve is left.
    bool renderMayContinue(double now) const;
    /// Whether a refresh at `now` expected to take `seconds` fits: the refreshes stay within
    /// their share and the reserve is still left after it.
    bool refreshFits(double now, double seconds) const;
    /// Records a refresh that took `seconds`; `finalQuality`: it ran at the final auto's
    /// quality, so its time is the final auto's new estimate.
    void refreshed(double seconds, bool finalQuality);
    /// What the final auto is expected to take (0: unknown).
    double expectedFinal() const { return m_final; }
    /// The refreshes' seconds so far.
    double refreshSeconds() const { return m_refreshes; }

  private:
    double m_limit, m_share, m_final;
    double m_refreshes = 0.0;
};

}  // namespace glint::pipeline
