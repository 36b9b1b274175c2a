// The screenshot tour: scenes/cornell through every stage of the workflow, one PNG of the whole
// window per stage, written to the folder given (build/screenshots/ under ctest; docs/images/
// holds reduced copies). Fails when a screenshot cannot be written or shows a blank canvas, or
// when a control of the window cannot be reached or has its text cut (widget_reach.h: each is
// printed).
//   studio_screenshots OUT_DIR [--docs DOCS_DIR] [--size WIDTHxHEIGHT] [--reach-sizes WxH,...]
// With --docs, reduced copies (720 px wide, an 8-bit palette with ordered dithering, which
// compresses about three times better than error diffusion) of the screenshots docs/studio.md
// shows are written to DOCS_DIR as studio-NAME.png. --size sets the window's size (1500x900 by
// default; 1280x720 and 1366x768 show the studio on laptop screens). --reach-sizes
// 1280x720,1366x768,1920x1080 (ctest's) also walks every shot's window at each of those sizes
// for reach and cut text (issue 48's goal), and writes the key shots at each as NAME-WxH.png.
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QImage>
#include <QPixmap>
#include <QProgressBar>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <cstdio>
#include <cstring>

#include "studio_fixture.h"
#include "views/compare_view.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/tune_view.h"
#include "views/viewer.h"
#include "widget_reach.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

int g_failures = 0;
QString g_docs;             // where reduced copies go (empty: none)
QList<QSize> g_reachSizes;  // the other sizes each shot's window is walked at (--reach-sizes)

// The shots also written at each of the reach sizes: one per kind of panel.
const QStringList kShotAtEverySize = {QStringLiteral("01-open"), QStringLiteral("06-navigate"),
                                      QStringLiteral("07-paint"), QStringLiteral("09-compare")};

// The screenshots docs/studio.md shows (a reach size's shot named with its size).
const QStringList kDocumented = {
    QStringLiteral("01-open"),           QStringLiteral("02-look"),
    QStringLiteral("04-region"),         QStringLiteral("06-navigate"),
    QStringLiteral("07-paint"),          QStringLiteral("08-change-map"),
    QStringLiteral("09-compare"),        QStringLiteral("11-help"),
    QStringLiteral("12-weight-overlay"), QStringLiteral("15-auto-choice-map"),
    QStringLiteral("07-paint-1280x720")};

// The reduced copy of a documented shot in the docs folder (with --docs).
void writeDocsCopy(const QImage& shot, const QString& name) {
    if (g_docs.isEmpty() || !kDocumented.contains(name)) return;
    const QImage small = shot.scaledToWidth(720, Qt::SmoothTransformation)
                             .convertToFormat(QImage::Format_Indexed8, Qt::OrderedDither);
    if (!small.save(QDir(g_docs).filePath(QStringLiteral("studio-%1.png").arg(name)))) ++g_failures;
}

// The spread of grey levels inside the canvas: 0 for a blank canvas.
double canvasSpread(MainWindow& w) {
    const QImage image = w.viewer()->canvas()->grab().toImage();
    double lo = 255, hi = 0;
    for (int y = 0; y < image.height(); y += 4)
        for (int x = 0; x < image.width(); x += 4) {
            const double g = qGray(image.pixel(x, y));
            lo = std::min(lo, g);
            hi = std::max(hi, g);
        }
    return hi - lo;
}

// "1280x720" as a size; an empty size when it is not one.
QSize parseSize(const QString& text) {
    const QStringList wh = text.split(QLatin1Char('x'));
    return wh.size() == 2 ? QSize(wh[0].toInt(), wh[1].toInt()) : QSize();
}

void settle(int turns) {
    for (int i = 0; i < turns; ++i) {
        QCoreApplication::processEvents();
        QTest::qWait(10);
    }
}

// Every control of the window reachable and whole (widget_reach.h), each problem printed.
void walkForReach(MainWindow& w, const QString& where) {
    for (const QString& problem : reachProblems(&w)) {
        std::printf("  %sunreachable or cut: %s\n", qPrintable(where), qPrintable(problem));
        ++g_failures;
    }
}

// The window at each reach size, walked (and shot, for the key shots), then its size again.
void walkAtReachSizes(MainWindow& w, const QString& folder, const QString& name) {
    const QSize size = w.size();
    for (const QSize& at : g_reachSizes) {
        w.resize(at);
        settle(5);
        const QString tag = QStringLiteral("%1x%2").arg(at.width()).arg(at.height());
        if (w.size() != at) {
            std::printf("  at %s: the window is %dx%d\n", qPrintable(tag), w.width(), w.height());
            ++g_failures;
        }
        if (kShotAtEverySize.contains(name)) {
            const QString sized = QStringLiteral("%1-%2").arg(name, tag);
            const QImage shot = w.grab().toImage();
            const QString path = QDir(folder).filePath(sized + QStringLiteral(".png"));
            const bool saved = shot.save(path);
            writeDocsCopy(shot, sized);
            std::printf("%s %s\n", saved ? "wrote" : "FAILED to write", qPrintable(path));
            if (!saved) ++g_failures;
        }
        walkForReach(w, QStringLiteral("at %1: ").arg(tag));
    }
    if (!g_reachSizes.isEmpty()) {
        w.resize(size);
        settle(5);
    }
}

