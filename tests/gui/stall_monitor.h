// How long the UI thread was busy without returning to its event loop: a 2 ms timer on the UI
// thread, and the longest gap between its firings minus the period. On a machine whose cores
// other processes (or the studio's own workers) keep busy, a gap also holds the time the UI
// thread waited for a core: the CPU time the UI thread itself used within the gap (its thread
// CPU clock) tells the two apart. Used by the studio's speed benchmark
// (lab/bench/bench_studio.cpp) only: a unit test asserts no time.
#pragma once

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

#include <algorithm>

#include <time.h>

namespace glint::studio::testing {

class StallMonitor : public QObject {
  public:
    StallMonitor() {
        m_timer.setInterval(kPeriodMs);
        m_timer.setTimerType(Qt::PreciseTimer);
        connect(&m_timer, &QTimer::timeout, this, [this] { sample(); });
    }
    /// Starts measuring (from no stall).
    void start() {
        m_worst = 0.0;
        m_worstBusy = 0.0;
        // The stretch before the first firing counts too.
        m_clock.start();
        m_last = 0.0;
        m_lastCpu = threadCpuMs();
        m_timer.start();
    }
    /// Stops; the longest stall since start() in milliseconds (the longest gap).
    double stop() {
        sample();  // and the stretch after the last firing
        m_timer.stop();
        return std::max(0.0, m_worst);
    }
    /// After stop(): the most CPU time the UI thread used between two firings, in milliseconds
    /// (the stall without the time spent waiting for a core).
    double busy() const { return m_worstBusy; }

  private:
    static constexpr int kPeriodMs = 2;
    // A firing (or the end): the gap since the previous one, and the UI thread's CPU time in it.
    void sample() {
        const double now = double(m_clock.nsecsElapsed()) * 1e-6;
        const double cpu = threadCpuMs();
        m_worst = std::max(m_worst, now - m_last - kPeriodMs);
        m_worstBusy = std::max(m_worstBusy, cpu - m_lastCpu);
        m_last = now;
        m_lastCpu = cpu;
    }
    static double threadCpuMs() {
        timespec t{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
        return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
    }
    QTimer m_timer;
    QElapsedTimer m_clock;
    double m_last = -1.0, m_worst = 0.0;
    double m_lastCpu = 0.0, m_worstBusy = 0.0;
};

}  // namespace glint::studio::testing
