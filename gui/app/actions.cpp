#include "app/actions.h"

#include <QKeySequence>

namespace glint::studio {

namespace {

QAction* make(QObject* owner, const QString& text, const QKeySequence& shortcut,
              const QString& tip) {
    auto* a = new QAction(text, owner);
    a->setShortcut(shortcut);
    a->setToolTip(shortcut.isEmpty() ? tip
                                     : QStringLiteral("%1 (%2)").arg(
                                           tip, shortcut.toString(QKeySequence::NativeText)));
    a->setStatusTip(tip);
    a->setShortcutContext(Qt::WindowShortcut);
    return a;
}

}  // namespace

QList<QAction*> StudioActions::all() const {
    QList<QAction*> list{open,        openReference, saveSession, saveSessionAs, saveScene,
                         exportExr,   exportPng,     newSession,  recover,       quit,
                         undo,        redo,          render,      cancelRender,  keepRefining,
                         fit,         oneToOne,      flip,        wipe,          exposureUp,
                         exposureDown};
    for (QAction* s : stages) list << s;
    list << lasso << wholeImage << brushSmaller << brushLarger << brush << wand << diffuse
         << showWeight << autoStart << same << back << help;
    return list;
}

StudioActions createActions(QObject* o) {
    StudioActions a{};
    a.open = make(o, QObject::tr("&Open…"), QKeySequence::Open,
                  QObject::tr("Open a scene.json, a layered EXR or a session"));
    a.openReference =
        make(o, QObject::tr("Open &Reference…"), QKeySequence(QObject::tr("Ctrl+Shift+O")),
             QObject::tr("Open a high-spp EXR to compare with"));
    a.saveSession = make(o, QObject::tr("&Save Session"), QKeySequence::Save,
                         QObject::tr("Save the painting session"));
    a.saveSessionAs =
        make(o, QObject::tr("Save Session &As…"), QKeySequence(QObject::tr("Ctrl+Shift+S")),
             QObject::tr("Save the painting session under a new name"));
    a.saveScene = make(o, QObject::tr("Save Scene as &JSON…"), QKeySequence(),
                       QObject::tr("Write the scene with its look edits as scene.json"));
    a.exportExr = make(o, QObject::tr("Export &EXR…"), QKeySequence(QObject::tr("Ctrl+E")),
                       QObject::tr("Write the result with the render's layers as a layered EXR"));
    a.exportPng = make(o, QObject::tr("Export &PNG…"), QKeySequence(QObject::tr("Ctrl+Shift+E")),
                       QObject::tr("Write the result as an 8-bit sRGB PNG"));
    a.newSession = make(o, QObject::tr("&New Session"), QKeySequence(),
                        QObject::tr("Drop the layers and start painting on the current render"));
    a.recover = make(o, QObject::tr("Re&cover Autosave…"), QKeySequence(),
                     QObject::tr("Restore the work a studio that did not exit cleanly autosaved"));
    a.quit = make(o, QObject::tr("&Quit"), QKeySequence::Quit, QObject::tr("Close the studio"));
    a.undo = make(o, QObject::tr("&Undo"), QKeySequence::Undo, QObject::tr("Undo the last edit"));
    a.redo = make(o, QObject::tr("&Redo"), QKeySequence(QObject::tr("Ctrl+Shift+Z")),
                  QObject::tr("Redo the edit undone"));
    // The same keys on every platform theme (the offscreen one knows only Ctrl+Y).
    a.redo->setShortcuts(
        {QKeySequence(QObject::tr("Ctrl+Shift+Z")), QKeySequence(QObject::tr("Ctrl+Y"))});
    a.render = make(o, QObject::tr("&Render"), QKeySequence(QObject::tr("Ctrl+R")),
                    QObject::tr("Render with the render bar's settings"));
    a.cancelRender = make(o, QObject::tr("&Cancel Render"), QKeySequence(Qt::Key_Escape),
                          QObject::tr("Stop the render, keeping what it has"));
    a.keepRefining =
        make(o, QObject::tr("&Keep Refining"), QKeySequence(),
             QObject::tr("Go on rendering past the spp where the denoised image is worst, until "
                         "an edit, Cancel or 64 times the spp"));
    a.keepRefining->setCheckable(true);
    a.fit = make(o, QObject::tr("&Fit"), QKeySequence(Qt::Key_F),
                 QObject::tr("Fit the image to the window"));
    a.oneToOne = make(o, QObject::tr("&1:1"), QKeySequence(Qt::Key_0),
                      QObject::tr("One image pixel per screen pixel"));
    a.flip = make(o, QObject::tr("A/B &Flip"), QKeySequence(Qt::Key_Space),
                  QObject::tr("Show the reference instead of the result, and back"));
    a.wipe = make(o, QObject::tr("&Wipe"), QKeySequence(Qt::Key_V),
                  QObject::tr("Result left of a line dragged on the canvas, reference right"));
    a.exposureUp = make(o, QObject::tr("Exposure +½"), QKeySequence(Qt::Key_E),
                        QObject::tr("Brighter by half a stop"));
    a.exposureDown = make(o, QObject::tr("Exposure −½"), QKeySequence(QObject::tr("Shift+E")),
                          QObject::tr("Darker by half a stop"));
    const QString stageNames[4] = {QObject::tr("Features"), QObject::tr("Region"),
                                   QObject::tr("Filter"), QObject::tr("Paint")};
    for (int i = 0; i < 4; ++i)
        a.stages[std::size_t(i)] =
            make(o, QObject::tr("Stage %1: %2").arg(i + 1).arg(stageNames[i]),
                 QKeySequence(Qt::Key_1 + i), QObject::tr("Go to stage %1").arg(i + 1));
    a.lasso = make(o, QObject::tr("&Lasso"), QKeySequence(Qt::Key_L),
                   QObject::tr("Draw the region of interest free-hand"));
    a.wholeImage = make(o, QObject::tr("&Whole Image"), QKeySequence(Qt::Key_W),
                        QObject::tr("Make the whole image the region"));
    a.brushSmaller = make(o, QObject::tr("Smaller Brush"), QKeySequence(Qt::Key_BracketLeft),
                          QObject::tr("Brush a quarter smaller"));
    a.brushLarger = make(o, QObject::tr("Larger Brush"), QKeySequence(Qt::Key_BracketRight),
                         QObject::tr("Brush a quarter larger"));
    a.brush = make(o, QObject::tr("&Brush"), QKeySequence(Qt::Key_B),
                   QObject::tr("Paint with the brush"));
    a.wand = make(o, QObject::tr("&Magic Wand"), QKeySequence(Qt::Key_M),
                  QObject::tr("Fill connected areas of similar features"));
    a.diffuse = make(o, QObject::tr("&Diffuse"), QKeySequence(Qt::Key_D),
                     QObject::tr("Poisson-diffuse the painted weights"));
    a.showWeight = make(o, QObject::tr("Show Layer &Weight"), QKeySequence(Qt::Key_O),
                        QObject::tr("Paint: dim the image where the selected layer does not show"));
    a.autoStart =
        make(o, QObject::tr("&Auto Start"), QKeySequence(QObject::tr("Ctrl+Shift+A")),
             QObject::tr("Start painting from a per-pixel choice among a filter bank, made by "
                         "SURE from the render's variance (no reference)"));
    a.same = make(o, QObject::tr("They Look the &Same"), QKeySequence(Qt::Key_S),
                  QObject::tr("Navigation: pick any member below this level"));
    a.back = make(o, QObject::tr("Navigate &Back"), QKeySequence(Qt::Key_Backspace),
                  QObject::tr("Navigation: up one level"));
    a.help = make(o, QObject::tr("&Shortcuts"), QKeySequence(Qt::Key_F1),
                  QObject::tr("Show every shortcut"));
    return a;
}

}  // namespace glint::studio