void shoot(MainWindow& w, const QString& folder, const QString& name) {
    settle(20);
    const QString path = QDir(folder).filePath(name + QStringLiteral(".png"));
    const QImage shot = w.grab().toImage();
    const bool saved = shot.save(path);
    writeDocsCopy(shot, name);
    const double spread = canvasSpread(w);
    std::printf("%s %s (canvas spread %.0f)\n", saved ? "wrote" : "FAILED to write",
                qPrintable(path), spread);
    if (!saved || spread < 20.0) ++g_failures;
    // The shortcut sheet covers the window on purpose.
    if (name.endsWith(QStringLiteral("help"))) return;
    walkForReach(w, QString());
    walkAtReachSizes(w, folder, name);
}

void drag(ImageCanvas* canvas, const QVector<QPointF>& path) {
    auto at = [&](const QPointF& p) { return canvas->toWidget(p).toPoint(); };
    QTest::mousePress(canvas, Qt::LeftButton, {}, at(path.first()));
    for (qsizetype i = 1; i < path.size(); ++i) QTest::mouseMove(canvas, at(path[i]), 2);
    QTest::mouseRelease(canvas, Qt::LeftButton, {}, at(path.last()));
}

}  // namespace

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    QSize size(1500, 900);
    bool usage = argc < 2 || argc % 2 != 0;
    for (int i = 2; i + 1 < argc && !usage; i += 2) {
        const QString value = QString::fromLocal8Bit(argv[i + 1]);
        if (std::strcmp(argv[i], "--docs") == 0) {
            g_docs = value;
        } else if (std::strcmp(argv[i], "--size") == 0) {
            size = parseSize(value);
            usage = size.isEmpty();
        } else if (std::strcmp(argv[i], "--reach-sizes") == 0) {
            for (const QString& text : value.split(QLatin1Char(','))) {
                g_reachSizes << parseSize(text);
                usage = usage || g_reachSizes.last().isEmpty();
            }
        } else {
            usage = true;
        }
    }
    if (usage) {
        std::fprintf(stderr,
                     "usage: studio_screenshots OUT_DIR [--docs DOCS_DIR] [--size WxH] "
                     "[--reach-sizes WxH,...]\n");
        return 2;
    }
    const QString out = QString::fromLocal8Bit(argv[1]);
    QDir().mkpath(out);
    QTemporaryDir tmp;
    auto w = makeWindow(tmp.filePath(QStringLiteral("autosave")), true);
    w->resize(size);
    const QString scene = QDir(sourceDir()).filePath(QStringLiteral("scenes/cornell/scene.json"));

    // 1. Open: the render refines and lands, denoised by the default layer.
    w->openFile(scene);
    if (!waitIdle(*w)) return 3;
    waitFor([&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); },
            20000);
    shoot(*w, out, QStringLiteral("01-open"));

    // 2. Look: a wall turns blue; the image renders again.
    const std::string wall = firstAlbedoMaterial(*w->document());
    const FramePtr before = w->document()->finishedFrame();
    w->lookPanel()->edit(wall, "albedo", {0.15, 0.3, 0.8});
    waitFor([&] { return w->document()->finishedFrame() != before; }, 20000);
    waitIdle(*w);
    shoot(*w, out, QStringLiteral("02-look"));

    // 3. Features: the normals.
    w->setStage(0);
    w->viewer()->setChannel(Viewer::Channel::Normal);
    shoot(*w, out, QStringLiteral("03-features"));

    // 4. Region: a lasso around the back wall and the boxes.
    w->setStage(1);
    drag(w->viewer()->canvas(),
         {{40, 40}, {210, 36}, {222, 150}, {180, 210}, {60, 214}, {34, 120}});
    shoot(*w, out, QStringLiteral("04-region"));

    // 5. Tune: it opens on the result's filter (the default layer's), then a bilateral filter
    // previewed inside the region.
    w->setStage(2);
    waitFor([&] { return w->tuneView()->previewReady(); }, 20000);
    shoot(*w, out, QStringLiteral("05a-tune-opens"));
    w->tuneView()->setFilter("bilateral");
    waitFor([&] { return w->tuneView()->previewReady(); }, 20000);
    shoot(*w, out, QStringLiteral("05-tune"));

    // 6. Navigate: the bank's four previews, one hovered.
    w->navigateView()->setBankSize(24);
    w->setStage(2, true);
    waitFor([&] { return w->navigateView()->ready(); }, 120000);
    // The learned result, pinned among them, hovered (another preview without it).
    const int learned = w->navigateView()->learnedOption();
    w->navigateView()->hoverOption(learned >= 0 ? learned : 1);
    shoot(*w, out, QStringLiteral("06-navigate"));
    // One level down: each preview says what sets it apart; then the choice in user terms.
    w->navigateView()->chooseOption(0);
    shoot(*w, out, QStringLiteral("06b-navigate-level2"));
    w->navigateView()->same();
    shoot(*w, out, QStringLiteral("06c-navigate-chosen"));

    // 7. Paint: the chosen filter painted on with strokes, the change map shown.
    const std::size_t layers = w->session()->session().layerCount();
    w->navigateView()->choose(false);
    waitFor(
        [&] {
            return w->session()->hasSession() && w->session()->session().layerCount() == layers + 1;
        },
        20000);
    w->paintView()->setBrushSize(40.0);
    drag(w->viewer()->canvas(), {{60, 80}, {120, 90}, {190, 80}});
    drag(w->viewer()->canvas(), {{70, 150}, {130, 170}, {190, 150}});
    QTest::mouseMove(w->viewer()->canvas(),
                     w->viewer()->canvas()->toWidget(QPointF(128, 120)).toPoint());
    shoot(*w, out, QStringLiteral("07-paint"));
    auto* change = w->paintView()->findChild<QCheckBox*>(QStringLiteral("changeMap"));
    if (change) change->setChecked(true);
    shoot(*w, out, QStringLiteral("08-change-map"));
    if (change) change->setChecked(false);
    // The painted layer's weight (O), then a wand click and its selection.
    QTest::keyClick(w->viewer()->canvas(), Qt::Key_O);
    shoot(*w, out, QStringLiteral("12-weight-overlay"));
    QTest::keyClick(w->viewer()->canvas(), Qt::Key_O);
    QTest::keyClick(w->viewer()->canvas(), Qt::Key_M);
    QTest::mouseClick(w->viewer()->canvas(), Qt::LeftButton, {},
                      w->viewer()->canvas()->toWidget(QPointF(128, 100)).toPoint());
    waitFor([&] { return w->viewer()->canvas()->hasSelection() && !w->session()->busy(); }, 20000);
    shoot(*w, out, QStringLiteral("13-wand-selection"));
    QTest::keyClick(w->viewer()->canvas(), Qt::Key_B);
    // The colour variance at EV 0, normalised for display.
    w->viewer()->setChannel(Viewer::Channel::ColorVariance);
    shoot(*w, out, QStringLiteral("14-colour-variance"));
    w->viewer()->setChannel(Viewer::Channel::Result);

    // 8. Compare: a 256-spp reference rendered in the background, a wipe, the metrics and plot.
    w->document()->renderReference(256);
    // While it renders, its bar shows the samples and the time left.
    auto* referenceBar = w->compareView()->findChild<QProgressBar*>();
    if (referenceBar &&
        waitFor([&] { return referenceBar->format().contains(QStringLiteral("left")); }, 60000))
        shoot(*w, out, QStringLiteral("08b-reference-progress"));
    waitFor([&] { return w->document()->reference() != nullptr; }, 120000);
    w->document()->render();  // a render against the reference draws the convergence plot
    waitIdle(*w);
    w->viewer()->setWipe(true);
    waitFor([&] { return w->compareView()->measurement().haveReference; }, 20000);
    shoot(*w, out, QStringLiteral("09-compare"));
    w->viewer()->setWipe(false);
    w->viewer()->setChannel(Viewer::Channel::ErrorRelative);
    w->viewer()->setDisplayMode(DisplayMode::FalseColor);
    shoot(*w, out, QStringLiteral("10-error"));
    w->viewer()->setDisplayMode(DisplayMode::Srgb);
    w->viewer()->setChannel(Viewer::Channel::Result);
    // A look edit: the reference is of another look, its metrics marked stale beside a warning.
    const FramePtr unedited = w->document()->finishedFrame();
    w->lookPanel()->edit(wall, "albedo", {0.8, 0.3, 0.15});
    waitFor([&] { return w->document()->finishedFrame() != unedited; }, 20000);
    waitIdle(*w);
    shoot(*w, out, QStringLiteral("09b-compare-stale"));
    w->session()->undoStack()->undo();
    waitIdle(*w);

    // 9. Auto Start: one result layer, its choice map with the members' names.
    w->session()->autoStart();
    waitFor([&] { return !w->session()->busy(); }, 300000);
    if (auto* choice = w->paintView()->findChild<QCheckBox*>(QStringLiteral("choiceMap")))
        choice->setChecked(true);
    waitFor([&] { return !w->viewer()->canvas()->legend().isEmpty(); }, 20000);
    shoot(*w, out, QStringLiteral("15-auto-choice-map"));
    if (auto* choice = w->paintView()->findChild<QCheckBox*>(QStringLiteral("choiceMap")))
        choice->setChecked(false);

    // 10. The shortcut sheet.
    QTest::keyClick(w.get(), Qt::Key_F1);
    shoot(*w, out, QStringLiteral("11-help"));
    QTest::keyClick(w.get(), Qt::Key_F1);

    w->close();
    std::printf("%d screenshot(s) failed\n", g_failures);
    return g_failures == 0 ? 0 : 1;
}
