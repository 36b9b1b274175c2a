// Keep refining's speed (issue 49's goal: on a 512² scene with 2 threads, the denoised image on
// screen improves at least every 2 s, with no stall of the UI): opens a 512² copy of the Cornell
// box at 16 spp with its default layer (model/first_denoise.h), switches Render ▸ Keep Refining
// on and, for --seconds, records each time the canvas paints a new denoised render (the session's
// input past the last one shown, its layers re-applied), and the longest gap between firings of
// a 2 ms timer on the UI thread (tests/gui/stall_monitor.h). Prints the intervals' median and
// max, the stall, the refreshes of the importance map and one JSON object.
//   QT_QPA_PLATFORM=offscreen build/bin/bench_studio_progressive [--seconds S] [--threads T]
//       [--layer default|bilateral]
#include <QApplication>
#include <QElapsedTimer>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "model/progressive_render.h"
#include "stall_monitor.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintBench"));
    QStandardPaths::setTestModeEnabled(true);
    double seconds = 30.0;
    int threads = 2;
    std::string layer = "default";
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::max(1.0, std::atof(argv[i + 1]));
        if (std::strcmp(argv[i], "--threads") == 0) threads = std::max(1, std::atoi(argv[i + 1]));
        if (std::strcmp(argv[i], "--layer") == 0) layer = argv[i + 1];
    }
    QTemporaryDir tmp;
    const QString scene = writeCornell(tmp.filePath(QStringLiteral("scene")), 512, 512, 16);

    // 1. The scene rendered at 16 spp with its first layer (the default one, or a bilateral).
    const bool defaultLayer = layer == "default";
    auto w = makeWindow(tmp.filePath(QStringLiteral("autosave")), defaultLayer);
    w->resize(1400, 900);
    QTest::qWait(200);
    w->openFile(scene);
    waitFor([&] { return w->document()->kind() == Document::Kind::Scene; });
    render::Settings settings = w->document()->settings();
    settings.threads = threads;
    settings.spp = 16;
    w->document()->setSettings(settings);
    waitIdle(*w);
    if (!defaultLayer) {
        w->setStage(2);
        w->tuneView()->setFilter(layer);
        w->tuneView()->choose(true);
    }
    waitFor([&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); });
    const std::string filter = w->session()->session().layer(0).filter;

    // 2. Keep refining: each new denoised render painted, from the refining render's first (at
    // the bar's spp) on.
    QElapsedTimer clock;
    clock.start();
    std::vector<double> shownAt;
    std::vector<int> shownSpp;
    int lastSpp = 0;
    bool fresh = false;  // the session's input changed and its composite was not painted yet
    SessionAdapter* s = w->session();
    QObject::connect(s, &SessionAdapter::inputChanged, [&] { fresh = true; });
    QObject::connect(w->viewer()->canvas(), &ImageCanvas::painted, [&] {
        if (!fresh || s->busy() || !w->document()->rendering()) return;
        fresh = false;
        const int spp = s->input()->metadata().spp;
        if (spp <= lastSpp) return;
        lastSpp = spp;
        shownAt.push_back(double(clock.nsecsElapsed()) * 1e-9);
        shownSpp.push_back(spp);
    });
    StallMonitor monitor;
    const double load0 = [] {
        double l = 0.0;
        if (FILE* f = std::fopen("/proc/loadavg", "r")) {
            if (std::fscanf(f, "%lf", &l) != 1) l = 0.0;
            std::fclose(f);
        }
        return l;
    }();
    monitor.start();
    w->actions().keepRefining->setChecked(true);
    QTest::qWait(int(seconds * 1000.0));
    const double stall = monitor.stop();
    const double busy = monitor.busy();
    const ProgressiveRender::Handed handed = w->progressive()->lastHanded();
    const int refreshes = handed.refreshes;
    const double autoSeconds = handed.from ? handed.from->seconds : 0.0;
    w->document()->cancelRender();
    waitIdle(*w);

    // The intervals between denoised renders on screen, from the first one of the refinement.
    std::vector<double> intervals;
    for (std::size_t i = 1; i < shownAt.size(); ++i)
        intervals.push_back(shownAt[i] - shownAt[i - 1]);
    const double first = shownAt.empty() ? 0.0 : shownAt.front();
    std::printf(
        "Keep refining, 512^2 Cornell box, 16 spp + refinement, %d threads, layer %s, "
        "%.0f s, load %.2f\n",
        threads, filter.c_str(), seconds, load0);
    std::printf("%-52s %d (%d .. %d spp)\n", "denoised renders shown", int(shownAt.size()),
                shownSpp.empty() ? 0 : shownSpp.front(), shownSpp.empty() ? 0 : shownSpp.back());
    std::printf("%-52s %.2f s\n", "Keep Refining on -> first refined image shown", first);
    std::printf("%-52s %.2f s median, %.2f s max\n", "interval between denoised renders shown",
                percentile(intervals, 0.5), percentile(intervals, 1.0));
    std::printf("%-52s %.0f ms (UI thread CPU %.0f ms)\n", "longest UI-thread stall", stall, busy);
    std::printf("%-52s %d (the last: auto %.2f s)\n", "importance maps from auto's error",
                refreshes, autoSeconds);
    std::printf(
        "{\"shown\": %d, \"firstS\": %.3f, \"intervalMedianS\": %.3f, \"intervalMaxS\": %.3f, "
        "\"stallMs\": %.1f, \"busyMs\": %.1f, \"refreshes\": %d, \"autoS\": %.3f, \"lastSpp\": %d, "
        "\"load\": %.2f, "
        "\"layer\": \"%s\"}\n",
        int(shownAt.size()), first, percentile(intervals, 0.5), percentile(intervals, 1.0), stall,
        busy, refreshes, autoSeconds, lastSpp, load0, filter.c_str());
    w->close();
    return 0;
}
