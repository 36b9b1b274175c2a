// What a session keeps and what counts as unsaved (issue 34, "Lost work"), and the panels around
// it: the look edits and render settings saved with a session and restored before any render,
// an older session file still opening, look and settings edits marking the window unsaved, the
// save dialogs' extensions, the Open dialog's and drag and drop's list of files (the renderer's
// asset formats), the View menu's panel toggles, the render bar's time left and the Tune panel's
// width with the cross-bilateral filter.
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QDockWidget>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QLineEdit>
#include <QListWidget>
#include <QMenu>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QSpinBox>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QToolBar>
#include <QUrl>

#include <functional>

#include "app/actions.h"
#include "app/file_naming.h"
#include "app/program_allowance.h"
#include "app/studio_settings.h"
#include "glint/denoise/external.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/render/asset_formats.h"
#include "heavy_actions.h"
#include "model/layer_names.h"
#include "model/openable_files.h"
#include "model/render_eta.h"
#include "random_edits.h"
#include "studio_fixture.h"
#include "views/look_panel.h"
#include "views/paint_view.h"
#include "views/render_bar.h"
#include "views/tune_view.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

bool unsavedTitle(const MainWindow& w) {
    return w.windowTitle().contains(QStringLiteral(" *"));
}

QMenu* menuNamed(MainWindow& w, const QString& title) {
    for (QAction* a : w.menuBar()->actions())
        if (a->menu() && a->text() == title) return a->menu();
    return nullptr;
}

}  // namespace

class StudioSessionTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;
    int m_windows = 0;

    // A journal of its own for every window.
    QString nextAutosave() { return m_dir.filePath(QStringLiteral("autosave%1").arg(m_windows++)); }

    std::unique_ptr<MainWindow> window() { return makeWindow(nextAutosave()); }

    std::unique_ptr<MainWindow> openScene() { return openAndWait(m_scene, nextAutosave()); }

    // Saves `w`'s session to `name` in the temporary folder and waits until it is written.
    QString save(MainWindow& w, const QString& name) {
        const QString path = m_dir.filePath(name);
        if (!w.saveSession(path)) return {};
        if (!waitFor([&] { return !w.session()->busy(); })) return {};
        return path;
    }

    // The session file at `path` with its view state replaced by `edit` of it (as an older studio
    // or a hand edit wrote it); false when it cannot be read or written.
    static bool editView(const QString& path, const std::function<QJsonObject(QJsonObject)>& edit) {
        QFile file(path);
        if (!file.open(QIODevice::ReadOnly)) return false;
        QJsonObject doc = QJsonDocument::fromJson(file.readAll()).object();
        file.close();
        doc.insert(QStringLiteral("view"), edit(doc.value(QStringLiteral("view")).toObject()));
        if (!file.open(QIODevice::WriteOnly | QIODevice::Truncate)) return false;
        return file.write(QJsonDocument(doc).toJson()) > 0;
    }

    // A window with the session at `path` open, its scene reopened and restored.
    std::unique_ptr<MainWindow> reopen(const QString& path) {
        auto w = window();
        w->openFile(path);
        const bool ok = waitFor([&] {
            return w->session()->hasSession() && !w->session()->busy() &&
                   w->document()->kind() == Document::Kind::Scene && !w->document()->loading() &&
                   w->document()->finishedFrame();
        });
        if (!ok) return nullptr;
        return w;
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    // External denoisers run only the programs the user allowed in the studio's own settings
    // (docs/external-denoiser.md): kept between runs, full paths only.
    void anExternalProgramRunsOnlyOnceAllowedInTheSettings() {
        const QString oidn = QStringLiteral("/opt/oidn/bin/oidnDenoise");
        QSettings().remove(QStringLiteral("externalDenoiser/allowedCommands"));
        applyAllowedCommands();
        const denoise::Filter& external = denoise::findFilter("external");
        denoise::ParamValues params;
        params.strings["command"] = {oidn.toStdString(), "--hdr", "{color}", "-o", "{output}"};
        params = denoise::resolveParams(external, params);
        QVERIFY(!external.unavailable(params).empty());
        QVERIFY(!allowCommandForGood(QStringLiteral("bin/oidnDenoise")));
        QVERIFY(allowCommandForGood(oidn));
        QVERIFY(allowCommandForGood(oidn));
        QCOMPARE(allowedCommands(), QStringList{oidn});
        QVERIFY(external.unavailable(params).empty());
        // The next run of the studio allows what the settings hold, and nothing else.
        denoise::allowCommand("/usr/bin/other");
        applyAllowedCommands();
        QVERIFY(denoise::commandAllowed(oidn.toStdString()));
        QVERIFY(!denoise::commandAllowed("/usr/bin/other"));
        QSettings().remove(QStringLiteral("externalDenoiser/allowedCommands"));
        applyAllowedCommands();
        QVERIFY(!external.unavailable(params).empty());
    }

    // A session naming a program the user has not allowed opens with that layer unavailable and
    // the program not run; a question names the program by its full path, and "Allow" keeps it
    // in the user's settings and runs the layer (docs/external-denoiser.md, "Security").
    void aSessionsExternalProgramRunsOnceAllowedInTheDialog() {
        const QString key = QStringLiteral("externalDenoiser/allowedCommands");
        const QString stub = QStringLiteral(GLINT_EXTERNAL_STUB);
        const QString marker = m_dir.filePath(QStringLiteral("ran"));
        // The session: one external layer (the stub, writing the marker) painted everywhere,
        // saved while the stub is allowed; then the allowance is dropped and the marker removed.
        denoise::ParamValues params;
        params.strings["command"] = {stub.toStdString(), "good",     "exr",
                                     "{color}",          "{output}", marker.toStdString()};
        const QString file = m_dir.filePath(QStringLiteral("ext.glint-session.json"));
        {
            denoise::allowCommand(stub.toStdString());
            FrameBuffers frame(16, 12);
            frame.set(Layer::Color, Image(16, 12, 3, 0.25f));
            denoise::Session s(frame);
            s.addLayer("external", params);
            s.setWeights(0, Image(16, 12, 1, 1.0f));
            s.save(file.toStdString());
        }
        QVERIFY(QFile::remove(marker));
        QSettings().remove(key);
        applyAllowedCommands();
        QVERIFY(!denoise::commandAllowed(stub.toStdString()));

        auto w = window();
        w->openFile(file);
        QVERIFY(waitFor([&] { return w->session()->hasSession() && !w->session()->busy(); }));
        QCOMPARE(w->session()->session().layerCount(), std::size_t(1));
        QVERIFY(!w->session()->session().layer(0).unavailable.empty());
        QVERIFY(!QFile::exists(marker));
        // The palette shows the layer unavailable, with a button that asks again.
        w->setStage(3);
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY(list && list->count() == 1);
        QVERIFY2(list->item(0)->text().contains(QStringLiteral("unavailable")),
                 qPrintable(list->item(0)->text()));
        auto* again = w->paintView()->findChild<QPushButton*>(QStringLiteral("allowProgram"));
        QVERIFY(again && again->isVisible());
        // The question names the program by its full path; "Not now" runs nothing.
        QVERIFY(waitFor([&] { return w->programAllowance()->question() != nullptr; }));
        QVERIFY2(w->programAllowance()->question()->text().contains(stub),
                 qPrintable(w->programAllowance()->question()->text()));
        w->programAllowance()
            ->question()
            ->findChild<QPushButton*>(QStringLiteral("notNow"))
            ->click();
        QVERIFY(waitFor([&] { return w->programAllowance()->question() == nullptr; }));
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));
        QVERIFY(!QFile::exists(marker));
        QVERIFY(allowedCommands().isEmpty());
        // Asked again from the palette, and allowed: kept in the settings, and the layer runs.
        again->click();
        QVERIFY(waitFor([&] { return w->programAllowance()->question() != nullptr; }));
        w->programAllowance()
            ->question()
            ->findChild<QPushButton*>(QStringLiteral("allow"))
            ->click();
        QVERIFY(waitFor([&] {
            return QFile::exists(marker) && !w->session()->busy() &&
                   w->session()->session().layer(0).unavailable.empty();
        }));
        QCOMPARE(allowedCommands(), QStringList{stub});
        QVERIFY(!list->item(0)->text().contains(QStringLiteral("unavailable")));
        QVERIFY(!again->isVisible());
        // The session file never holds the allowance: opened elsewhere, only the settings count.
        QFile saved(file);
        QVERIFY(saved.open(QIODevice::ReadOnly));
        QVERIFY(!saved.readAll().contains("allowedCommands"));
        QSettings().remove(key);
        applyAllowedCommands();
    }

    void randomEditsComeBackBitForBitFromTheSavedSession() {
        // Four fixed seeds, 24 random edits each (random_edits.h: every kind the paint stage
        // offers, look edits and Auto Start among them), saved and reopened in a new window: the
        // layers, names, weights, corrections, composite and look come back bit for bit.
        for (unsigned seed = 21; seed <= 24; ++seed) {
            auto w = openScene();
            QVERIFY(w);
            const std::string wall = firstAlbedoMaterial(*w->document());
            const RandomEdits made = randomEdits(*w, seed, 24, wall, m_dir.path());
            QVERIFY2(made.failure.isEmpty(), qPrintable(made.failure + ": " + made.text()));
            const QString path = save(*w, QStringLiteral("random-%1.glint-session.json").arg(seed));
            QVERIFY(!path.isEmpty());
            auto again = reopen(path);
            QVERIFY(again);
            const QString difference =
                sessionDifference(again->session()->session(), w->session()->session());
            QVERIFY2(
                difference.isEmpty(),
                qPrintable(
                    QStringLiteral("seed %1: %2 after %3").arg(seed).arg(difference, made.text())));
            QCOMPARE(again->document()->lookValue(wall, "albedo"),
                     w->document()->lookValue(wall, "albedo"));
            QCOMPARE(again->region()->coordinates(), w->region()->coordinates());
            QVERIFY(waitFor([&] { return !again->document()->loading(); }));
            const QString reference =
                referenceDifference(again->document()->reference(), w->document()->reference());
            QVERIFY2(reference.isEmpty(), qPrintable(reference + " after " + made.text()));
        }
    }

    void aSessionKeepsTheLookAndTheRenderSettings() {
        auto w = openScene();
        QVERIFY(w);
        const std::string wall = firstAlbedoMaterial(*w->document());
        QVERIFY(!wall.empty());
        const std::array<double, 3> edited{0.2, 0.3, 0.7};
        const std::array<double, 3> original = w->document()->lookValue(wall, "albedo");
        QVERIFY(original != edited);
        w->lookPanel()->edit(wall, "albedo", edited);
        QVERIFY(waitIdle(*w));
        w->renderBar()->sppBox()->setValue(6);
        w->renderBar()->halvesBox()->setChecked(false);  // on by default
        const QString path = save(*w, QStringLiteral("look.glint-session.json"));
        QVERIFY(!path.isEmpty());
        QVERIFY(w->lastError().isEmpty());
        w->close();
        w.reset();

        auto again = reopen(path);
        QVERIFY(again);
        // Restored before any render: the look, the settings and the render bar's controls.
        QVERIFY(waitFor([&] { return again->document()->lookValue(wall, "albedo") == edited; }));
        QCOMPARE(again->document()->settings().spp, 6);
        QVERIFY(!again->document()->settings().halfBuffers);
        QCOMPARE(again->renderBar()->sppBox()->value(), 6);
        QVERIFY(!again->renderBar()->halvesBox()->isChecked());
        QVERIFY(!again->document()->rendering());
        QVERIFY2(!unsavedTitle(*again), qPrintable(again->windowTitle()));
        // A render keeps them.
        again->renderBar()->renderButton()->click();
        QVERIFY(waitIdle(*again));
        QVERIFY(again->document()->lookValue(wall, "albedo") == edited);
        QCOMPARE(again->document()->finishedFrame()->metadata().spp, 6);
        QVERIFY(!again->document()->finishedFrame()->has(Layer::HalfColor));
        QVERIFY(again->lastError().isEmpty());
    }

    void renderSettingsChangesComeBackAfterACrash() {
        auto w = openScene();
        QVERIFY(w);
        // Changed after the last render: only the journal knows them.
        w->renderBar()->sppBox()->setValue(6);
        w->renderBar()->halvesBox()->setChecked(false);  // on by default
        QCOMPARE(w->document()->settings().spp, 6);
        const QString crashed = m_dir.filePath(QStringLiteral("crashed-settings"));
        QVERIFY(copyAsCrashed(*w, crashed));
        auto again = makeWindow(crashed);
        QVERIFY(restore(*again));
        QCOMPARE(again->document()->settings().spp, 6);
        QVERIFY(!again->document()->settings().halfBuffers);
        QCOMPARE(again->renderBar()->sppBox()->value(), 6);
        QVERIFY(!again->renderBar()->halvesBox()->isChecked());
    }

    void anOlderSessionFileStillOpens() {
        auto w = openScene();
        QVERIFY(w);
        const std::array<double, 3> original =
            w->document()->lookValue(firstAlbedoMaterial(*w->document()), "albedo");
        const QString path = save(*w, QStringLiteral("old.glint-session.json"));
        QVERIFY(!path.isEmpty());
        w->close();
        w.reset();
        // The view state as the studio wrote it before sessions kept the look, the halves and
        // the channel.
        QStringList missing;
        bool newKeys = false;
        QVERIFY(editView(path, [&](const QJsonObject& view) {
            QJsonObject old;
            for (const char* key :
                 {"scene", "spp", "seed", "integrator", "mis", "lasso", "exposure", "stage"}) {
                if (!view.contains(QLatin1String(key))) missing << QLatin1String(key);
                old.insert(QLatin1String(key), view.value(QLatin1String(key)));
            }
            newKeys = view.size() > old.size();
            return old;
        }));
        QVERIFY2(missing.isEmpty(), qPrintable(missing.join(QLatin1Char(' '))));
        QVERIFY(newKeys);  // the new keys were there

        auto again = reopen(path);
        QVERIFY(again);
        QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
        QVERIFY(again->document()->lookValue(firstAlbedoMaterial(*again->document()), "albedo") ==
                original);
        QVERIFY(again->document()->settings().halfBuffers);  // missing: the render bar's (on)
        QCOMPARE(again->viewer()->channel(), Viewer::Channel::Result);  // missing: the viewer's
        QVERIFY(!unsavedTitle(*again));
    }

    void theViewersChannelComesBackWithTheSessionAndANameNoChannelHasIsNamed() {
        auto w = openScene();
        QVERIFY(w);
        w->viewer()->setChannel(Viewer::Channel::SampleCount);
        const QString path = save(*w, QStringLiteral("channel.glint-session.json"));
        QVERIFY(!path.isEmpty());
        w->close();
        w.reset();
        auto again = reopen(path);
        QVERIFY(again);
        QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
        QCOMPARE(again->viewer()->channel(), Viewer::Channel::SampleCount);
        QVERIFY(!unsavedTitle(*again));
        again->close();
        again.reset();

        // A name no channel has (a hand edit, a later studio's): said, naming the file and the
        // name; the rest of the session opens and the viewer shows the result.
        QString saved;
        QVERIFY(editView(path, [&](QJsonObject view) {
            saved = view.value(QStringLiteral("channel")).toString();
            view.insert(QStringLiteral("channel"), QStringLiteral("Sample count"));
            return view;
        }));
        QCOMPARE(saved, QStringLiteral("sampleCount"));
        auto bad = reopen(path);
        QVERIFY(bad);
        QVERIFY2(bad->lastError().contains(QLatin1String("Sample count")) &&
                     bad->lastError().contains(QLatin1String("channel.glint-session.json")),
                 qPrintable(bad->lastError()));
        QCOMPARE(bad->viewer()->channel(), Viewer::Channel::Result);
    }

    void lookAndRenderSettingsEditsAreUnsaved() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY2(!unsavedTitle(*w), qPrintable(w->windowTitle()));
        QVERIFY(!w->isModified());
        // A look edit (the re-render starts a new session: the undo stack is clean again).
        const std::string wall = firstAlbedoMaterial(*w->document());
        w->lookPanel()->edit(wall, "albedo", {0.9, 0.1, 0.1});
        QVERIFY(waitIdle(*w));
        QCOMPARE(w->session()->session().layerCount(), std::size_t(0));
        QVERIFY2(unsavedTitle(*w), qPrintable(w->windowTitle()));
        QVERIFY(w->isModified());
        QVERIFY(!save(*w, QStringLiteral("unsaved.glint-session.json")).isEmpty());
        QVERIFY2(!unsavedTitle(*w), qPrintable(w->windowTitle()));
        QVERIFY(!w->isModified());
        // A render setting.
        w->renderBar()->sppBox()->setValue(w->renderBar()->sppBox()->value() + 3);
        QVERIFY2(unsavedTitle(*w), qPrintable(w->windowTitle()));
        QVERIFY(w->isModified());
        w->renderBar()->sppBox()->setValue(w->renderBar()->sppBox()->value() - 3);
        QVERIFY(!w->isModified());  // back to what was saved
        w->renderBar()->halvesBox()->toggle();
        QVERIFY(w->isModified());
    }

    void saveDialogsAddTheChosenFiltersExtension() {
        const QString exr = QStringLiteral("OpenEXR (*.exr)");
        const QString png = QStringLiteral("PNG (*.png)");
        const QString scene = QStringLiteral("Scenes (*.json)");
        const QString session = QStringLiteral("Glint sessions (*.glint-session.json)");
        QCOMPARE(filterExtensions(QStringLiteral("Images (*.exr *.png)")),
                 QStringList({QStringLiteral(".exr"), QStringLiteral(".png")}));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/out"), exr),
                 QStringLiteral("/tmp/out.exr"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/out"), png),
                 QStringLiteral("/tmp/out.png"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/out."), png),
                 QStringLiteral("/tmp/out.png"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/out.EXR"), exr),
                 QStringLiteral("/tmp/out.EXR"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/a.b/box"), scene),
                 QStringLiteral("/tmp/a.b/box.json"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/box.json"), scene),
                 QStringLiteral("/tmp/box.json"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/s"), session),
                 QStringLiteral("/tmp/s.glint-session.json"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/s.json"), session),
                 QStringLiteral("/tmp/s.json.glint-session.json"));
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/s.glint-session.json"), session),
                 QStringLiteral("/tmp/s.glint-session.json"));
        QCOMPARE(withFilterExtension(QString(), exr), QString());
        QCOMPARE(withFilterExtension(QStringLiteral("/tmp/any"), QStringLiteral("All files (*)")),
                 QStringLiteral("/tmp/any"));
        // The name the helper gives is one an export can write.
        auto w = openScene();
        QVERIFY(w);
        const QString out = withFilterExtension(m_dir.filePath(QStringLiteral("typed")), exr);
        QString error = QStringLiteral("not written");
        w->session()->exportResult(out, true, {}, [&](const QString& e) { error = e; });
        QVERIFY(waitFor([&] { return error != QStringLiteral("not written"); }));
        QVERIFY2(error.isEmpty(), qPrintable(error));
        QVERIFY(QFileInfo::exists(m_dir.filePath(QStringLiteral("typed.exr"))));
    }

    void theViewMenuShowsAndHidesEachPanel() {
        auto w = window();
        QMenu* view = menuNamed(*w, QStringLiteral("&View"));
        QVERIFY(view);
        const QList<QDockWidget*> docks = w->findChildren<QDockWidget*>();
        QVERIFY(docks.size() >= 3);
        for (QDockWidget* dock : docks) {
            QAction* toggle = dock->toggleViewAction();
            QVERIFY2(view->actions().contains(toggle), qPrintable(dock->objectName()));
            QVERIFY(dock->isVisible());
            toggle->trigger();
            QVERIFY(!dock->isVisible());
            toggle->trigger();
            QVERIFY(dock->isVisible());
        }
        QToolBar* bar = w->findChild<QToolBar*>(QStringLiteral("renderBar"));
        QVERIFY(bar);
        QVERIFY(view->actions().contains(bar->toggleViewAction()));
    }

    void theTimeLeftIsEstimatedFromTheWorkDone() {
        QVERIFY(!remainingSeconds(0.0, 0, 0.0));
        QVERIFY(!remainingSeconds(0.3, 0, 2.0));  // no pass done yet
        QVERIFY(!remainingSeconds(1.0, 4, 2.0));  // done
        QCOMPARE(*remainingSeconds(0.25, 1, 3.0), 9.0);
        QCOMPARE(formatRemaining(12.2), QStringLiteral("~12 s left"));
        QCOMPARE(formatRemaining(600.0), QStringLiteral("~10 min left"));
        // A long render shows it in the render bar.
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(w->renderBar()->remaining().isEmpty());
        w->renderBar()->sppBox()->setValue(1 << 14);
        w->renderBar()->renderButton()->click();
        QVERIFY(waitFor([&] { return !w->renderBar()->remaining().isEmpty(); }));
        QVERIFY2(w->renderBar()->remaining().endsWith(QStringLiteral(" left")),
                 qPrintable(w->renderBar()->remaining()));
        w->document()->cancelRender();
        QVERIFY(waitFor([&] { return !w->document()->rendering(); }));
        QVERIFY(waitFor([&] { return w->renderBar()->remaining().isEmpty(); }));
    }

    void layersAreNamedReadablyWithTheirParametersInATooltip() {
        QCOMPARE(layerName("nlmeans", {{"strength", 1.2}}),
                 QStringLiteral("Non-local means, strong"));
        QCOMPARE(layerName("nlmeans", {{"strength", 0.45}}),
                 QStringLiteral("Non-local means, medium"));
        QCOMPARE(layerName("cross-bilateral", {{"sigmaS", 4.0}}),
                 QStringLiteral("Cross-bilateral, σs 4"));
        QCOMPARE(layerName("gaussian", {{"sigma", 2.5}}), QStringLiteral("Gaussian, σ 2.5"));
        // The learned filter by its weights' quality (a choice: its option's name).
        QCOMPARE(layerName("unet", {{"quality", 0.0}}), QStringLiteral("Learned (unet), fast"));
        QCOMPARE(layerName("unet", {{"quality", 1.0}}), QStringLiteral("Learned (unet), balanced"));
        auto w = openScene();
        QVERIFY(w);
        w->session()->addLayer("nlmeans", {{"strength", 1.2}});
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == 1; }));
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY(list);
        QCOMPARE(list->count(), 1);
        QCOMPARE(list->item(0)->text(), QStringLiteral("1. Non-local means, strong"));
        const QString tip = list->item(0)->toolTip();
        for (const char* part : {"nlmeans", "patch radius", "search radius", "strength k"})
            QVERIFY2(tip.contains(QLatin1String(part)), qPrintable(tip));
        QCOMPARE(w->session()->undoStack()->undoText(),
                 QStringLiteral("Add Non-local means, strong"));
    }

    void aLayerIsRenamedByDoubleClickUndoablyAndSavedWithTheSession() {
        auto w = openScene();
        QVERIFY(w);
        w->session()->addLayer("nlmeans", {{"strength", 1.2}});
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == 1; }));
        w->setStage(3);
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY(list);
        const QRect row = list->visualItemRect(list->item(0));
        QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, row.center());
        QTest::mouseDClick(list->viewport(), Qt::LeftButton, {}, row.center());
        auto* editor = list->findChild<QLineEdit*>();
        QVERIFY(editor);
        QVERIFY(waitFor([&] { return editor->isVisible(); }, 2000));
        editor->selectAll();
        QTest::keyClicks(editor, QStringLiteral("walls"));
        QTest::keyClick(editor, Qt::Key_Return);
        QVERIFY(waitFor([&] { return w->session()->session().layer(0).name == "walls"; }, 2000));
        QVERIFY(waitFor([&] { return list->item(0)->text() == QStringLiteral("1. walls"); }));
        QCOMPARE(w->session()->undoStack()->undoText(), QStringLiteral("Rename layer 1"));
        w->session()->undoStack()->undo();
        QVERIFY(w->session()->session().layer(0).name.empty());
        QCOMPARE(list->item(0)->text(), QStringLiteral("1. Non-local means, strong"));
        w->session()->undoStack()->redo();
        QCOMPARE(list->item(0)->text(), QStringLiteral("1. walls"));
        // A look edit re-renders and re-applies the layers, the rename in their history.
        const FramePtr before = w->document()->finishedFrame();
        w->lookPanel()->edit(firstAlbedoMaterial(*w->document()), "albedo", {0.2, 0.3, 0.7});
        QVERIFY(waitFor([&] { return w->session()->input() != before; }, 60000));
        QVERIFY(waitIdle(*w));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QCOMPARE(list->item(0)->text(), QStringLiteral("1. walls"));
        // A new session carrying the layers (feature prefiltering turned on) keeps the name.
        w->session()->setOptions({true, {}});
        QVERIFY(waitFor([&] {
            return !w->session()->busy() && w->session()->options().prefilter &&
                   w->session()->session().options().prefilter;
        }));
        QVERIFY(w->session()->session().layer(0).name == "walls");
        const QString path = save(*w, QStringLiteral("named.glint-session.json"));
        QVERIFY(!path.isEmpty());
        w->close();
        w.reset();
        auto again = reopen(path);
        QVERIFY(again);
        QVERIFY(again->session()->session().layer(0).name == "walls");
        auto* againList = again->paintView()->findChild<QListWidget*>();
        QVERIFY(waitFor([&] {
            return againList->count() == 1 &&
                   againList->item(0)->text() == QStringLiteral("1. walls");
        }));
    }

    void aGltfAssetOpensByDropAndItsMetallicRoughnessIsEditable() {
        auto w = window();
        w->renderBar()->sppBox()->setValue(1);
        const QString asset =
            QDir(sourceDir()).filePath(QStringLiteral("tests/fuzz/seeds/gltf/triangle.glb"));
        QMimeData mime;
        mime.setUrls({QUrl::fromLocalFile(asset)});
        // A drop reaches the widget that accepted the drag's entry.
        QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &mime, Qt::LeftButton,
                              Qt::NoModifier);
        QApplication::sendEvent(w.get(), &enter);
        QVERIFY(enter.isAccepted());
        QDropEvent drop(QPointF(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
        QApplication::sendEvent(w.get(), &drop);
        const bool idle = waitIdle(*w, 60000);
        QVERIFY2(idle, qPrintable(QStringLiteral("%1 kind %2 frame %3 session %4 error %5")
                                      .arg(w->document()->path())
                                      .arg(int(w->document()->kind()))
                                      .arg(bool(w->document()->finishedFrame()))
                                      .arg(w->session()->hasSession())
                                      .arg(w->lastError())));
        QCOMPARE(w->document()->kind(), Document::Kind::Scene);
        std::string material;
        for (const render::LookItem& item : w->document()->look())
            if (item.type == "metallicRoughness") material = item.name;
        QVERIFY(!material.empty());
        QVERIFY(
            w->lookPanel()->findChild<QWidget*>(QString::fromStdString(material + "/metallic")));
        QVERIFY(
            w->lookPanel()->findChild<QWidget*>(QString::fromStdString(material + "/roughness")));
        w->lookPanel()->edit(material, "metallic", {0.9, 0.0, 0.0});
        w->lookPanel()->edit(material, "roughness", {0.2, 0.0, 0.0});
        w->lookPanel()->edit(material, "albedo", {0.1, 0.5, 0.9});
        QVERIFY(waitIdle(*w, 60000));
        QCOMPARE(w->document()->lookValue(material, "metallic")[0], 0.9);
        QCOMPARE(w->document()->lookValue(material, "roughness")[0], 0.2);
        QVERIFY(w->isModified());
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
    }

    void theOpenDialogAndDropTakeTheirListFromTheRenderersAssetFormats() {
        // Every asset format the renderer registers, and nothing else, in one list: the Open
        // dialog's filter, drag and drop, and the document's choice of a scene over an EXR.
        const QString filter = openDialogFilter();
        for (const std::string& ext : render::assetExtensions()) {
            const QString e = QString::fromStdString(ext);
            QVERIFY2(openablePatterns().contains(QLatin1Char('*') + e), qPrintable(filter));
            QVERIFY2(filter.contains(QLatin1Char('*') + e + QLatin1Char(' ')), qPrintable(filter));
            QVERIFY(isScenePath(QStringLiteral("/tmp/model") + e.toUpper()));
            QVERIFY(isOpenableFile(QStringLiteral("/tmp/model") + e));
        }
        QCOMPARE(openablePatterns().size(), int(render::assetExtensions().size()) + 2);
        QVERIFY(isScenePath(QStringLiteral("/tmp/scene.json")));
        QVERIFY(!isScenePath(QStringLiteral("/tmp/render.exr")));
        QVERIFY(isOpenableFile(QStringLiteral("/tmp/render.EXR")));
        QVERIFY(!isOpenableFile(QStringLiteral("/tmp/notes.txt")));

        // The Open dialog shows that filter.
        auto w = window();
        QString shown;
        int tries = 0;
        std::function<void()> answer = [&] {
            auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget());
            if (!dialog && ++tries < 100) {
                QTimer::singleShot(50, answer);
                return;
            }
            if (!dialog) return;
            shown = dialog->nameFilters().join(QStringLiteral(";;"));
            dialog->reject();
        };
        QTimer::singleShot(0, answer);
        w->actions().open->trigger();
        QCOMPARE(shown, filter);

        // A drag is let in for an asset and refused for a file the studio does not open.
        auto enters = [&](const QString& file) {
            QMimeData mime;
            mime.setUrls({QUrl::fromLocalFile(file)});
            QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &mime, Qt::LeftButton,
                                  Qt::NoModifier);
            enter.setAccepted(false);
            QApplication::sendEvent(w.get(), &enter);
            return enter.isAccepted();
        };
        for (const std::string& ext : render::assetExtensions())
            QVERIFY(enters(m_dir.filePath(QStringLiteral("model") + QString::fromStdString(ext))));
        QVERIFY(enters(m_dir.filePath(QStringLiteral("scene.json"))));
        QVERIFY(!enters(m_dir.filePath(QStringLiteral("notes.txt"))));
    }

    void aBareObjOpensAsASceneWithItsMtlMaterial() {
        // An OBJ made elsewhere, opened alone: framed and lit as glint-render frames it, its MTL
        // material in the look panel.
        QFile obj(m_dir.filePath(QStringLiteral("quad.obj")));
        QVERIFY(obj.open(QIODevice::WriteOnly));
        obj.write(
            "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl clay\n"
            "f 1 2 3 4\n");
        obj.close();
        QFile mtl(m_dir.filePath(QStringLiteral("quad.mtl")));
        QVERIFY(mtl.open(QIODevice::WriteOnly));
        mtl.write("newmtl clay\nKd 0.8 0.4 0.2\n");
        mtl.close();
        auto w = openAndWait(obj.fileName(), nextAutosave(), false, 60000);
        QVERIFY(w);
        QCOMPARE(w->document()->kind(), Document::Kind::Scene);
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        QCOMPARE(firstAlbedoMaterial(*w->document()), std::string("clay"));
        QCOMPARE(float(w->document()->lookValue("clay", "albedo")[0]), 0.8f);
    }

    void crossBilateralsHelpDoesNotWidenTheTunePanel() {
        auto w = openScene();
        QVERIFY(w);
        w->setStage(2);
        w->tuneView()->setFilter("gaussian");
        QCoreApplication::processEvents();
        const int narrow = w->tuneView()->minimumSizeHint().width();
        w->tuneView()->setFilter("cross-bilateral");
        QVERIFY(w->tuneView()->filter() == "cross-bilateral");
        QCoreApplication::processEvents();
        const int wide = w->tuneView()->minimumSizeHint().width();
        QVERIFY2(wide <= narrow, qPrintable(QStringLiteral("%1 > %2").arg(wide).arg(narrow)));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioSessionTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_session_test.moc"
