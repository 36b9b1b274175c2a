// The studio's actions whose work grows with the image, each driven as a user would and waited
// for to completion: shared by the restore test (tests/gui/restore_test.cpp) and the speed
// benchmark (lab/bench/bench_studio.cpp), which measures how long each stalls the UI thread.
#pragma once

#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QPushButton>
#include <QSpinBox>
#include <QTest>

#include "app/autosave.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/render_bar.h"
#include "views/tune_view.h"
#include "views/viewer.h"

namespace glint::studio::testing {

/// The check box of `parent` whose text is `text` (null when there is none).
inline QCheckBox* checkBox(QWidget* parent, const QString& text) {
    for (QCheckBox* box : parent->findChildren<QCheckBox*>())
        if (box->text() == text) return box;
    return nullptr;
}

/// Opens `scene` rendered at 1 spp (the render bar's spp set to 1) with one Gaussian layer of
/// weight 0, on the paint stage.
inline bool openWithLayer(MainWindow& w, const QString& scene) {
    auto* spp = w.renderBar()->findChild<QSpinBox*>();  // the render bar's first box: spp
    if (!spp) return false;
    spp->setValue(1);
    w.openFile(scene);
    if (!waitIdle(w, 120000)) return false;
    if (!addGaussian(w, false, 120000)) return false;
    return waitIdle(w, 120000);
}

/// Renders the middle quarter of the frame again (a region render merged into the frame).
inline bool regionRender(MainWindow& w, std::uint64_t seed) {
    const FramePtr before = w.document()->finishedFrame();
    render::Settings s = w.document()->settings();
    s.seed = seed;
    w.document()->setSettings(s);
    const int width = before->width(), height = before->height();
    w.document()->renderRegion(Rect{width / 4, 3 * width / 4, height / 4, 3 * height / 4});
    return waitFor([&] { return w.document()->finishedFrame() != before; }, 120000) &&
           waitIdle(w, 120000);
}

/// A magic-wand click in the middle of the image on layer 0: waits for its fill's undo step.
inline bool wandClick(MainWindow& w) {
    w.setStage(3);
    w.paintView()->setCurrentLayer(0);
    ImageCanvas* canvas = w.viewer()->canvas();
    canvas->setTool(ImageCanvas::Tool::Wand);
    const int steps = w.session()->undoStack()->count();
    const FramePtr in = w.session()->input();
    const QPointF middle(in->width() * 0.5 + 0.5, in->height() * 0.5 + 0.5);
    QTest::mouseClick(canvas, Qt::LeftButton, {}, canvas->toWidget(middle).toPoint());
    const bool done =
        waitFor([&] { return w.session()->undoStack()->count() == steps + 1; }, 60000);
    canvas->setTool(ImageCanvas::Tool::Brush);
    return done;
}

/// The paint stage's "Everywhere" on layer 0 (weight 1 over the whole image): waits for its undo
/// step and for the composite to be redrawn.
inline bool everywhereClick(MainWindow& w) {
    w.setStage(3);
    w.paintView()->setCurrentLayer(0);
    QPushButton* button = nullptr;
    for (QPushButton* b : w.paintView()->findChildren<QPushButton*>())
        if (b->text() == QObject::tr("Everywhere")) button = b;
    if (!button) return false;
    const int steps = w.session()->undoStack()->count();
    QTest::mouseClick(button, Qt::LeftButton);
    return waitFor([&] { return w.session()->undoStack()->count() == steps + 1; }, 60000) &&
           waitIdle(w, 60000);
}

/// Turns the paint stage's change map on until it shows, then off.
inline bool changeMap(MainWindow& w) {
    w.setStage(3);
    QCheckBox* box = checkBox(w.paintView(), QObject::tr("Show change map"));
    if (!box) return false;
    box->setChecked(true);
    const bool shown = waitFor([&] { return w.viewer()->canvas()->hasOverlay(); }, 60000);
    box->setChecked(false);
    return shown;
}

/// Builds a navigation bank of `size` members over the whole image (size differs between runs:
/// the bank service would answer a repeated build from its cache).
inline bool navigateBuild(MainWindow& w, int size) {
    w.navigateView()->setBankSize(size);
    // Entering the stage builds when the bank is of another render; else the button does.
    w.setStage(2, true);
    if (w.navigateView()->ready()) w.navigateView()->build();
    return waitFor([&] { return w.navigateView()->ready(); }, 240000);
}

/// Turns Navigate's filter-variance overlay on until it shows, then off.
inline bool varianceMap(MainWindow& w) {
    w.setStage(2, true);
    QCheckBox* box = checkBox(w.navigateView(), QObject::tr("Show filter variance"));
    if (!box || !w.navigateView()->ready()) return false;
    box->setChecked(true);
    const bool shown = waitFor([&] { return w.viewer()->canvas()->hasOverlay(); }, 60000);
    box->setChecked(false);
    return shown;
}

/// File > Save Session to `path`, until it is written.
inline bool saveSession(MainWindow& w, const QString& path) {
    QDir().mkpath(QFileInfo(path).path());
    return w.saveSession(path) && waitFor([&] { return !w.session()->busy(); }, 120000) &&
           w.session()->undoStack()->isClean();
}

/// File > Export EXR to `path`, until it is written.
inline bool exportExr(MainWindow& w, const QString& path) {
    QDir().mkpath(QFileInfo(path).path());
    bool done = false, ok = false;
    w.session()->exportResult(path, true, {}, [&](const QString& error) {
        done = true;
        ok = error.isEmpty();
    });
    return waitFor([&] { return done; }, 120000) && ok;
}

/// Copies `w`'s autosave journal to `base` as the journal of a studio that crashed (a process
/// id no process has). Returns false when a file cannot be copied.
inline bool copyAsCrashed(MainWindow& w, const QString& base) {
    w.autosave()->flush();
    const QDir from(w.autosave()->journal()->folder());
    const QDir to(QDir(base).filePath(QStringLiteral("999999999")));
    QDir(to.path()).removeRecursively();
    QDir().mkpath(to.path());
    for (const QString& name : from.entryList(QDir::Files))
        if (!QFile::copy(from.filePath(name), to.filePath(name))) return false;
    return true;
}

/// Restores the crashed journal under `w`'s autosave base into `w`, until it is in place.
inline bool restore(MainWindow& w) {
    w.offerRestore(false);
    return waitFor([&] { return !w.autosave()->restoring(); }, 240000) &&
           waitFor([&] { return w.session()->hasSession() && !w.session()->busy(); }, 120000) &&
           w.lastError().isEmpty();
}

}  // namespace glint::studio::testing
