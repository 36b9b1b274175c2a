// The actions whose work grows with the image (a region render merged into the frame, the magic
// wand, the change map, a navigation bank and its variance map, save, export, restoring an
// autosave), driven at 1024×1024, never stall the UI thread: a 2 ms timer on the UI thread
// records the longest gap between its firings while each action runs to completion
// (StallMonitor, the method of tests/perf/bench_studio.cpp).
//
// Tolerance: 50 ms, the bound (docs/studio.md, "Speed"). Unit tests here normally assert
// no timing; this one is what issue 33 asks for, so it is made robust: the work itself runs on
// workers, and what is left on the UI thread (applying a result, an undo step, painting) is a
// few milliseconds, an order of magnitude under the bound. Actions whose first run includes a
// one-time warm-up run twice and the better run counts (see kRuns below); the others count once.
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <functional>

#include "heavy_actions.h"
#include "model_test.h"
#include "stall_monitor.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

constexpr double kToleranceMs = 50.0;

// The longest stall of `action` over `runs` runs (the best run), and whether every run finished.
struct Stall {
    double ms = 0.0;
    bool done = true;
};

Stall measure(int runs, const std::function<bool(int run)>& action) {
    StallMonitor monitor;
    Stall best{1e9, true};
    for (int r = 0; r < runs; ++r) {
        monitor.start();
        const bool done = action(r);
        const double ms = monitor.stop();
        best.done = best.done && done;
        best.ms = std::min(best.ms, ms);
        qInfo("  run %d: longest stall %.1f ms", r + 1, ms);
    }
    return best;
}

}  // namespace

class StallTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;

    void check(const char* what, const Stall& stall) {
        qInfo("%s: longest UI-thread stall %.1f ms (tolerance %.0f ms)", what, stall.ms,
              kToleranceMs);
        QVERIFY2(stall.done, what);
        QVERIFY2(stall.ms <= kToleranceMs,
                 qPrintable(QStringLiteral("%1 stalled the UI thread for %2 ms")
                                .arg(QLatin1String(what))
                                .arg(stall.ms, 0, 'f', 1)));
    }

  private slots:
    void heavyActionsNeverStallTheUiThreadAt1024() {
        QVERIFY(m_dir.isValid());
        const QString scene = writeCornell(m_dir.filePath(QStringLiteral("big")), 1024, 1024, 1);
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave")));
        QVERIFY(openWithLayer(*w, scene));
        // Navigation over a 512² region keeps the bank's build short; its overlay is frame-sized.
        w->region()->setPolygon({{256, 256}, {768, 256}, {768, 768}, {256, 768}});

        // Runs per action: two where the first run pays a one-time cost on the UI thread (the
        // first overlay drawn over the canvas, the first bank's previews), one elsewhere.
        check("region render merged into the frame",
              measure(1, [&](int r) { return regionRender(*w, 2 + std::uint64_t(r)); }));
        check("magic wand", measure(1, [&](int) { return wandClick(*w); }));
        check("change map", measure(2, [&](int) { return changeMap(*w); }));
        check("navigation bank build", measure(2, [&](int r) { return navigateBuild(*w, 4 + r); }));
        check("bank variance map", measure(2, [&](int) { return varianceMap(*w); }));
        check("session save", measure(1, [&](int r) {
                  return saveSession(
                      *w, m_dir.filePath(QStringLiteral("s%1/big.glint-session.json").arg(r)));
              }));
        check("export EXR", measure(1, [&](int r) {
                  return exportExr(*w, m_dir.filePath(QStringLiteral("out/big-%1.exr").arg(r)));
              }));

        // Restoring: the journal of this studio, as if it had crashed, into a second one.
        const QString crashed = m_dir.filePath(QStringLiteral("crashed"));
        QVERIFY(copyAsCrashed(*w, crashed));
        auto again = makeWindow(crashed);
        check("autosave restore", measure(1, [&](int) { return restore(*again); }));
        QCOMPARE(again->session()->session().layerCount(), w->session()->session().layerCount());
    }
};

std::unique_ptr<QObject> makeStallTest() {
    return std::make_unique<StallTest>();
}

#include "stall_test.moc"
