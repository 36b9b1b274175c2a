// Defects seen in the screenshot tour (build/screenshots, build/shots-1366), each held down:
// the bank says what it holds (a "bank 24" listed 30 results without saying why), the shortcut
// sheet lays out inside the window on an opaque card at 1366×768 and 1600×1000 (its key column
// was drawn over the left panel), the view bar shows its display mode whole ("False colou"), and
// the status bar's pixel readout ends with "…" instead of a character cut in half, and the paint
// stage's side preview sits under its controls.
#include <QApplication>
#include <QComboBox>
#include <QLabel>
#include <QRegularExpression>
#include <QSpinBox>
#include <QStandardPaths>
#include <QStatusBar>
#include <QStyleOptionComboBox>
#include <QTemporaryDir>
#include <QTest>

#include "glint/denoise/registry.h"
#include "glint/image/io.h"
#include "model/learned_member.h"
#include "studio_fixture.h"
#include "views/elided_label.h"
#include "views/help_overlay.h"
#include "views/image_canvas.h"
#include "views/navigate_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

void settle() {
    for (int i = 0; i < 10; ++i) {
        QCoreApplication::processEvents();
        QTest::qWait(5);
    }
}

QString rectText(const QRect& r) {
    return QStringLiteral("(%1, %2) %3×%4").arg(r.x()).arg(r.y()).arg(r.width()).arg(r.height());
}

// The width a combo box gives its current text.
int comboTextRoom(QComboBox* box) {
    QStyleOptionComboBox option;
    option.initFrom(box);
    option.currentText = box->currentText();
    option.editable = box->isEditable();
    option.frame = box->hasFrame();
    return box->style()
        ->subControlRect(QStyle::CC_ComboBox, &option, QStyle::SC_ComboBoxEditField, box)
        .width();
}

// The filters of the studio's banks: the default bank's, and the learned one when it runs here.
std::size_t studioBankFilterCount() {
    const std::vector<std::string> named = studioBankFilters();
    return named.empty() ? denoise::defaultBankFilters().size() : named.size();
}

// What Navigate says its bank holds: results, sampled, defaults, and (4) the samples left out.
QRegularExpression bankPattern() {
    return QRegularExpression(
        QStringLiteral("^(\\d+) filter results: (\\d+) sampled and the defaults of (\\d+) "
                       "filters(?: \\((\\d+) of the 24 sampled left out: .*\\))?; pick"));
}

}  // namespace

class StudioLayoutTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;

    std::unique_ptr<MainWindow> openScene(QSize size) {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave")));
        if (w) {
            w->resize(size);
            settle();
        }
        return w;
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    // "bank 24" built 30 results (each filter's defaults join the 24 Latin-hypercube samples,
    // as glint-denoise bank --size counts them) and said only "30 filter results". The box and
    // the label now say what the bank holds and why.
    void aBankSaysWhatItHolds() {
        auto w = openScene(QSize(1366, 768));
        QVERIFY(w);
        w->navigateView()->setBankSize(24);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        auto* size = w->navigateView()->findChild<QSpinBox*>();
        QLabel* state = nullptr;
        for (QLabel* label : w->navigateView()->findChildren<QLabel*>())
            if (label->text().contains(QStringLiteral("filter results"))) state = label;
        QVERIFY(size && state);
        QVERIFY2(size->text().contains(QStringLiteral("24 sampled + defaults")),
                 qPrintable(size->text()));
        // The small Cornell box has every feature layer: every filter of the studio's banks
        // joins with its defaults; the samples that fall on a filter with fixed parameters (the
        // learned one) are its default only, and the label says so.
        const std::size_t filters = studioBankFilterCount();
        const QRegularExpressionMatch m = bankPattern().match(state->text());
        QVERIFY2(m.hasMatch(), qPrintable(state->text()));
        const int total = m.captured(1).toInt(), kept = m.captured(2).toInt(),
                  defaults = m.captured(3).toInt();
        QCOMPARE(std::size_t(defaults), filters);
        QCOMPARE(total, kept + defaults);
        if (kept < 24) {
            QVERIFY2(state->text().contains(QStringLiteral("fixed parameters")),
                     qPrintable(state->text()));
            QVERIFY2(!state->text().contains(QStringLiteral("lacks")), qPrintable(state->text()));
        }
        // What the label says is what the navigation holds.
        QVERIFY(w->navigateView()->optionCount() == 4);
    }

    // On an image without feature layers, the sampled members that need one (guided with an
    // albedo, normal or depth guide) are left out; the label says how many, and its numbers add
    // up to the bank's.
    void aBankOfAColourOnlyImageSaysWhatItLeftOut() {
        FrameBuffers frame(48, 32);
        Image colour(48, 32, 3, 0.0f);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 48; ++x)
                for (int c = 0; c < 3; ++c)
                    colour(x, y, c) = float((x * 7 + y * 13 + c * 5) % 17) / 17.0f;
        frame.set(Layer::Color, colour);
        const QString path = m_dir.filePath(QStringLiteral("colour-only.exr"));
        writeExr(frame, path.toStdString());
        auto w = openAndWait(path, m_dir.filePath(QStringLiteral("autosave-exr")));
        QVERIFY(w);
        w->navigateView()->setBankSize(24);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }, 60000));
        QString text;
        for (QLabel* label : w->navigateView()->findChildren<QLabel*>())
            if (label->text().contains(QStringLiteral("filter results"))) text = label->text();
        const QRegularExpressionMatch m = bankPattern().match(text);
        QVERIFY2(m.hasMatch() && !m.captured(4).isEmpty(), qPrintable(text));
        QVERIFY2(text.contains(QStringLiteral("some need layers this image lacks")),
                 qPrintable(text));
        const int total = m.captured(1).toInt(), kept = m.captured(2).toInt(),
                  defaults = m.captured(3).toInt(), left = m.captured(4).toInt();
        QCOMPARE(total, kept + defaults);
        QCOMPARE(kept + left, 24);
        QVERIFY(left > 0);
        // Cross-bilateral needs the features: not every default filter can run.
        QVERIFY(defaults >= 1 && std::size_t(defaults) < studioBankFilterCount());
    }

    void theShortcutSheetFitsTheWindow_data() {
        QTest::addColumn<QSize>("size");
        QTest::newRow("1366x768") << QSize(1366, 768);
        QTest::newRow("1600x1000") << QSize(1600, 1000);
    }

    void theShortcutSheetFitsTheWindow() {
        QFETCH(QSize, size);
        auto w = openScene(size);
        QVERIFY(w);
        QCOMPARE(w->size(), size);
        auto* help = w->findChild<HelpOverlay*>();
        QVERIFY(help && !help->isVisible());
        QTest::keyClick(w.get(), Qt::Key_F1);
        settle();
        QVERIFY(help->isVisible());
        QCOMPARE(help->geometry(), w->rect());
        const HelpOverlay::Sheet sheet = help->layoutFor(help->size());
        const QRect window = w->rect();
        QVERIFY2(window.contains(sheet.card), qPrintable(rectText(sheet.card)));
        QVERIFY(sheet.card.contains(sheet.title) && sheet.card.contains(sheet.footer));
        QVERIFY2(sheet.rows.size() >= 30, qPrintable(QString::number(sheet.rows.size())));
        QVERIFY(sheet.columns >= 1 && sheet.columns <= 3);
        const QFontMetrics fm = help->fontMetrics();
        std::vector<QRect> boxes;
        for (const HelpOverlay::Row& row : sheet.rows) {
            const QString what = row.key + QStringLiteral(" / ") + row.text;
            QVERIFY2(!row.key.isEmpty() && !row.text.isEmpty(), qPrintable(what));
            // Inside the card, above the footer, and whole (no elision at these sizes).
            for (const QRect& r : {row.keyRect, row.textRect}) {
                QVERIFY2(sheet.card.contains(r), qPrintable(what + QLatin1Char(' ') + rectText(r)));
                QVERIFY2(r.bottom() < sheet.footer.top(), qPrintable(what));
                QVERIFY2(r.top() > sheet.title.bottom(), qPrintable(what));
            }
            QVERIFY2(fm.horizontalAdvance(row.key) <= row.keyRect.width(), qPrintable(what));
            QVERIFY2(fm.horizontalAdvance(row.text) <= row.textRect.width(), qPrintable(what));
            boxes.push_back(row.keyRect);
            boxes.push_back(row.textRect);
        }
        // No key or text overlaps another (a column's keys stay clear of the column before).
        for (std::size_t i = 0; i < boxes.size(); ++i)
            for (std::size_t j = i + 1; j < boxes.size(); ++j)
                QVERIFY2(!boxes[i].intersects(boxes[j]),
                         qPrintable(rectText(boxes[i]) + QStringLiteral(" meets ") +
                                    rectText(boxes[j])));
        // The card is opaque: the panels under it do not show through. Its margin left of the
        // first column, from the title to the footer, is one colour.
        const QImage shot = w->grab().toImage();
        const QRect strip(sheet.card.left() + 2, sheet.title.bottom() + 1,
                          sheet.rows.front().keyRect.left() - sheet.card.left() - 4,
                          sheet.footer.top() - sheet.title.bottom() - 1);
        QVERIFY2(strip.width() > 4 && strip.height() > 100, qPrintable(rectText(strip)));
        const QRgb card = shot.pixel(strip.topLeft());
        for (int y = strip.top(); y <= strip.bottom(); ++y)
            for (int x = strip.left(); x <= strip.right(); ++x)
                QVERIFY2(shot.pixel(x, y) == card,
                         qPrintable(QStringLiteral("(%1, %2)").arg(x).arg(y)));
        QTest::keyClick(w.get(), Qt::Key_F1);
        QVERIFY(!help->isVisible());
    }

    // At 1366×768 with the false-colour error shown, the view bar's boxes show their items whole.
    void theViewBarShowsItsChoicesWholeAt1366x768() {
        auto w = openScene(QSize(1366, 768));
        QVERIFY(w);
        w->viewer()->setChannel(Viewer::Channel::ErrorRelative);
        w->viewer()->setDisplayMode(DisplayMode::FalseColor);
        settle();
        int checked = 0;
        for (QComboBox* box : w->viewer()->findChildren<QComboBox*>()) {
            if (!box->isVisible()) continue;
            const QString text = box->currentText();
            if (text != QStringLiteral("False colour") && text != QStringLiteral("Error: relative"))
                continue;
            ++checked;
            QVERIFY2(box->fontMetrics().horizontalAdvance(text) <= comboTextRoom(box),
                     qPrintable(QStringLiteral("%1: %2 px for %3 px of text")
                                    .arg(text)
                                    .arg(comboTextRoom(box))
                                    .arg(box->fontMetrics().horizontalAdvance(text))));
        }
        QCOMPARE(checked, 2);
    }

    // At 1600×1000 the paint stage's side preview sat in the middle of a tall empty area, far
    // from the controls it belongs to: it now starts at the top of its place.
    void theSidePreviewSitsUnderItsControls() {
        auto w = openScene(QSize(1600, 1000));
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        w->setStage(3);
        QLabel* side = nullptr;
        for (QLabel* label : w->findChildren<QLabel*>())
            if (label->toolTip() == QStringLiteral("The selected filter applied everywhere"))
                side = label;
        QVERIFY(side);
        QVERIFY(waitFor([&] { return !side->pixmap().isNull(); }));
        settle();
        const QSize picture = side->pixmap().deviceIndependentSize().toSize();
        QVERIFY2(side->height() > picture.height() + 40,
                 "the preview fills its place: this test no longer tests where it sits");
        // The first row of the grab that differs from the label's background.
        const QImage shot = side->grab().toImage();
        const QRgb background = shot.pixel(0, shot.height() - 1);
        int first = -1;
        for (int y = 0; y < shot.height() && first < 0; ++y)
            if (shot.pixel(shot.width() / 2, y) != background) first = y;
        QVERIFY2(
            first >= 0 && first <= side->contentsRect().top() + 2,
            qPrintable(QStringLiteral("picture from row %1 of %2").arg(first).arg(shot.height())));
    }

    // The pixel readout lists more layers than 1366 px hold: it shows what fits, ends with "…",
    // keeps the whole in its tooltip, and the result comes first.
    void theReadoutEndsWithAnEllipsisAt1366x768() {
        auto w = openScene(QSize(1366, 768));
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        QTest::mouseMove(canvas, canvas->toWidget(QPointF(40.5, 40.5)).toPoint());
        settle();
        auto* readout = w->statusBar()->findChild<ElidedLabel*>();
        QVERIFY(readout);
        const QString full = readout->fullText();
        QVERIFY2(full.startsWith(QStringLiteral("(40, 40)")), qPrintable(full));
        QVERIFY(full.contains(QStringLiteral("result ")));
        const QString shown = readout->text();
        QVERIFY2(readout->fontMetrics().horizontalAdvance(shown) <= readout->contentsRect().width(),
                 qPrintable(shown));
        QVERIFY2(readout->fontMetrics().horizontalAdvance(full) > readout->contentsRect().width(),
                 "the readout fits at 1366 px: this test no longer tests eliding");
        QVERIFY2(shown.endsWith(QChar(0x2026)), qPrintable(shown));
        QCOMPARE(readout->toolTip(), full);
        QVERIFY(shown.contains(QStringLiteral("result ")));
        // Wider, it shows more of the same text.
        w->resize(1600, 1000);
        settle();
        QVERIFY(readout->text().size() > shown.size());
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioLayoutTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_layout_test.moc"
