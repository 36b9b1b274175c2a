// Keep refining's speed (issue 49's goal: on a 512² scene with 2 threads, the denoised image on
// screen improves at least every 2 s, with no stall of the UI): opens a 512² copy of the Cornell
// box at 16 spp with its default layer (model/first_denoise.h), switches Render ▸ Keep Refining
// on and, for --seconds, records each time the canvas paints a new denoised render (the session's
// input past the last one shown, its layers re-applied), and the longest gap between firings of
// a 2 ms timer on the UI thread (tests/gui/stall_monitor.h). Prints each interval's parts (the
// wait for the render's pass, the wait for the session, the layers' re-application, the display,
// whether auto's refresh ran meanwhile) and, with --reference, the relMSE of each denoised image
// shown against a high-spp render of the same scene, on 8 × 8 block means less the reference's
// own noise there (improving: falling); then the intervals'
// median and max, the stall, the refreshes of the importance map and one JSON object. --write-scene
// writes the scene (for glint-render to make the reference) and exits. Like the studio, it runs
// itself again with OMP_WAIT_POLICY=PASSIVE unless the variable is set (app/openmp_policy.h):
// OMP_WAIT_POLICY= (empty: libgomp's default spin-then-sleep, with its "Invalid value" warning)
// measures the wait as it was before. --halves on (the studio's default) renders the bar's 16 spp
// with half buffers, so that the toggle goes on from that render (Settings::continueFrom); off
// renders it without, and the toggle renders it again.
//   QT_QPA_PLATFORM=offscreen build/bin/bench_studio_progressive [--seconds S] [--threads T]
//       [--layer default|bilateral] [--halves on|off] [--reference REF.exr] [--write-scene DIR]
#include <QApplication>
#include <QElapsedTimer>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/openmp_policy.h"
#include "bench_options.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "model/progressive_render.h"
#include "stall_monitor.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

/// The side of the blocks relMSE is measured on.
constexpr int kBlock = 8;

/// The means of `image` over kBlock × kBlock blocks.
Image boxMeans(const Image& image) {
    Image out(image.width() / kBlock, image.height() / kBlock, image.channels());
    for (int y = 0; y < out.height() * kBlock; ++y)
        for (int x = 0; x < out.width() * kBlock; ++x)
            for (int c = 0; c < image.channels(); ++c)
                out(x / kBlock, y / kBlock, c) += image(x, y, c) / float(kBlock * kBlock);
    return out;
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

}  // namespace

