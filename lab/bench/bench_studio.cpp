// The studio's speed, instrumented (docs/studio.md, "Speed"): time from opening scenes/cornell
// to the first image on screen; from a look change to the denoised new image on screen (16 spp,
// one layer applied everywhere); from a brush dab to the screen at 1024×1024; and the longest
// time the UI thread was busy in each phase (a 2 ms timer that fires late tells), the heavy
// actions at 1024×1024 (magic wand, Everywhere, navigation build, save, autosave restore, region
// render, change map, variance map, export) included. Prints a table and one JSON object. The
// studio's "≤ 50 ms" stall target (docs/studio.md, "Speed") is checked here, by reading, never by a
// test. First of all, the time from a 16-spp 512² render's end to its first denoised image on
// screen (issue 46's goal, ≤ 1.5 s; --first-denoise measures only that).
//   QT_QPA_PLATFORM=offscreen build/bin/bench_studio [--repeats N] [--first-denoise]
#include <QApplication>
#include <QElapsedTimer>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "glint/image/io.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "heavy_actions.h"
#include "stall_monitor.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/paint_view.h"
#include "views/tune_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double maximum(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

// Milliseconds until `done()` holds and the canvas has painted since.
double untilPainted(MainWindow& w, const QElapsedTimer& t, const std::function<bool()>& done) {
    bool painted = false;
    auto c =
        QObject::connect(w.viewer()->canvas(), &ImageCanvas::painted, [&] { painted = done(); });
    waitFor([&] { return painted; }, 60000);
    QObject::disconnect(c);
    return double(t.nsecsElapsed()) * 1e-6;
}

// The first denoise (issue 46): a 16-spp 512² Cornell box opened with the default layer on (the
// learned filter where it runs, model/first_denoise.h); milliseconds from the finished render
// (the document's final frame) to the session started on it, to the default layer in the session
// (its output computed) and to its denoised image painted on screen, once per window.
struct FirstDenoise {
    std::vector<double> session, layer, screen;
    std::string filter;  // the default layer's
};

