// Studio.FirstSession (issue 48): a first-time artist's session needs nothing outside the F1
// sheet and the visible panels. Open a scene, change a wall's colour in the Look panel, Auto
// Start, paint a stroke on the result layer, render a reference from the Compare panel, save,
// close, reopen: the layers, the look edit and the reference come back. Every action is found on
// the F1 sheet by its text and triggered through the key the sheet names; every other step is a
// visible widget (a spin box, a button, a list row, the canvas). The model is only read, to
// assert. docs/studio.md, "Your first session", walks the same steps.
#include <QAction>
#include <QApplication>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QListWidget>
#include <QPushButton>
#include <QSpinBox>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>

#include "glint/denoise/session.h"
#include "studio_fixture.h"
#include "views/compare_view.h"
#include "views/help_overlay.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/paint_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// The action the F1 sheet lists as `text` (no "&", no "…"), found through the key the sheet
// shows beside it; null when the sheet does not name it or no action of the window has that key.
QAction* fromSheet(MainWindow& w, const QString& text) {
    auto* help = w.findChild<HelpOverlay*>();
    if (!help) return nullptr;
    for (const HelpOverlay::Row& row : help->layoutFor(w.size()).rows) {
        if (row.text != text) continue;
        for (QAction* a : w.QWidget::actions()) {
            QString shown = a->text();
            shown.remove(QLatin1Char('&'));
            shown.remove(QStringLiteral("…"));
            if (shown == text && a->shortcut().toString(QKeySequence::NativeText) == row.key)
                return a;
        }
    }
    return nullptr;
}

// One try at answering the open file dialog with `path` (as a user types a name and presses
// Enter); tried again every 50 ms, 200 times at most.
void answerFileDialogTry(const QString& path, int tries) {
    auto* dialog = qobject_cast<QFileDialog*>(QApplication::activeModalWidget());
    if (!dialog) {
        if (tries < 200)
            QTimer::singleShot(50, [path, tries] { answerFileDialogTry(path, tries + 1); });
        return;
    }
    dialog->selectFile(path);
    static_cast<QDialog*>(dialog)->accept();  // as Enter in the name box
}

// Answers the next file dialog with `path` once it is open (each try re-arms a timer: no
// self-owning callback, which LeakSanitizer reported).
void answerFileDialog(const QString& path) {
    QTimer::singleShot(0, [path] { answerFileDialogTry(path, 0); });
}

// Drags the canvas through image points `path` with `button`.
void drag(ImageCanvas* canvas, const QVector<QPointF>& path, Qt::MouseButton button) {
    auto at = [&](const QPointF& p) { return canvas->toWidget(p).toPoint(); };
    QTest::mousePress(canvas, button, {}, at(path.first()));
    for (qsizetype i = 1; i < path.size(); ++i) QTest::mouseMove(canvas, at(path[i]), 1);
    QTest::mouseRelease(canvas, button, {}, at(path.last()));
}

// The visible push button of `parent` reading `text`.
QPushButton* button(QWidget* parent, const QString& text) {
    for (QPushButton* b : parent->findChildren<QPushButton*>())
        if (b->text() == text) return b;
    return nullptr;
}

// Every metric of the Compare panel's table is a figure (not empty, not "stale").
bool figuresShown(const CompareView& c) {
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 4; ++col) {
            bool number = false;
            c.cellText(row, col).toDouble(&number);
            if (!number) return false;
        }
    return !c.metricsStale();
}

}  // namespace

class StudioFirstSessionTest : public QObject {
    Q_OBJECT

    QTemporaryDir m_dir;