int main(int argc, char** argv) {
    // As the studio starts (gui/app/main.cpp): OpenMP's passive wait unless the caller set one.
    usePassiveOpenMpWait(argv);
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintBench"));
    QStandardPaths::setTestModeEnabled(true);
    double seconds = 30.0;
    int threads = 2;
    std::string layer = "default";
    std::string referencePath;
    std::string writeScene;
    bool halves = true;  // the render bar's default
    const int bad = glint::bench::parseOptions(
        "bench_studio_progressive", argc, argv,
        [&](const std::string& name, const std::string& value) {
            if (name == "--reference")
                referencePath = value;
            else if (name == "--write-scene")
                writeScene = value;
            else if (name == "--seconds")
                seconds = std::max(1.0, glint::bench::numberOption(name, value));
            else if (name == "--threads")
                threads = std::max(1, glint::bench::intOption(name, value));
            else if (name == "--layer")
                layer = value;
            else if (name == "--halves" && (value == "on" || value == "off"))
                halves = value == "on";
            else
                return false;
            return true;
        });
    if (bad != 0) return bad;
    QTemporaryDir tmp;
    const QString scene = writeCornell(tmp.filePath(QStringLiteral("scene")), 512, 512, 16);
    if (!writeScene.empty()) {
        const QString out = writeCornell(QString::fromStdString(writeScene), 512, 512, 16);
        std::printf("%s\n", out.toStdString().c_str());
        return 0;
    }
    // The reference and its own noise's share of relMSE (the variance of its mean relative to
    // its square, as relMse weighs it): the images' relMSE less it is their error alone.
    // At the scale of kBlock² pixels (box means), where a reference of a few hundred spp is
    // far less noisy than the images measured.
    std::optional<Image> reference;
    double referenceNoise = 0.0;
    if (!referencePath.empty()) {
        const FrameBuffers ref = readExr(referencePath);
        reference = boxMeans(ref.color());
        const Image& r = *reference;
        const Image v = boxMeans(ref.layer(Layer::Variance));
        for (std::size_t i = 0; i < r.data().size(); ++i)
            referenceNoise += double(v.data()[i]) / double(kBlock * kBlock) /
                              (double(r.data()[i]) * r.data()[i] + 0.01);
        referenceNoise /= double(r.data().size());
    }

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
    settings.halfBuffers = halves;
    w->document()->setSettings(settings);
    waitIdle(*w);
    // The render the toggle goes on from: the bar's, with half buffers.
    if (halves) {
        w->document()->render();
        waitIdle(*w);
    }
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
    // Each shown image's history: its pass's arrival, its re-application's start and end, auto's
    // refreshes started by then, its relMSE.
    struct Shown {
        double passAt = -1.0, reapplyAt = -1.0, landedAt = -1.0;
        int autoStarted = 0, autoFinished = 0;
        double relMse = -1.0;
    };
    std::vector<Shown> shown;
    std::map<int, double> passAt;  // spp -> arrival of the first pass with it
    double reapplyAt = -1.0, landedAt = -1.0;
    int lastSpp = 0;
    bool fresh = false;  // the session's input changed and its composite was not painted yet
    SessionAdapter* s = w->session();
    auto now = [&] { return double(clock.nsecsElapsed()) * 1e-9; };
    QObject::connect(w->document(), &Document::frameChanged, [&](bool) {
        if (const FramePtr f = w->document()->frame()) passAt.emplace(f->metadata().spp, now());
    });
    QObject::connect(s, &SessionAdapter::busyChanged, [&](bool busy) {
        if (busy) reapplyAt = now();
    });
    int freshSpp = 0;
    double freshReapplyAt = -1.0;
    QObject::connect(s, &SessionAdapter::inputChanged, [&] {
        // The composite of the new input is installed with it (the session may be busy with
        // the next one by the time the canvas paints).
        fresh = true;
        freshSpp = s->input()->metadata().spp;
        freshReapplyAt = reapplyAt;
        landedAt = now();
    });
    QObject::connect(w->viewer()->canvas(), &ImageCanvas::painted, [&] {
        if (!fresh || !w->document()->rendering()) return;
        fresh = false;
        const int spp = freshSpp;
        if (spp <= lastSpp) return;
        lastSpp = spp;
        shownAt.push_back(now());
        shownSpp.push_back(spp);
        Shown sh;
        const auto p = passAt.find(spp);
        sh.passAt = p == passAt.end() ? -1.0 : p->second;
        sh.reapplyAt = freshReapplyAt;
        sh.landedAt = landedAt;
        const ProgressiveRender::Activity a = w->progressive()->activity();
        sh.autoStarted = a.started;
        sh.autoFinished = a.finished;
        if (reference)
            sh.relMse =
                relMse(boxMeans(s->session().composite()), *reference).value - referenceNoise;
        shown.push_back(sh);
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
    // The first image better than the one on screen before the toggle (past the bar's 16 spp).
    const auto past = std::find_if(shownSpp.begin(), shownSpp.end(), [](int n) { return n > 16; });
    const double firstPast =
        past == shownSpp.end() ? 0.0 : shownAt[std::size_t(past - shownSpp.begin())];
    // Each interval's parts: waiting for the pass (from the last image shown), waiting for the
    // session (busy with something else), the layers' re-application, the display; "auto" when
    // one of auto's refreshes ran during it.
    std::printf("%8s %6s %7s %7s %7s %7s %7s %5s %9s\n", "shown s", "spp", "interval", "pass",
                "queue", "reapply", "display", "auto", "relMSE");
    for (std::size_t i = 0; i < shown.size(); ++i) {
        const Shown& sh = shown[i];
        const double prev = i == 0 ? 0.0 : shownAt[i - 1];
        const double pass = std::max(0.0, sh.passAt - prev);
        const double queue = sh.reapplyAt - std::max(sh.passAt, prev);
        const bool autoRan = i > 0 && (sh.autoStarted != shown[i - 1].autoStarted ||
                                       shown[i - 1].autoStarted != shown[i - 1].autoFinished);
        std::printf("%8.2f %6d %7.2f %7.2f %7.2f %7.2f %7.2f %5s %9.5f\n", shownAt[i], shownSpp[i],
                    shownAt[i] - prev, pass, queue, sh.landedAt - sh.reapplyAt,
                    shownAt[i] - sh.landedAt, autoRan ? "yes" : "", sh.relMse);
    }
    bool falling = true;
    for (std::size_t i = 1; i < shown.size(); ++i)
        if (shown[i].relMse > shown[i - 1].relMse) falling = false;
    std::printf(
        "Keep refining, 512^2 Cornell box, 16 spp%s + refinement, %d threads, layer %s, "
        "%.0f s, load %.2f\n",
        halves ? " with half buffers" : "", threads, filter.c_str(), seconds, load0);
    std::printf("%-52s %d (%d .. %d spp)\n", "denoised renders shown", int(shownAt.size()),
                shownSpp.empty() ? 0 : shownSpp.front(), shownSpp.empty() ? 0 : shownSpp.back());
    std::printf("%-52s %.2f s\n", "Keep Refining on -> first refined image shown", first);
    std::printf("%-52s %.2f s\n", "Keep Refining on -> first image past the bar's spp", firstPast);
    std::printf("%-52s %.2f s median, %.2f s max\n", "interval between denoised renders shown",
                percentile(intervals, 0.5), percentile(intervals, 1.0));
    std::printf("%-52s %.0f ms (UI thread CPU %.0f ms)\n", "longest UI-thread stall", stall, busy);
    std::printf("%-52s %d (the last: auto %.2f s)\n", "importance maps from auto's error",
                refreshes, autoSeconds);
    if (reference)
        std::printf("%-52s %.5f .. %.5f (the reference's noise, %.5f, taken off), %s\n",
                    "relMSE of the images shown (8x8 blocks)",
                    shown.empty() ? 0.0 : shown.front().relMse,
                    shown.empty() ? 0.0 : shown.back().relMse, referenceNoise,
                    falling ? "falling at every image" : "NOT falling at every image");
    std::printf(
        "{\"shown\": %d, \"firstS\": %.3f, \"firstPastBarS\": %.3f, \"halves\": %s, "
        "\"intervalMedianS\": %.3f, \"intervalMaxS\": %.3f, "
        "\"stallMs\": %.1f, \"busyMs\": %.1f, \"refreshes\": %d, \"autoS\": %.3f, \"lastSpp\": %d, "
        "\"load\": %.2f, "
        "\"layer\": \"%s\", \"relMseFalling\": %s}\n",
        int(shownAt.size()), first, firstPast, halves ? "true" : "false",
        percentile(intervals, 0.5), percentile(intervals, 1.0), stall, busy, refreshes, autoSeconds,
        lastSpp, load0, filter.c_str(), reference ? (falling ? "true" : "false") : "null");
    w->close();
    return 0;
}
