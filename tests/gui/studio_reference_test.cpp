// The reference is part of what an artist made (reliability round 3): a reference rendered in
// the studio is saved with the session (its pixels in the side folder, with what it was rendered
// for) and comes back with its metrics on reopening; one opened from a file comes back from the
// file when it is unchanged; an unsaved reference makes Quit ask.
#include <QAbstractButton>
#include <QApplication>
#include <QDir>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMessageBox>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

#include "glint/image/io.h"
#include "studio_fixture.h"
#include "views/compare_view.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

class StudioReferenceTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;
    int m_windows = 0;

    QString nextAutosave() { return m_dir.filePath(QStringLiteral("autosave%1").arg(m_windows++)); }

    // Saves `w`'s session to `name` and waits until it is written (the title then is clean).
    QString save(MainWindow& w, const QString& name) {
        const QString path = m_dir.filePath(name);
        if (!w.saveSession(path)) return {};
        if (!waitFor([&] { return !w.session()->busy() && !w.isModified(); })) return {};
        return path;
    }

    // Waits for the compare panel's metrics against a reference.
    static bool waitMetrics(MainWindow& w) {
        return waitFor([&] { return w.compareView()->measurement().haveReference; });
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void aRenderedReferenceIsSavedWithTheSessionAndComesBackWithItsMetrics() {
        auto w = openAndWait(m_scene, nextAutosave());
        QVERIFY(w);
        QVERIFY(!w->isModified());
        w->document()->renderReference(8);
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }, 60000));
        // An unsaved reference is unsaved work.
        QVERIFY(w->isModified());
        QVERIFY(w->windowTitle().contains(QStringLiteral(" *")));
        QVERIFY(waitMetrics(*w));
        const Measurement before = w->compareView()->measurement();
        const FramePtr reference = w->document()->reference();

        const QString path = save(*w, QStringLiteral("rendered.glint-session.json"));
        QVERIFY(!path.isEmpty());
        // The pixels in the side folder, what it was rendered for in the session file.
        const QString side = m_dir.filePath(QStringLiteral("rendered.glint-session"));
        QVERIFY(QFileInfo::exists(QDir(side).filePath(QStringLiteral("reference.exr"))));
        QFile json(path);
        QVERIFY(json.open(QIODevice::ReadOnly));
        const QJsonObject doc = QJsonDocument::fromJson(json.readAll()).object();
        QCOMPARE(doc.value(QStringLiteral("frames")).toObject().value(QStringLiteral("reference")),
                 QJsonValue(QStringLiteral("reference.exr")));
        const QJsonObject view = doc.value(QStringLiteral("view")).toObject();
        QCOMPARE(view.value(QStringLiteral("reference/source")).toString(),
                 QStringLiteral("rendered"));
        QCOMPARE(view.value(QStringLiteral("reference/spp")).toString(), QStringLiteral("8"));
        QCOMPARE(view.value(QStringLiteral("reference/scene")).toString(),
                 QFileInfo(m_scene).absoluteFilePath());
        QVERIFY(view.value(QStringLiteral("reference/camera"))
                    .toString()
                    .contains(QStringLiteral("lookAt")));
        w.reset();

        // A new window: the reference and the metrics come back, the title is clean.
        auto again = makeWindow(nextAutosave());
        again->openFile(path);
        QVERIFY(waitFor([&] { return again->document()->reference() != nullptr; }));
        QVERIFY(waitIdle(*again));
        QVERIFY(sameBits(again->document()->reference()->color(), reference->color()));
        QVERIFY(again->document()->referenceInfo());
        QCOMPARE(again->document()->referenceInfo()->settings.spp, 8);
        QVERIFY(!again->document()->referenceLookDiffers());
        QVERIFY(!again->isModified());
        QVERIFY(waitMetrics(*again));
        const Measurement after = again->compareView()->measurement();
        QCOMPARE(after.ssimImage, before.ssimImage);
        QCOMPARE(after.relMseImage, before.relMseImage);
        QCOMPARE(after.psnrImage, before.psnrImage);
        // Clearing it is an unsaved change again.
        again->document()->clearReference();
        QVERIFY(again->isModified());
    }

    void aReferenceFromAFileComesBackFromTheFileWhenItIsUnchanged() {
        auto w = openAndWait(m_scene, nextAutosave());
        QVERIFY(w);
        // A "high-spp" EXR of the same size: the render itself will do.
        const QString exr = m_dir.filePath(QStringLiteral("reference-file.exr"));
        writeExr(*w->document()->finishedFrame(), exr.toStdString());
        w->document()->openReference(exr);
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }));
        QVERIFY(w->isModified());
        const QString path = save(*w, QStringLiteral("file.glint-session.json"));
        QVERIFY(!path.isEmpty());
        // Remembered by path, not copied.
        QVERIFY(!QFileInfo::exists(
            QDir(m_dir.filePath(QStringLiteral("file.glint-session"))).filePath("reference.exr")));
        w.reset();

        auto again = makeWindow(nextAutosave());
        again->openFile(path);
        QVERIFY(waitFor([&] { return again->document()->reference() != nullptr; }));
        QCOMPARE(QString::fromStdString(again->document()->referenceInfo()->file),
                 QFileInfo(exr).absoluteFilePath());
        QVERIFY(waitIdle(*again));
        QVERIFY(waitMetrics(*again));
        QVERIFY(!again->isModified());
        again.reset();

        // The file changed since: it is not taken for the reference, and the dialog says why.
        FrameBuffers changed = readExr(exr.toStdString());
        for (float& v : changed.color().data()) v *= 2.0f;
        writeExr(changed, exr.toStdString());
        auto third = makeWindow(nextAutosave());
        third->openFile(path);
        QVERIFY(waitFor([&] { return third->lastError().contains(QStringLiteral("changed")); }));
        QVERIFY(third->lastError().contains(QFileInfo(exr).fileName()));
        QVERIFY(waitIdle(*third));
        QVERIFY(!third->document()->reference());
    }

    void aRenderedReferenceComesBackFromTheAutosave() {
        auto w = openAndWait(m_scene, nextAutosave());
        QVERIFY(w);
        w->document()->renderReference(8);
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }, 60000));
        const FramePtr reference = w->document()->reference();
        w->autosave()->flush();
        // The journal as a crash leaves it: a copy in a folder no running studio owns.
        const QString crashed = m_dir.filePath(QStringLiteral("crash/999999"));
        QDir().mkpath(crashed);
        const QDir journal(w->autosave()->journal()->folder());
        for (const QString& f : journal.entryList(QDir::Files))
            QVERIFY(QFile::copy(journal.filePath(f), QDir(crashed).filePath(f)));
        w.reset();

        StudioOptions options;
        options.autosaveBase = m_dir.filePath(QStringLiteral("crash"));
        options.offerRestore = false;
        options.confirmDiscard = false;
        options.denoiseFirstImage = false;
        MainWindow restored(options);
        restored.show();
        restored.offerRestore(false);
        QVERIFY(waitFor([&] { return !restored.autosave()->restoring(); }, 60000));
        QVERIFY(waitFor([&] { return restored.document()->reference() != nullptr; }));
        QVERIFY(sameBits(restored.document()->reference()->color(), reference->color()));
        QCOMPARE(restored.document()->referenceInfo()->settings.spp, 8);
        QVERIFY(restored.isModified());  // restored, not saved in a session file
        QVERIFY(waitMetrics(restored));
    }

    void quittingWithAnUnsavedReferenceAsks() {
        StudioOptions options;
        options.autosaveBase = nextAutosave();
        options.offerRestore = false;
        options.confirmDiscard = true;  // as the artist runs it
        options.denoiseFirstImage = false;
        MainWindow w(options);
        w.resize(1280, 800);
        w.show();
        w.openFile(m_scene);
        QVERIFY(waitIdle(w));
        QVERIFY(!w.isModified());
        w.document()->renderReference(8);
        QVERIFY(waitFor([&] { return w.document()->reference() != nullptr; }, 60000));

        // The question comes up as a modal box: read it and answer Cancel.
        QString asked;
        QTimer answer;
        answer.setInterval(20);
        connect(&answer, &QTimer::timeout, this, [&] {
            auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget());
            if (!box) return;
            asked = box->text();
            box->button(QMessageBox::Cancel)->click();
        });
        answer.start();
        QVERIFY(!w.close());
        answer.stop();
        QVERIFY2(asked.contains(QStringLiteral("unsaved")), qPrintable(asked));
        QVERIFY(w.isVisible());
        // Saved, the window closes without a question.
        QVERIFY(!save(w, QStringLiteral("quit.glint-session.json")).isEmpty());
        QVERIFY(w.close());
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioReferenceTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_reference_test.moc"
