// Restoring an autosave (docs/studio.md, "Autosave and restore"; issue "reliability round 3"):
// a studio killed after layers from Auto Start, an undo, a look edit and a stroke comes back
// whole and consistent, and so do random sequences of every kind of edit, bit for bit, a session
// opened from a file with its look and region, and the exposure and Keep Refining; the replay
// runs off the UI thread and changes nothing until it is done; a broken autosave changes
// nothing, says so once and is kept aside; "No" keeps the autosave aside and it is not offered
// again; a file named on the command line opens at once.
#include <QApplication>
#include <QDir>
#include <QListWidget>
#include <QMessageBox>
#include <QPointer>
#include <QProcess>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QThread>
#include <QUndoStack>

#include <csignal>
#include <cstring>
#include <random>
#include <thread>

#include "heavy_actions.h"
#include "model/progressive_render.h"
#include "random_edits.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// The look edit the killed studio makes (a wall's albedo).
constexpr std::array<double, 3> kAlbedo{0.3, 0.6, 0.2};

double sum(const Image& image) {
    double s = 0.0;
    for (float v : image.data()) s += v;
    return s;
}

// Folders under `base` kept aside (declined or broken autosaves).
QStringList keptAside(const QString& base) {
    return QDir(base).entryList({QStringLiteral("*.kept-*")}, QDir::Dirs | QDir::NoDotAndDotDot);
}

// Runs Auto Start with a bank of 4 members and waits until its layers are in.
bool autoStart(MainWindow& w) {
    const std::size_t before = w.session()->session().layerCount();
    w.session()->autoStart(4);
    return waitFor(
        [&] { return w.session()->session().layerCount() > before && !w.session()->busy(); },
        180000);
}

// The top layer that runs a filter (Auto Start's result layer is auto's correction).
std::size_t lastMember(const denoise::Session& s) {
    std::size_t i = s.layerCount() - 1;
    while (i > 0 && s.layer(i).correction) --i;
    return i;
}

// How `got`'s undo stack differs from `want`'s (its steps' names, its place): "" when it does not.
QString historyDifference(MainWindow& got, MainWindow& want) {
    const QUndoStack& g = *got.session()->undoStack();
    const QUndoStack& w = *want.session()->undoStack();
    if (g.count() != w.count() || g.index() != w.index())
        return QStringLiteral("%1 undo steps at %2, expected %3 at %4")
            .arg(g.count())
            .arg(g.index())
            .arg(w.count())
            .arg(w.index());
    for (int i = 0; i < w.count(); ++i)
        if (g.text(i) != w.text(i))
            return QStringLiteral("step %1 named \"%2\", expected \"%3\"")
                .arg(i)
                .arg(g.text(i), w.text(i));
    return {};
}

}  // namespace

class RestoreTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;

    // A crashed studio's autosave under `base`: a window with `m_scene` open, a Gaussian layer
    // filled and a stroke, its journal copied as that of a process that is gone.
    QString crashedAutosave(const QString& base) {
        auto w = openAndWait(m_scene, m_dir.filePath(base + QStringLiteral("-live")));
        if (!w || !addGaussian(*w, true) || !waitIdle(*w)) return {};
        w->session()->beginStroke(0, {8.0, 0.5}, denoise::BrushMode::Subtract);
        w->session()->dab(20.0, 20.0);
        w->session()->endStroke();
        if (!copyAsCrashed(*w, m_dir.filePath(base))) return {};
        w->close();
        const QStringList crashed = Autosave::crashed(m_dir.filePath(base));
        return crashed.size() == 1 ? crashed.first() : QString();
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void randomEditsComeBackBitForBitFromTheJournal() {
        // Eight fixed seeds, 32 random edits each (random_edits.h: every kind the paint stage
        // offers, look edits and Auto Start among them): the replay of the journal gives the
        // live session's layers, names, weights, composite and history bit for bit.
        const std::string wall = [&] {
            auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("random-probe")));
            return w ? firstAlbedoMaterial(*w->document()) : std::string();
        }();
        QVERIFY(!wall.empty());
        // Seeds that end with a reference, with a lasso, and that reopened a saved session: the
        // comparisons are not vacuous.
        int withReference = 0, withLasso = 0, reopened = 0, undoneSteps = 0;
        for (unsigned seed = 11; seed <= 18; ++seed) {
            const QString base = m_dir.filePath(QStringLiteral("random-%1").arg(seed));
            auto w = openAndWait(m_scene, base + QStringLiteral("-live"));
            QVERIFY(w);
            const RandomEdits made = randomEdits(*w, seed, 32, wall, m_dir.path());
            const QString edits = made.text();
            QVERIFY2(made.failure.isEmpty(), qPrintable(made.failure + ": " + edits));
            QVERIFY(copyAsCrashed(*w, base));
            const QStringList crashed = Autosave::crashed(base);
            QCOMPARE(crashed.size(), 1);
            const Recovered r = recover(crashed.first());
            QVERIFY2(r.complete && r.session, qPrintable(edits));
            const denoise::Session& live = w->session()->session();
            const QString difference = sessionDifference(*r.session, live);
            QVERIFY2(difference.isEmpty(),
                     qPrintable(
                         QStringLiteral("seed %1: %2 after %3").arg(seed).arg(difference, edits)));
            const QString reference = referenceDifference(r.referenceSet ? r.reference : nullptr,
                                                          w->document()->reference());
            QVERIFY2(reference.isEmpty(), qPrintable(reference + " after " + edits));
            QCOMPARE(r.lasso, w->region()->coordinates());
            QCOMPARE(r.session->canUndo(), live.canUndo());
            QCOMPARE(r.session->canRedo(), live.canRedo());
            // The whole restore, as "Restore your work? > Yes" does, into a new window: the
            // same session, look and undo history.
            auto again = makeWindow(base);
            again->restoreFrom(crashed.first());
            QVERIFY(waitFor([&] { return !again->autosave()->restoring(); }, 240000));
            QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
            QVERIFY(waitFor(
                [&] { return again->session()->hasSession() && !again->session()->busy(); }));
            const QString restored = sessionDifference(again->session()->session(), live);
            QVERIFY2(
                restored.isEmpty(),
                qPrintable(QStringLiteral("seed %1: %2 after %3").arg(seed).arg(restored, edits)));
            QCOMPARE(again->document()->lookValue(wall, "albedo"),
                     w->document()->lookValue(wall, "albedo"));
            QCOMPARE(again->region()->coordinates(), w->region()->coordinates());
            const QString againReference =
                referenceDifference(again->document()->reference(), w->document()->reference());
            QVERIFY2(againReference.isEmpty(), qPrintable(againReference + " after " + edits));
            // The undo history comes back too: the same steps, named alike, at the same place;
            // then the same undos and redos on both give the same work, and a second crash of
            // the restored studio replays to it.
            const QString history = historyDifference(*again, *w);
            QVERIFY2(
                history.isEmpty(),
                qPrintable(QStringLiteral("seed %1: %2 after %3").arg(seed).arg(history, edits)));
            undoneSteps += w->session()->undoStack()->index();
            std::mt19937 rng(seed);
            QStringList moves;
            for (int k = 0; k < 6; ++k) {
                const bool undo = std::uniform_int_distribution<int>(0, 2)(rng) > 0;
                moves << (undo ? QStringLiteral("undo") : QStringLiteral("redo"));
                for (MainWindow* x : {w.get(), again.get()}) {
                    if (undo)
                        x->session()->undoStack()->undo();
                    else
                        x->session()->undoStack()->redo();
                    QVERIFY(waitIdle(*x, 60000));
                }
                const QString after =
                    sessionDifference(again->session()->session(), w->session()->session());
                QVERIFY2(after.isEmpty(),
                         qPrintable(QStringLiteral("seed %1: %2 after %3, then %4")
                                        .arg(seed)
                                        .arg(after, edits, moves.join(QStringLiteral(", ")))));
                QCOMPARE(again->document()->lookValue(wall, "albedo"),
                         w->document()->lookValue(wall, "albedo"));
                QCOMPARE(historyDifference(*again, *w), QString());
            }
            const QString second = base + QStringLiteral("-second");
            QVERIFY(copyAsCrashed(*again, second));
            const Recovered r2 = recover(Autosave::crashed(second).value(0));
            QVERIFY(r2.session);
            const QString secondDifference =
                sessionDifference(*r2.session, again->session()->session());
            QVERIFY2(
                secondDifference.isEmpty(),
                qPrintable(QStringLiteral("seed %1, second crash: %2 after %3, then %4")
                               .arg(seed)
                               .arg(secondDifference, edits, moves.join(QStringLiteral(", ")))));
            QCOMPARE(int(r2.undo.size()), again->session()->undoStack()->index());
            QCOMPARE(int(r2.undo.size() + r2.redo.size()), again->session()->undoStack()->count());
            withReference += w->document()->reference() ? 1 : 0;
            withLasso += w->region()->wholeImage() ? 0 : 1;
            reopened += made.done.contains(QStringLiteral("reopen")) ? 1 : 0;
            again->close();
            w->close();
        }
        QVERIFY(withReference > 0);
        QVERIFY(withLasso > 0);
        QVERIFY(reopened > 0);
        QVERIFY(undoneSteps > 0);
        qInfo(
            "of 8 seeds: %d end with a reference, %d with a lasso; %d reopened a session; "
            "%d undo steps restored in all",
            withReference, withLasso, reopened, undoneSteps);
    }

    void aSessionOpenedFromAFileComesBackWithItsLookAndRegion() {
        // A session saved with a look edit and a lasso, opened in a fresh studio, a stroke made,
        // then the studio gone: the restore brings back the file's look and region with the
        // stroke. (Before they were journalled: the scene file's own look and the whole image.)
        const std::array<double, 3> edited{0.7, 0.2, 0.4};
        const std::vector<double> lasso{3.25, 4.0, 40.5, 6.0, 20.0, 30.75};
        const QString path = m_dir.filePath(QStringLiteral("looked.glint-session.json"));
        std::string wall;
        {
            auto first = openAndWait(m_scene, m_dir.filePath(QStringLiteral("looked-first")));
            QVERIFY(first);
            wall = firstAlbedoMaterial(*first->document());
            QVERIFY(first->document()->lookValue(wall, "albedo") != edited);
            const FramePtr before = first->document()->finishedFrame();
            first->lookPanel()->edit(wall, "albedo", edited);
            QVERIFY(waitFor([&] { return first->document()->finishedFrame() != before; }));
            QVERIFY(waitIdle(*first));
            QVERIFY(addGaussian(*first, true));
            QVERIFY(waitIdle(*first));
            first->region()->setCoordinates(lasso);
            QVERIFY(first->saveSession(path));
            QVERIFY(waitFor([&] { return !first->session()->busy() && !first->isModified(); }));
        }
        const QString base = m_dir.filePath(QStringLiteral("looked"));
        auto w = makeWindow(base + QStringLiteral("-live"));
        w->openFile(path);
        QVERIFY(waitFor([&] {
            return w->session()->hasSession() && !w->session()->busy() &&
                   w->document()->kind() == Document::Kind::Scene && !w->document()->loading() &&
                   w->document()->lookValue(wall, "albedo") == edited;
        }));
        QCOMPARE(w->region()->coordinates(), lasso);
        w->session()->beginStroke(0, {6.0, 0.5}, denoise::BrushMode::Subtract);
        w->session()->dab(30.0, 20.0);
        w->session()->endStroke();
        QVERIFY(copyAsCrashed(*w, base));
        const QStringList crashed = Autosave::crashed(base);
        QCOMPARE(crashed.size(), 1);

        auto again = makeWindow(base);
        again->restoreFrom(crashed.first());
        QVERIFY(waitFor([&] { return !again->autosave()->restoring(); }, 240000));
        QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
        QVERIFY(
            waitFor([&] { return again->session()->hasSession() && !again->session()->busy(); }));
        QCOMPARE(again->document()->lookValue(wall, "albedo"), edited);
        QCOMPARE(again->region()->coordinates(), lasso);
        const QString difference =
            sessionDifference(again->session()->session(), w->session()->session());
        QVERIFY2(difference.isEmpty(), qPrintable(difference));
        // Restored a second time from the restored studio's own journal: the same again.
        QVERIFY(copyAsCrashed(*again, base + QStringLiteral("-second")));
        const QStringList second = Autosave::crashed(base + QStringLiteral("-second"));
        QCOMPARE(second.size(), 1);
        const Recovered r = recover(second.first());
        QVERIFY(r.session);
        QCOMPARE(r.lasso, lasso);
        bool found = false;
        for (const LookValue& v : r.look)
            if (v.item == wall && v.property == "albedo") found = v.value == edited;
        QVERIFY(found);
    }

    void aJournalCutByTheCrashIsContinuedWithoutTheCutLine() {
        // The restored studio carries the crashed journal on (its undo history then survives a
        // second crash): the line the crash cut goes, and what is made next replays whole.
        const QString folder = crashedAutosave(QStringLiteral("cut"));
        QVERIFY(!folder.isEmpty());
        QFile lines(QDir(folder).filePath(QStringLiteral("journal.jsonl")));
        QVERIFY(lines.open(QIODevice::Append));
        lines.write("{\"op\":\"stroke\",\"lay");
        lines.close();
        auto w = makeWindow(m_dir.filePath(QStringLiteral("cut")));
        w->restoreFrom(folder);
        QVERIFY(waitFor([&] { return !w->autosave()->restoring(); }, 240000));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QVERIFY(waitFor([&] { return w->session()->hasSession() && !w->session()->busy(); }));
        QVERIFY(w->lastStatus().contains(QStringLiteral("lost")));
        QVERIFY(!QFileInfo::exists(folder));              // moved into this studio's autosave
        QCOMPARE(w->session()->undoStack()->count(), 2);  // the layer (filled), the stroke
        w->session()->undoStack()->undo();
        w->session()->beginStroke(0, {5.0, 0.5}, denoise::BrushMode::Subtract);
        w->session()->dab(44.0, 30.0);
        w->session()->endStroke();
        const QString second = m_dir.filePath(QStringLiteral("cut-second"));
        QVERIFY(copyAsCrashed(*w, second));
        const Recovered r = recover(Autosave::crashed(second).value(0));
        QVERIFY(r.complete);
        QVERIFY(r.session);
        const QString difference = sessionDifference(*r.session, w->session()->session());
        QVERIFY2(difference.isEmpty(), qPrintable(difference));
        QCOMPARE(int(r.undo.size()), 2);
        QVERIFY(r.redo.empty());
    }

    void aRestoredStudioIsUnsavedSoClosingItAsksFirst() {
        // A layer and a stroke, no look or settings change: what comes back is in no file. A
        // window that called itself saved would close without asking and drop the autosave with
        // the work (it did: only look, settings and reference changes made a restore unsaved).
        const QString folder = crashedAutosave(QStringLiteral("unsaved"));
        QVERIFY(!folder.isEmpty());
        auto w = makeWindow(m_dir.filePath(QStringLiteral("unsaved")));
        w->restoreFrom(folder);
        QVERIFY(waitFor([&] { return !w->autosave()->restoring(); }, 240000));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QVERIFY(waitFor([&] { return w->session()->hasSession() && !w->session()->busy(); }));
        QVERIFY(!w->document()->modified());  // the look, settings and reference are the file's
        QVERIFY(w->isModified());
        QVERIFY2(w->windowTitle().contains(QStringLiteral(" *")), qPrintable(w->windowTitle()));
        // Saved, it is clean; a stroke then makes it unsaved again.
        const QString path = m_dir.filePath(QStringLiteral("unsaved.glint-session.json"));
        QVERIFY(w->saveSession(path));
        QVERIFY(waitFor([&] { return !w->session()->busy() && !w->isModified(); }));
        w->session()->beginStroke(0, {4.0, 0.5}, denoise::BrushMode::Subtract);
        w->session()->dab(40.0, 30.0);
        w->session()->endStroke();
        QVERIFY(w->isModified());
    }

    void theExposureKeepRefiningStageAndChannelComeBackWithoutRendering() {
        // What a session file keeps of the view besides the region, changed since no save: the
        // exposure (set twice), Keep Refining (on, its render cancelled), the stage and the
        // viewer's channel. The restore
        // brings them back and renders nothing (they came back as the scene file's defaults
        // before).
        const QString base = m_dir.filePath(QStringLiteral("view"));
        auto w = openAndWait(m_scene, base + QStringLiteral("-live"));
        QVERIFY(w && addGaussian(*w, true) && waitIdle(*w));
        w->viewer()->setExposure(1.5);
        w->actions().keepRefining->setChecked(true);
        QVERIFY(waitFor([&] { return w->document()->refining(); }));
        w->document()->cancelRender();
        QVERIFY(waitIdle(*w));
        w->viewer()->setExposure(-1.0);
        w->setStage(3);  // Paint, as a session file would keep it
        w->viewer()->setChannel(Viewer::Channel::Albedo);
        QVERIFY(copyAsCrashed(*w, base));
        const QStringList crashed = Autosave::crashed(base);
        QCOMPARE(crashed.size(), 1);

        auto again = makeWindow(base);
        QVERIFY(!again->actions().keepRefining->isChecked());
        QCOMPARE(again->viewer()->exposure(), 0.0);
        QCOMPARE(again->viewer()->channel(), Viewer::Channel::Result);
        const int stageBefore = again->stage();
        QVERIFY(stageBefore != 3);
        again->restoreFrom(crashed.first());
        QVERIFY(waitFor([&] { return !again->autosave()->restoring(); }, 240000));
        QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
        QVERIFY(
            waitFor([&] { return again->session()->hasSession() && !again->session()->busy(); }));
        QCOMPARE(again->viewer()->exposure(), -1.0);
        QCOMPARE(again->stage(), 3);
        QCOMPARE(again->viewer()->channel(), Viewer::Channel::Albedo);
        // The canvas shows the restored result (drawn once, after everything came back).
        const QImage shown = again->viewer()->canvas()->shownImage();
        QVERIFY(!shown.isNull());
        again->viewer()->refresh();
        QVERIFY(again->viewer()->canvas()->shownImage() == shown);
        QVERIFY(again->actions().keepRefining->isChecked());
        QVERIFY(again->progressive()->enabled());
        QVERIFY(!again->document()->rendering());
        // The restored studio's own journal holds them for a second crash.
        QVERIFY(copyAsCrashed(*again, base + QStringLiteral("-second")));
        const Recovered r = recover(Autosave::crashed(base + QStringLiteral("-second")).value(0));
        QVERIFY(r.view);
        QCOMPARE(r.view->exposure, -1.0);
        QVERIFY(r.view->keepRefining);
        QCOMPARE(r.view->stage, std::optional<int>(3));
        QCOMPARE(r.view->channel, std::optional<std::string>("albedo"));
    }

    void aKilledStudioComesBackWholeAfterAutoStartALookEditAndAStroke() {
        const QString base = m_dir.filePath(QStringLiteral("killed"));
        QProcess child;
        child.setProcessChannelMode(QProcess::ForwardedChannels);
        child.start(QCoreApplication::applicationFilePath(),
                    {QStringLiteral("--kill-child"), base, m_scene});
        QVERIFY(child.waitForFinished(400000));
        QCOMPARE(child.exitStatus(), QProcess::CrashExit);  // SIGKILL: nothing cleaned up
        const QString expected = QDir(base).filePath(QStringLiteral("expected.glint-session.json"));
        QVERIFY(QFileInfo::exists(expected));
        const QStringList crashed = Autosave::crashed(base);
        QCOMPARE(crashed.size(), 1);

        // The default layer stays on here: applying a restore must not add one.
        auto w = makeWindow(base, true);
        // 1. The replay alone: on a worker, the studio untouched until the result is applied.
        std::shared_ptr<Recovered> recovered;
        QString error;
        bool done = false;
        w->autosave()->restore(crashed.first(),
                               [&](std::shared_ptr<Recovered> r, const QString& e) {
                                   recovered = std::move(r);
                                   error = e;
                                   done = true;
                               });
        QVERIFY(waitFor([&] { return done; }, 240000));
        QVERIFY2(recovered, qPrintable(error));
        QVERIFY(recovered->worker != std::this_thread::get_id());
        QVERIFY(!w->session()->hasSession());
        QVERIFY(!w->document()->isOpen());
        QVERIFY(QFileInfo::exists(crashed.first()));

        // 2. The whole restore, as "Restore your work? > Yes" does.
        w->restoreFrom(crashed.first());
        QVERIFY(waitFor([&] { return !w->autosave()->restoring(); }, 240000));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QVERIFY(waitFor([&] { return w->session()->hasSession() && !w->session()->busy(); }));
        const denoise::Session want = denoise::Session::load(expected.toStdString());
        const denoise::Session& got = w->session()->session();
        QCOMPARE(got.layerCount(), want.layerCount());
        QVERIFY(got.layerCount() >= 2);  // the default layer and Auto Start's result
        for (std::size_t i = 0; i < want.layerCount(); ++i) {
            QCOMPARE(got.layer(i).filter, want.layer(i).filter);
            QCOMPARE(got.layer(i).params, want.layer(i).params);
            QVERIFY2(sameBits(got.layer(i).weights, want.layer(i).weights),
                     qPrintable(QStringLiteral("layer %1").arg(i)));
        }
        QVERIFY(sameBits(got.composite(), want.composite()));
        // The stroke made before the kill (on the last member's layer) is there; so is auto's
        // correction, with its images, when Auto Start added one.
        QVERIFY(sum(got.layer(lastMember(got)).weights) > 0.0);
        for (std::size_t i = 0; i < want.layerCount(); ++i) {
            QCOMPARE(bool(got.layer(i).correction), bool(want.layer(i).correction));
            if (want.layer(i).correction) {
                QVERIFY(
                    sameBits(got.layer(i).correction->result, want.layer(i).correction->result));
                QVERIFY(sameBits(got.layer(i).correction->blend, want.layer(i).correction->blend));
            }
        }
        // The document, its look and the canvas agree with the session.
        QCOMPARE(w->document()->path(), m_scene);
        QCOMPARE(w->document()->kind(), Document::Kind::Scene);
        const std::string wall = firstAlbedoMaterial(*w->document());
        QCOMPARE(w->document()->lookValue(wall, "albedo"), kAlbedo);
        QCOMPARE(w->document()->finishedFrame(), w->session()->input());
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY(list);
        QCOMPARE(std::size_t(list->count()), got.layerCount());
        // The restored folder goes once this studio's journal holds the restored state.
        QVERIFY(waitFor([&] { return !QFileInfo::exists(crashed.first()); }));
        QVERIFY2(Autosave::crashed(base).isEmpty(),
                 qPrintable(Autosave::crashed(base).join(QStringLiteral(", "))));
        QVERIFY(w->lastStatus().contains(QStringLiteral("Restored")));
    }

    void aBrokenAutosaveChangesNothingSaysSoOnceAndIsKeptAside() {
        const QString folder = crashedAutosave(QStringLiteral("broken"));
        QVERIFY(!folder.isEmpty());
        // An entry the session cannot apply: a stroke on a layer it does not have (what the
        // tester's autosave held).
        {
            QFile journal(QDir(folder).filePath(QStringLiteral("journal.jsonl")));
            QVERIFY(journal.open(QIODevice::Append));
            journal.write(
                R"({"op":"stroke","layer":63,"size":8,"softness":0.5,"mode":"add","dabs":[5,5]})"
                "\n");
        }
        // A studio with work of its own: a Gaussian layer and a look edit.
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("broken-base")));
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        QVERIFY(waitIdle(*w));
        const std::size_t layers = w->session()->session().layerCount();
        const Image composite = w->session()->session().composite();
        const FramePtr input = w->session()->input();
        const QString path = w->document()->path();
        int errors = 0;
        connect(w.get(), &MainWindow::errorShown, this, [&] { ++errors; });

        w->restoreFrom(folder);
        QVERIFY(waitFor([&] { return !w->autosave()->restoring(); }, 120000));
        QVERIFY(waitFor([&] { return errors > 0; }));
        QTest::qWait(50);
        QCOMPARE(errors, 1);
        const QString error = w->lastError();
        QVERIFY2(error.contains(QStringLiteral("journal.jsonl")), qPrintable(error));
        QVERIFY2(error.contains(QStringLiteral("layer 63")), qPrintable(error));
        QVERIFY2(error.contains(QStringLiteral("Nothing was changed")), qPrintable(error));
        // Nothing changed.
        QCOMPARE(w->session()->session().layerCount(), layers);
        QVERIFY(sameBits(w->session()->session().composite(), composite));
        QCOMPARE(w->session()->input(), input);
        QCOMPARE(w->document()->path(), path);
        // Kept aside, not offered again.
        const QString base = QFileInfo(folder).path();
        QVERIFY(Autosave::crashed(base).isEmpty());
        const QStringList kept = keptAside(base);
        QCOMPARE(kept.size(), 1);
        QVERIFY(error.contains(kept.first()));
        QVERIFY(QFileInfo::exists(QDir(base).filePath(kept.first() + "/journal.jsonl")));
        w->offerRestore(true);
        QVERIFY(!w->findChild<QMessageBox*>(QStringLiteral("restoreQuestion")));
    }

    void noKeepsTheAutosaveAsideAndItIsNotOfferedAgain() {
        const QString folder = crashedAutosave(QStringLiteral("declined"));
        QVERIFY(!folder.isEmpty());
        const QString base = QFileInfo(folder).path();
        auto w = makeWindow(base);
        w->offerRestore(true);
        QPointer<QMessageBox> box = w->findChild<QMessageBox*>(QStringLiteral("restoreQuestion"));
        QVERIFY(box);
        QVERIFY(!box->isModal());
        box->button(QMessageBox::No)->click();
        QVERIFY(waitFor([&] { return box.isNull(); }));
        QVERIFY(Autosave::crashed(base).isEmpty());
        const QStringList kept = keptAside(base);
        QCOMPARE(kept.size(), 1);
        QVERIFY(QFileInfo::exists(QDir(base).filePath(kept.first() + "/journal.jsonl")));
        QVERIFY2(w->lastStatus().contains(kept.first()), qPrintable(w->lastStatus()));
        QVERIFY(!w->session()->hasSession());
        // The next start does not ask again.
        auto again = makeWindow(base);
        again->offerRestore(true);
        QVERIFY(!again->findChild<QMessageBox*>(QStringLiteral("restoreQuestion")));
    }

    void aFileOnTheCommandLineOpensWhileTheRestoreQuestionWaits() {
        const QString folder = crashedAutosave(QStringLiteral("waiting"));
        QVERIFY(!folder.isEmpty());
        auto w = makeWindow(QFileInfo(folder).path());
        w->start(m_scene, true);
        QPointer<QMessageBox> box = w->findChild<QMessageBox*>(QStringLiteral("restoreQuestion"));
        QVERIFY(box);
        QVERIFY(!box->isModal());
        // Unanswered, the question holds nothing back: the file opens and renders.
        QVERIFY(waitIdle(*w));
        QCOMPARE(w->document()->path(), m_scene);
        QVERIFY(box && box->isVisible());
        QVERIFY(QFileInfo::exists(folder));
    }
};