FirstDenoise firstDenoiseTimes(const QTemporaryDir& tmp, int repeats) {
    const QString scene = writeCornell(tmp.filePath(QStringLiteral("first")), 512, 512, 16);
    FirstDenoise out;
    for (int r = 0; r < repeats; ++r) {
        auto w = makeWindow(tmp.filePath(QStringLiteral("autosave-first%1").arg(r)), true);
        w->resize(1400, 900);
        QTest::qWait(200);
        QElapsedTimer t;
        bool rendered = false;
        double session = -1.0, layer = -1.0;
        SessionAdapter* s = w->session();
        auto c1 = QObject::connect(w->document(), &Document::frameChanged, [&](bool final) {
            if (final && !rendered) {
                t.start();
                rendered = true;
            }
        });
        auto c2 = QObject::connect(s, &SessionAdapter::sessionReset, [&] {
            if (rendered && session < 0.0) session = double(t.nsecsElapsed()) * 1e-6;
        });
        auto c3 = QObject::connect(s, &SessionAdapter::layersChanged, [&] {
            if (rendered && layer < 0.0 && s->hasSession() && s->session().layerCount() == 1)
                layer = double(t.nsecsElapsed()) * 1e-6;
        });
        w->openFile(scene);
        out.screen.push_back(untilPainted(*w, t, [&] {
            return rendered && s->hasSession() && s->session().layerCount() == 1 && !s->busy() &&
                   s->input() == w->document()->finishedFrame();
        }));
        out.session.push_back(session);
        out.layer.push_back(layer);
        for (const auto& c : {c1, c2, c3}) QObject::disconnect(c);
        out.filter = s->session().layer(0).filter;
        w->close();
    }
    return out;
}

}  // namespace

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintBench"));
    QStandardPaths::setTestModeEnabled(true);
    int repeats = 7;
    bool firstOnly = false;
    for (int i = 1; i < argc; ++i) {
        if (i + 1 < argc && std::strcmp(argv[i], "--repeats") == 0)
            repeats = std::max(1, std::atoi(argv[i + 1]));
        if (std::strcmp(argv[i], "--first-denoise") == 0) firstOnly = true;
    }
    QTemporaryDir tmp;

    // 0. A new render's first denoised image on screen (goal: ≤ 1.5 s after a 16-spp 512² render).
    const FirstDenoise first = firstDenoiseTimes(tmp, std::min(repeats, 5));
    std::printf("%-58s %8.0f ms %7.0f ms  (%s)\n",
                "16-spp 512^2 render -> first denoised image on screen", median(first.screen),
                maximum(first.screen), first.filter.c_str());
    std::printf("%-58s %8.0f ms %7.0f ms\n", "  of which: render -> session started",
                median(first.session), maximum(first.session));
    std::printf("%-58s %8.0f ms %7.0f ms\n", "  render -> default layer in the session",
                median(first.layer), maximum(first.layer));
    std::fflush(stdout);
    if (firstOnly) {
        std::printf(
            "{\"firstDenoiseMedianMs\": %.1f, \"firstDenoiseMaxMs\": %.1f, "
            "\"firstSessionMedianMs\": %.1f, \"firstLayerMedianMs\": %.1f, "
            "\"firstDenoiseFilter\": \"%s\"}\n",
            median(first.screen), maximum(first.screen), median(first.session), median(first.layer),
            first.filter.c_str());
        return 0;
    }
    StallMonitor monitor;
    const QString cornell = QDir(sourceDir()).filePath(QStringLiteral("scenes/cornell/scene.json"));

    // 1. Open scenes/cornell: the first pass on screen, then the 16-spp render and its session.
    auto w = makeWindow(tmp.filePath(QStringLiteral("autosave")));
    w->resize(1400, 900);
    QTest::qWait(200);
    monitor.start();
    QElapsedTimer t;
    t.start();
    w->openFile(cornell);
    const double firstImage =
        untilPainted(*w, t, [&] { return w->viewer()->canvas()->hasImage(); });
    waitIdle(*w);
    const double fullRender = double(t.nsecsElapsed()) * 1e-6;
    const double openStall = monitor.stop();

    // 2. Look changes with one layer (bilateral, weight 1 everywhere) to re-apply each time.
    w->setStage(2);
    w->tuneView()->setFilter("bilateral");
    w->tuneView()->choose(true);
    waitFor([&] { return w->session()->session().layerCount() == 1; });
    waitIdle(*w);
    const std::string wall = firstAlbedoMaterial(*w->document());
    std::vector<double> lookTimes;
    monitor.start();
    for (int r = 0; r < repeats; ++r) {
        const FramePtr before = w->document()->finishedFrame();
        t.restart();
        w->lookPanel()->edit(wall, "albedo", {0.2 + 0.1 * (r % 7), 0.5, 0.4});
        lookTimes.push_back(untilPainted(*w, t, [&] {
            FramePtr now = w->document()->finishedFrame();
            return now != before && w->session()->input() == now && !w->session()->busy();
        }));
    }
    const double lookStall = monitor.stop();

    // 3. Dabs on a 1024×1024 render with one layer, brush 64 px, the image fitted to the window.
    const QString big = tmp.filePath(QStringLiteral("big.exr"));
    {
        const QString scene = writeCornell(tmp.filePath(QStringLiteral("big")), 1024, 1024, 1);
        render::Renderer renderer(render::loadScene(scene.toStdString()));
        render::Settings s = renderer.scene().settings();
        s.spp = 1;
        writeExr(renderer.render(s).frame, big.toStdString());
    }
    monitor.start();
    w->openFile(big);
    waitIdle(*w);
    w->setStage(2);
    w->tuneView()->setFilter("gaussian");
    w->tuneView()->choose(false);
    waitFor([&] { return w->session()->session().layerCount() == 1; });
    waitIdle(*w);
    const double bigStall = monitor.stop();
    w->setStage(3);
    w->paintView()->setBrushSize(64.0);
    ImageCanvas* canvas = w->viewer()->canvas();
    QTest::qWait(100);
    std::vector<double> dabTimes;
    monitor.start();
    for (int stroke = 0; stroke < 4; ++stroke) {
        const double y = 200.0 + 200.0 * stroke;
        QTest::mousePress(canvas, Qt::LeftButton, {}, canvas->toWidget(QPointF(100, y)).toPoint());
        for (int k = 1; k <= 50; ++k) {
            // Each move is 16 px: one dab of the 64-px brush.
            const QPoint at = canvas->toWidget(QPointF(100 + 16.0 * k, y)).toPoint();
            t.restart();
            QTest::mouseMove(canvas, at, 0);
            dabTimes.push_back(untilPainted(*w, t, [] { return true; }));
        }
        QTest::mouseRelease(canvas, Qt::LeftButton, {},
                            canvas->toWidget(QPointF(900, y)).toPoint());
    }
    const double dabStall = monitor.stop();

    // 4. The heavy actions at 1024×1024 (tests/gui/heavy_actions.h), each to completion: the
    // longest gap of each and the UI thread's own CPU time in its longest busy stretch (-1: it
    // did not finish).
    struct Stall {
        double gap = -1.0, busy = -1.0;
    };
    auto stallOf = [&](const std::function<bool()>& action) {
        monitor.start();
        const bool done = action();
        const double gap = monitor.stop();
        return done ? Stall{gap, monitor.busy()} : Stall{};
    };
    const Stall wandStall = stallOf([&] { return wandClick(*w); });
    const Stall everywhereStall = stallOf([&] { return everywhereClick(*w); });
    w->region()->setPolygon({{256, 256}, {768, 256}, {768, 768}, {256, 768}});
    const Stall navigateStall = stallOf([&] { return navigateBuild(*w, 4); });
    QElapsedTimer saving;
    saving.start();
    const Stall saveStall = stallOf(
        [&] { return saveSession(*w, tmp.filePath(QStringLiteral("s/big.glint-session.json"))); });
    const double saveMs = double(saving.nsecsElapsed()) * 1e-6;  // the session locked meanwhile
    copyAsCrashed(*w, tmp.filePath(QStringLiteral("crashed")));
    auto again = makeWindow(tmp.filePath(QStringLiteral("crashed")));
    const Stall restoreStall = stallOf([&] { return restore(*again); });
    again->close();

    // 5. The actions of a 1024×1024 scene (at 1 spp, one Gaussian layer): a region render merged
    // into the frame, the change map, the bank's variance map (after a navigation build over a
    // 512² region) and an EXR export. Formerly asserted by a unit test (Studio.Stall), which a
    // loaded machine failed: measured here, never asserted.
    auto scene = makeWindow(tmp.filePath(QStringLiteral("autosave-scene")));
    openWithLayer(*scene, writeCornell(tmp.filePath(QStringLiteral("big-scene")), 1024, 1024, 1));
    scene->region()->setPolygon({{256, 256}, {768, 256}, {768, 768}, {256, 768}});
    const Stall regionStall = stallOf([&] { return regionRender(*scene, 2); });
    const Stall changeStall = stallOf([&] { return changeMap(*scene); });
    navigateBuild(*scene, 4);
    const Stall varianceStall = stallOf([&] { return varianceMap(*scene); });
    const Stall exportStall =
        stallOf([&] { return exportExr(*scene, tmp.filePath(QStringLiteral("out/big.exr"))); });
    scene->close();

    std::printf("Glint Studio, %s platform, 2 threads of this machine\n",
                qPrintable(QGuiApplication::platformName()));
    std::printf("%-58s %10s %10s\n", "what", "median", "max");
    std::printf("%-58s %8.0f ms %8s\n", "open scenes/cornell -> first image on screen", firstImage,
                "");
    std::printf("%-58s %8.0f ms %8s\n", "open scenes/cornell -> 16-spp render and session ready",
                fullRender, "");
    std::printf("%-58s %8.0f ms %7.0f ms\n", "look change -> denoised new image on screen (16 spp)",
                median(lookTimes), maximum(lookTimes));
    std::printf("%-58s %8.1f ms %7.1f ms\n", "brush dab -> screen, 1024x1024, brush 64 px",
                median(dabTimes), maximum(dabTimes));
    std::printf("%-58s %8.0f ms / %.0f ms / %.0f ms / %.0f ms\n",
                "longest UI-thread stall: open / look / 1024^2 open+layer / paint", openStall,
                lookStall, bigStall, dabStall);
    std::printf("%-58s %8.0f ms / %.0f ms / %.0f ms / %.0f ms\n",
                "longest UI-thread stall, 1024^2: wand / navigate build / save / restore",
                wandStall.gap, navigateStall.gap, saveStall.gap, restoreStall.gap);
    std::printf("%-58s %8.0f ms / %.0f ms / %.0f ms / %.0f ms\n",
                "  of which UI-thread CPU time: wand / navigate / save / restore", wandStall.busy,
                navigateStall.busy, saveStall.busy, restoreStall.busy);
    std::printf("%-58s %8.0f ms\n", "save session, 1024^2 -> written (painting waits)", saveMs);
    std::printf("%-58s %8.0f ms (of which UI-thread CPU time %.0f ms)\n",
                "longest UI-thread stall, 1024^2: Everywhere", everywhereStall.gap,
                everywhereStall.busy);
    std::printf("%-58s %8.0f ms / %.0f ms / %.0f ms / %.0f ms\n",
                "longest UI-thread stall, 1024^2: region / change map / variance / export",
                regionStall.gap, changeStall.gap, varianceStall.gap, exportStall.gap);
    std::printf("%-58s %8.0f ms / %.0f ms / %.0f ms / %.0f ms\n",
                "  of which UI-thread CPU time: region / change / variance / export",
                regionStall.busy, changeStall.busy, varianceStall.busy, exportStall.busy);
    std::printf(
        "{\"firstImageMs\": %.1f, \"renderReadyMs\": %.1f, \"lookMedianMs\": %.1f, \"lookMaxMs\": "
        "%.1f, "
        "\"dabMedianMs\": %.2f, \"dabMaxMs\": %.2f, \"stallOpenMs\": %.1f, \"stallLookMs\": %.1f, "
        "\"stallBigOpenMs\": %.1f, \"stallPaintMs\": %.1f, \"stallWandMs\": %.1f, "
        "\"stallNavigateMs\": %.1f, \"stallSaveMs\": %.1f, \"stallRestoreMs\": %.1f, "
        "\"busyWandMs\": %.1f, \"busyNavigateMs\": %.1f, \"busySaveMs\": %.1f, "
        "\"busyRestoreMs\": %.1f, \"stallRegionMs\": %.1f, \"stallChangeMapMs\": %.1f, "
        "\"stallVarianceMs\": %.1f, \"stallExportMs\": %.1f, \"busyRegionMs\": %.1f, "
        "\"busyChangeMapMs\": %.1f, \"busyVarianceMs\": %.1f, \"busyExportMs\": %.1f, "
        "\"stallEverywhereMs\": %.1f, \"busyEverywhereMs\": %.1f, \"saveMs\": %.1f}\n",
        firstImage, fullRender, median(lookTimes), maximum(lookTimes), median(dabTimes),
        maximum(dabTimes), openStall, lookStall, bigStall, dabStall, wandStall.gap,
        navigateStall.gap, saveStall.gap, restoreStall.gap, wandStall.busy, navigateStall.busy,
        saveStall.busy, restoreStall.busy, regionStall.gap, changeStall.gap, varianceStall.gap,
        exportStall.gap, regionStall.busy, changeStall.busy, varianceStall.busy, exportStall.busy,
        everywhereStall.gap, everywhereStall.busy, saveMs);
    w->close();
    return 0;
}
