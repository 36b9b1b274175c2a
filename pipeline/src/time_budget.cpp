#include "glint/pipeline/time_budget.h"

namespace glint::pipeline {

TimeBudget::TimeBudget(double limit, double refreshShare, double expectedFinal)
    : m_limit(limit), m_share(refreshShare), m_final(expectedFinal) {}

bool TimeBudget::renderMayContinue(double now) const {
    return !timed() || now + reserve() < m_limit;
}

bool TimeBudget::refreshFits(double now, double seconds) const {
    if (!timed()) return true;
    return m_refreshes + seconds <= m_share * m_limit && now + seconds + reserve() < m_limit;
}

void TimeBudget::refreshed(double seconds, bool finalQuality) {
    m_refreshes += seconds;
    if (finalQuality) m_final = seconds;
}

}  // namespace glint::pipeline