// The child of aKilledStudioComesBack…: the default layer, Auto Start, undo, Auto Start again, a
// look edit and a stroke; it saves what the restore should give and dies by SIGKILL.
static int killChild(const QString& base, const QString& scene) {
    StudioOptions options;
    options.autosaveBase = base;
    options.offerRestore = false;
    options.confirmDiscard = false;
    MainWindow w(options);
    w.resize(1000, 700);
    w.show();
    w.openFile(scene);
    if (!waitIdle(w, 60000)) return 3;
    if (!waitFor([&] { return w.session()->session().layerCount() == 1 && !w.session()->busy(); }))
        return 4;  // the default layer
    // Auto Start, undone (one undo step for all its layers), and again: the journal's undo must
    // take back exactly what it did.
    if (!autoStart(w)) return 5;
    w.session()->undoStack()->undo();
    if (w.session()->session().layerCount() != 1) return 6;
    if (!autoStart(w)) return 7;
    // A look edit: a new render, the layers re-applied to it.
    const FramePtr before = w.document()->finishedFrame();
    w.lookPanel()->edit(firstAlbedoMaterial(*w.document()), "albedo", kAlbedo);
    if (!waitFor([&] { return w.document()->finishedFrame() != before; }, 60000)) return 8;
    if (!waitIdle(w, 60000)) return 9;
    // A stroke on the last member's layer (beneath auto's correction, if any).
    const std::size_t last = lastMember(w.session()->session());
    w.session()->beginStroke(last, {12.0, 0.5}, denoise::BrushMode::Add);
    for (double x = 8.0; x < 56.0; x += 4.0) w.session()->dab(x, 24.0);
    w.session()->endStroke();
    bool saved = false;
    w.session()->save(QDir(base).filePath(QStringLiteral("expected.glint-session.json")),
                      std::nullopt, {}, {}, [&](const QString& error) { saved = error.isEmpty(); });
    if (!waitFor([&] { return saved; })) return 10;
    w.autosave()->flush();
    std::raise(SIGKILL);
    return 11;
}

int main(int argc, char** argv) {
    if (argc == 4 && std::strcmp(argv[1], "--kill-child") == 0) {
        QApplication app(argc, argv);
        return killChild(QString::fromLocal8Bit(argv[2]), QString::fromLocal8Bit(argv[3]));
    }
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    RestoreTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "restore_test.moc"
