// How long the UI thread was busy without returning to its event loop: a 2 ms timer on the UI
// thread, and the longest gap between its firings minus the period. Shared by the studio's stall
// test (tests/gui/model_test.cpp) and its speed benchmark (tests/perf/bench_studio.cpp).
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

#include <algorithm>

namespace glint::studio::testing {

class StallMonitor : public QObject {
  public:
    StallMonitor() {
        m_timer.setInterval(kPeriodMs);
        m_timer.setTimerType(Qt::PreciseTimer);
        connect(&m_timer, &QTimer::timeout, this, [this] {
            const double now = double(m_clock.nsecsElapsed()) * 1e-6;
            if (m_last >= 0.0) m_worst = std::max(m_worst, now - m_last - kPeriodMs);
            m_last = now;
        });
    }
    /// Starts measuring (from no stall).
    void start() {
        m_worst = 0.0;
        m_last = -1.0;
        m_clock.start();
        m_timer.start();
    }
    /// Stops; the longest stall since start() in milliseconds.
    double stop() {
        m_timer.stop();
        return std::max(0.0, m_worst);
    }

  private:
    static constexpr int kPeriodMs = 2;
    QTimer m_timer;
    QElapsedTimer m_clock;
    double m_last = -1.0, m_worst = 0.0;
};

}  // namespace glint::studio::testing