  private slots:
    void aFirstSessionNeedsNothingOutsideTheShortcutSheet() {
        QVERIFY(m_dir.isValid());
        const QString scene = writeSmallCornell(m_dir);
        const QString saved = m_dir.filePath(QStringLiteral("first.glint-session.json"));
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave0")));

        // 1. Open (Ctrl+O): the Open dialog, the scene chosen.
        QAction* open = fromSheet(*w, QStringLiteral("Open"));
        QVERIFY2(open, "the F1 sheet names Open");
        answerFileDialog(scene);
        open->trigger();
        QVERIFY(waitIdle(*w));

        // 2. The Look panel: the first wall's blue typed in its colour row; the scene re-renders.
        const std::string wall = firstAlbedoMaterial(*w->document());
        QVERIFY(!wall.empty());
        auto* row = w->lookPanel()->findChild<QWidget*>(QString::fromStdString(wall + "/albedo"));
        QVERIFY(row);
        auto* blue = row->findChild<QDoubleSpinBox*>(QStringLiteral("c2"));
        QVERIFY(blue);
        // The colour as it was (the untouched channels keep their full precision), the blue
        // one retyped.
        auto edited = w->document()->lookValue(wall, "albedo");
        edited[2] = blue->value() > 0.5 ? 0.125 : 0.875;
        const FramePtr before = w->document()->finishedFrame();
        blue->selectAll();
        QTest::keyClicks(blue, QString::number(edited[2]));
        QTest::keyClick(blue, Qt::Key_Return);
        QVERIFY2(blue->value() == edited[2], qPrintable(blue->text()));
        QVERIFY(waitFor([&] { return w->document()->lookValue(wall, "albedo") == edited; }, 5000));
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));

        // 3. Auto Start (Ctrl+Shift+A): one result layer, on the Paint stage.
        QAction* autoStart = fromSheet(*w, QStringLiteral("Auto Start"));
        QVERIFY2(autoStart, "the F1 sheet names Auto Start");
        autoStart->trigger();
        const denoise::Session& s = w->session()->session();
        QVERIFY(waitFor([&] { return s.layerCount() == 1 && !w->session()->busy(); }));
        QCOMPARE(w->stage(), 3);

        // 4. Paint: the layer's row clicked, the brush (B), a right-button stroke paints it out.
        auto* layers = w->paintView()->findChild<QListWidget*>();
        QVERIFY(layers && layers->count() == 1 && layers->isVisible());
        QTest::mouseClick(layers->viewport(), Qt::LeftButton, {},
                          layers->visualItemRect(layers->item(0)).center());
        QCOMPARE(layers->currentRow(), 0);
        QAction* brush = fromSheet(*w, QStringLiteral("Brush"));
        QVERIFY2(brush, "the F1 sheet names Brush");
        brush->trigger();
        ImageCanvas* canvas = w->viewer()->canvas();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        const float weightBefore = s.layer(0).weights(32, 24, 0);
        QVERIFY(weightBefore > 0.5f);
        const int steps = w->session()->undoStack()->count();
        drag(canvas, {{16, 24}, {24, 24}, {32, 24}, {40, 24}, {48, 24}}, Qt::RightButton);
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));
        QVERIFY(s.layer(0).weights(32, 24, 0) < weightBefore);
        QCOMPARE(w->session()->undoStack()->count(), steps + 1);
        const Image weights = s.layer(0).weights;

        // 5. Compare: a reference rendered at the panel's lowest spp; figures, none stale.
        CompareView* compare = w->compareView();
        QSpinBox* spp = nullptr;
        for (QSpinBox* box : compare->findChildren<QSpinBox*>())
            if (box->prefix() == QStringLiteral("spp ")) spp = box;
        QVERIFY(spp);
        spp->setValue(spp->minimum());
        QPushButton* renderReference = button(compare, QStringLiteral("Render reference"));
        QVERIFY(renderReference);
        renderReference->click();
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }));
        QVERIFY(waitFor([&] { return compare->measurement().haveReference; }));
        QVERIFY2(figuresShown(*compare), qPrintable(compare->cellText(0, 0)));

        // 6. Save (Ctrl+S): the Save dialog asks for a name the first time.
        QAction* save = fromSheet(*w, QStringLiteral("Save Session"));
        QVERIFY2(save, "the F1 sheet names Save Session");
        answerFileDialog(saved);
        save->trigger();
        QVERIFY(waitFor([&] { return !w->session()->busy() && QFileInfo::exists(saved); }));
        QVERIFY(waitFor([&] { return !w->isModified(); }));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));

        // 7. Close, and 8. open the session again (Ctrl+O) in a new window.
        QVERIFY(w->close());
        w.reset();
        auto again = makeWindow(m_dir.filePath(QStringLiteral("autosave1")));
        answerFileDialog(saved);
        QAction* reopen = fromSheet(*again, QStringLiteral("Open"));
        QVERIFY(reopen);
        reopen->trigger();
        QVERIFY(waitFor([&] {
            return again->session()->hasSession() && !again->session()->busy() &&
                   again->document()->kind() == Document::Kind::Scene &&
                   !again->document()->loading() && again->document()->finishedFrame() &&
                   again->document()->reference() != nullptr;
        }));
        // The layer and its painted weights, the look edit and the reference with its figures.
        const denoise::Session& back = again->session()->session();
        QCOMPARE(back.layerCount(), std::size_t(1));
        QVERIFY(sameBits(back.layer(0).weights, weights));
        QVERIFY(again->document()->lookValue(wall, "albedo") == edited);
        QVERIFY(waitFor([&] { return again->compareView()->measurement().haveReference; }));
        QVERIFY2(figuresShown(*again->compareView()),
                 qPrintable(again->compareView()->cellText(0, 0)));
        QVERIFY2(again->lastError().isEmpty(), qPrintable(again->lastError()));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioFirstSessionTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_first_session_test.moc"
