// The studio on a 1366×768 laptop, its tools and its keys: the window's minimum size in every
// stage, what shows at that size, the one-shot render-region tool, one source of truth for the
// canvas tool, single-key shortcuts wherever the focus is (but a field being typed in), the look
// panel's sliders, swatches and refusals, the render bar's figures and the paint stage's side
// preview, and the first stroke after a click in a side panel.
#include <QApplication>
#include <QComboBox>
#include <QDockWidget>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QLabel>
#include <QListWidget>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSlider>
#include <QSpinBox>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QToolBar>
#include <QToolButton>

#include "glint/denoise/session.h"
#include "studio_fixture.h"
#include "views/compare_view.h"
#include "views/convergence_plot.h"
#include "views/image_canvas.h"
#include "views/log_control.h"
#include "views/look_panel.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/param_controls.h"
#include "views/region_view.h"
#include "views/render_bar.h"
#include "views/tune_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// A 1366×768 screen less the window manager's title bar and a panel.
constexpr int kMaxWidth = 1340, kMaxHeight = 720;

void drag(ImageCanvas* canvas, const QVector<QPointF>& path) {
    auto at = [&](const QPointF& p) { return canvas->toWidget(p).toPoint(); };
    QTest::mousePress(canvas, Qt::LeftButton, {}, at(path.first()));
    for (qsizetype i = 1; i < path.size(); ++i) QTest::mouseMove(canvas, at(path[i]), 1);
    QTest::mouseRelease(canvas, Qt::LeftButton, {}, at(path.last()));
}

void settle() {
    for (int i = 0; i < 10; ++i) {
        QCoreApplication::processEvents();
        QTest::qWait(5);
    }
}

// `widget`'s rectangle in `window` coordinates.
QRect inWindow(const QWidget* widget, const QWidget* window) {
    return QRect(widget->mapTo(window, QPoint(0, 0)), widget->size());
}

template <class T>
T* childWithText(QWidget* parent, const QString& text) {
    for (T* b : parent->findChildren<T*>())
        if (b->text() == text) return b;
    return nullptr;
}

// The minimum sizes of the window's parts, for a failure message.
QString parts(MainWindow& w) {
    QStringList list;
    auto add = [&](const QString& name, const QWidget* part) {
        if (!part) return;
        const QSize m = part->minimumSizeHint().expandedTo(part->minimumSize());
        list << QStringLiteral("%1 %2×%3").arg(name).arg(m.width()).arg(m.height());
    };
    add(QStringLiteral("central"), w.centralWidget());
    for (const QDockWidget* d : w.findChildren<QDockWidget*>()) add(d->objectName(), d);
    for (const QWidget* t : w.findChildren<QToolBar*>()) add(t->objectName(), t);
    return list.join(QStringLiteral(", "));
}

double paintedSum(const MainWindow& w) {
    double s = 0.0;
    const denoise::Session& session = const_cast<MainWindow&>(w).session()->session();
    for (std::size_t i = 0; i < session.layerCount(); ++i)
        for (float v : session.layer(i).painted.data()) s += v;
    return s;
}

// One stroke with the mouse from `from` to `to` (image pixels), as a user drags.
void stroke(ImageCanvas* canvas, QPointF from, QPointF to) {
    auto at = [&](const QPointF& p) { return canvas->toWidget(p).toPoint(); };
    QTest::mousePress(canvas, Qt::LeftButton, {}, at(from));
    for (int k = 1; k <= 8; ++k) QTest::mouseMove(canvas, at(from + (to - from) * (k / 8.0)), 1);
    QTest::mouseRelease(canvas, Qt::LeftButton, {}, at(to));
}

}  // namespace

class StudioFitTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;

    std::unique_ptr<MainWindow> openScene() {
        return openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave")));
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void theMinimumSizeFitsA1366x768ScreenInEveryStage() {
        auto w = openScene();
        QVERIFY(w);
        const std::pair<int, bool> stages[] = {
            {0, false}, {1, false}, {2, false}, {2, true}, {3, false}};
        for (const auto& [stage, navigate] : stages) {
            w->setStage(stage, navigate);
            if (navigate) QVERIFY(waitFor([&] { return w->navigateView()->ready(); }));
            settle();
            const QSize least = w->minimumSizeHint().expandedTo(w->minimumSize());
            qInfo("stage %d%s: minimum %d×%d (%s)", stage + 1, navigate ? " (navigate)" : "",
                  least.width(), least.height(), qPrintable(parts(*w)));
            QVERIFY2(least.width() <= kMaxWidth && least.height() <= kMaxHeight,
                     qPrintable(QStringLiteral("stage %1%2: minimum %3×%4 (%5)")
                                    .arg(stage + 1)
                                    .arg(navigate ? QStringLiteral(" (navigate)") : QString())
                                    .arg(least.width())
                                    .arg(least.height())
                                    .arg(parts(*w))));
        }
    }

    void at1366x768TheStatusBarAndNavigateButtonsShowUncovered() {
        auto w = openScene();
        QVERIFY(w);
        w->resize(1366, 768);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }));
        settle();
        QVERIFY2(w->size() == QSize(1366, 768),
                 qPrintable(
                     QStringLiteral("%1×%2 (%3)").arg(w->width()).arg(w->height()).arg(parts(*w))));
        const QRect window = w->rect();
        QStatusBar* status = w->statusBar();
        QVERIFY(status->isVisible());
        QVERIFY(window.contains(inWindow(status, w.get())));
        const QDockWidget* compare = w->findChild<QDockWidget*>(QStringLiteral("compare"));
        QVERIFY(compare);
        for (const QString& text : {QStringLiteral("They look the same"), QStringLiteral("Back"),
                                    QStringLiteral("Restart")}) {
            auto* button = childWithText<QPushButton>(w->navigateView(), text);
            QVERIFY(button);
            QVERIFY(button->isVisible());
            const QRect r = inWindow(button, w.get());
            QVERIFY2(window.contains(r), qPrintable(text));
            // Inside what its scroll area shows, and not under the Compare panel.
            if (auto* area =
                    qobject_cast<QScrollArea*>(w->navigateView()->parentWidget()->parentWidget()))
                QVERIFY2(inWindow(area->viewport(), w.get()).contains(r), qPrintable(text));
            if (compare->isVisible())
                QVERIFY2(!inWindow(compare, w.get()).intersects(r), qPrintable(text));
        }
    }

    void theConvergencePlotsTextsFitAt1366x768() {
        auto w = openScene();
        QVERIFY(w);
        w->resize(1366, 768);
        settle();
        auto* plot = w->findChild<ConvergencePlot*>();
        QVERIFY(plot);
        QVERIFY(plot->height() >= plot->minimumHeight());
        // Scrolled to, the whole plot shows in its panel (the panel scrolls at this size).
        QScrollArea* area = nullptr;
        for (QWidget* p = plot->parentWidget(); p && !area; p = p->parentWidget())
            area = qobject_cast<QScrollArea*>(p);
        if (area) {
            area->ensureWidgetVisible(plot, 0, 0);
            settle();
        }
        if (area)
            QVERIFY2(inWindow(area->viewport(), w.get()).contains(inWindow(plot, w.get())),
                     qPrintable(QStringLiteral("plot %1 px tall, panel viewport %2 px")
                                    .arg(plot->height())
                                    .arg(area->viewport()->height())));
        plot->setPoints({{0.05, 1, 0.31}, {0.4, 8, 0.0421}, {3.2, 64, 0.00087}});
        const QFontMetricsF fm(plot->font());
        for (bool spp : {false, true}) {
            plot->setAgainstSpp(spp);
            const ConvergencePlot::Texts t = plot->texts();
            QCOMPARE(t.items.size(), std::size_t(5));  // the title and four tick labels
            for (std::size_t i = 0; i < t.items.size(); ++i) {
                const auto& [box, text] = t.items[i];
                const QString what = QStringLiteral("'%1' at %2,%3 %4×%5 in %6×%7")
                                         .arg(text)
                                         .arg(box.x())
                                         .arg(box.y())
                                         .arg(box.width())
                                         .arg(box.height())
                                         .arg(plot->width())
                                         .arg(plot->height());
                // Inside the widget, as wide as its text, clear of the frame and the others.
                QVERIFY2(QRectF(plot->rect()).contains(box), qPrintable(what));
                QVERIFY2(fm.horizontalAdvance(text) <= box.width() + 0.5, qPrintable(what));
                QVERIFY2(!t.area.intersects(box), qPrintable(what));
                for (std::size_t j = 0; j < i; ++j)
                    QVERIFY2(!t.items[j].first.intersects(box), qPrintable(what));
            }
            QVERIFY(!t.items[0].second.contains(QChar(0x2026)));  // the title is not elided
        }
    }

    void theRenderRegionToolDisarmsAfterOneRectangle() {
        auto w = openScene();
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        QToolButton* regionTool = w->renderBar()->regionButton();
        w->setStage(1);
        w->regionView()->selectTool(ImageCanvas::Tool::Rectangle);
        regionTool->click();
        QVERIFY(regionTool->isChecked());
        const FramePtr before = w->document()->finishedFrame();
        drag(canvas, {{8, 8}, {20, 16}, {30, 24}});
        QVERIFY(!regionTool->isChecked());
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Rectangle);
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));
        QVERIFY(w->region()->wholeImage());  // the render's rectangle is not the region
        // The next rectangle is a region, and renders nothing.
        const FramePtr rendered = w->document()->finishedFrame();
        drag(canvas, {{4, 4}, {30, 20}, {40, 30}});
        QVERIFY(!w->region()->wholeImage());
        settle();
        QVERIFY(!w->document()->rendering());
        QCOMPARE(w->document()->finishedFrame(), rendered);
        // A stage change disarms it too.
        regionTool->click();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::RenderRegion);
        w->setStage(3);
        QVERIFY(!regionTool->isChecked());
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
    }

    void shortcutsAndToolButtonsShareOneTool() {
        auto w = openScene();
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        auto* brush = childWithText<QToolButton>(w->paintView(), QStringLiteral("Brush"));
        auto* wand = childWithText<QToolButton>(w->paintView(), QStringLiteral("Magic wand"));
        QVERIFY(brush && wand);
        QTest::keyClick(w.get(), Qt::Key_M);
        QCOMPARE(w->stage(), 3);
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Wand);
        QVERIFY(wand->isChecked());
        QVERIFY(!brush->isChecked());
        brush->click();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        QTest::keyClick(w.get(), Qt::Key_M);
        QTest::keyClick(w.get(), Qt::Key_B);
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        QVERIFY(brush->isChecked());
        // L is stage 2 with the lasso, whichever tool stage 2 had.
        w->setStage(1);
        childWithText<QToolButton>(w->regionView(), QStringLiteral("Rectangle"))->click();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Rectangle);
        w->setStage(3);
        QTest::keyClick(w.get(), Qt::Key_L);
        QCOMPARE(w->stage(), 1);
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Lasso);
        QVERIFY(childWithText<QToolButton>(w->regionView(), QStringLiteral("Lasso"))->isChecked());
    }

    void singleKeysActOnTheCanvasUnlessAFieldIsBeingEdited() {
        auto w = openScene();
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        QSpinBox* seed = nullptr;
        for (QSpinBox* s : w->renderBar()->findChildren<QSpinBox*>())
            if (s->prefix().startsWith(QStringLiteral("seed"))) seed = s;
        QVERIFY(seed);
        // Typing a seed: the digits go into it; Enter hands the keys back to the canvas.
        QTest::mouseClick(seed, Qt::LeftButton);
        QVERIFY(seed->hasFocus());
        seed->selectAll();
        QTest::keyClicks(QApplication::focusWidget(), QStringLiteral("5"));
        QTest::keyClick(QApplication::focusWidget(), Qt::Key_Return);
        QCOMPARE(seed->value(), 5);
        QVERIFY(canvas->hasFocus());
        QTest::keyClick(QApplication::focusWidget(), Qt::Key_2);
        QCOMPARE(w->stage(), 1);
        QCOMPARE(seed->value(), 5);
        // A combo box with the focus does not take Space: A/B flips.
        auto* integrator = w->renderBar()->findChild<QComboBox*>();
        integrator->setFocus();
        QVERIFY(integrator->hasFocus());
        const bool flipped = canvas->flipped();
        QTest::keyClick(integrator, Qt::Key_Space);
        QCOMPARE(canvas->flipped(), !flipped);
        QVERIFY(!QApplication::activePopupWidget());
        // Escape leaves a field for the canvas.
        QTest::mouseClick(seed, Qt::LeftButton);
        QVERIFY(seed->hasFocus());
        QTest::keyClick(QApplication::focusWidget(), Qt::Key_Escape);
        QVERIFY(canvas->hasFocus());
    }

    void tabReachesThePanelFieldsAndSingleKeysStillGoToTheCanvas() {
        auto w = openScene();
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        QSpinBox* spp = w->renderBar()->sppBox();
        canvas->setFocus();
        QVERIFY(canvas->hasFocus());
        // Tab from the canvas through the window's fields until the spp box has the focus.
        bool reached = false;
        for (int i = 0; i < 120 && !reached; ++i) {
            QTest::keyClick(QApplication::focusWidget(), Qt::Key_Tab);
            reached = spp->hasFocus();
        }
        QVERIFY2(reached, "Tab never reached the spp box");
        // A keyboard user types into it; Enter hands the keys back to the canvas.
        spp->selectAll();
        QTest::keyClicks(QApplication::focusWidget(), QStringLiteral("9"));
        QTest::keyClick(QApplication::focusWidget(), Qt::Key_Return);
        QCOMPARE(spp->value(), 9);
        QVERIFY(canvas->hasFocus());
        QTest::keyClick(QApplication::focusWidget(), Qt::Key_2);
        QCOMPARE(w->stage(), 1);
        QCOMPARE(spp->value(), 9);
        // The wheel over a field does not take the keys from the canvas.
        QVERIFY(spp->focusPolicy() != Qt::WheelFocus);
    }

    void aClickThatFocusesTheCanvasDoesNotPaint() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        QVERIFY(waitIdle(*w));
        w->setStage(3);
        ImageCanvas* canvas = w->viewer()->canvas();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        w->paintView()->setBrushSize(12.0);
        const QPoint at = canvas->toWidget(QPointF(32, 24)).toPoint();
        // Out of a field being typed in (a spin box): the click takes the keys back only.
        w->renderBar()->findChild<QSpinBox*>()->setFocus();
        QVERIFY(!canvas->hasFocus());
        QTest::mouseClick(canvas, Qt::LeftButton, {}, at);
        QVERIFY(canvas->hasFocus());
        settle();
        QCOMPARE(paintedSum(*w), 0.0);
        QTest::mouseClick(canvas, Qt::LeftButton, {}, at);  // now it paints
        QVERIFY(waitFor([&] { return paintedSum(*w) > 0.0; }));
    }

    void theFirstStrokeAfterAClickInASidePanelPaints() {
        auto w = openScene();
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        // "Paint with it" clicked in the Tune panel: a layer with weight 0, then stage 4.
        w->setStage(2);
        w->tuneView()->setFilter("gaussian");
        QPushButton* paintWithIt = nullptr;
        for (QPushButton* b : w->tuneView()->findChildren<QPushButton*>())
            if (b->text() == QStringLiteral("Paint with it")) paintWithIt = b;
        QVERIFY(paintWithIt);
        QTest::mouseClick(paintWithIt, Qt::LeftButton, {}, paintWithIt->rect().center());
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == 1; }));
        QVERIFY(waitIdle(*w));
        QCOMPARE(w->stage(), 3);
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        QVERIFY(!canvas->hasFocus());  // the click left the focus in the side panel
        w->paintView()->setBrushSize(10.0);
        const int steps = w->session()->undoStack()->count();
        stroke(canvas, {8, 8}, {30, 12});
        QVERIFY(waitFor([&] { return paintedSum(*w) > 0.0; }, 2000));
        QCOMPARE(w->session()->undoStack()->count(), steps + 1);

        // The layer list clicked, then a stroke elsewhere: it paints too.
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY(list && list->count() == 1);
        canvas->setFocus();
        const double painted = paintedSum(*w);
        QTest::mouseClick(list->viewport(), Qt::LeftButton, {},
                          list->visualItemRect(list->item(0)).center());
        QVERIFY(!canvas->hasFocus());
        QCOMPARE(w->paintView()->currentLayer(), 0);
        stroke(canvas, {40, 36}, {58, 40});
        QVERIFY(waitFor([&] { return paintedSum(*w) > painted; }, 2000));
        QCOMPARE(w->session()->undoStack()->count(), steps + 2);
    }

    void theEmissionSliderStaysInASaneRange() {
        auto w = openScene();
        QVERIFY(w);
        LogControl* strength = nullptr;
        for (LogControl* c : w->lookPanel()->findChildren<LogControl*>())
            if (c->objectName().endsWith(QStringLiteral("/strength")) && c->value() > 1.0)
                strength = c;
        QVERIFY(strength);
        const double value = strength->value();
        // The whole slider spans a few stops around the value, so a short drag is a small
        // change...
        strength->slider()->setValue(strength->slider()->maximum());
        QVERIFY2(strength->value() <= value * (1 << LogControl::kStops) * 1.0001,
                 qPrintable(QString::number(strength->value())));
        // ...and the spin box still takes an exact value beyond it.
        strength->spinBox()->setValue(5e5);
        QCOMPARE(strength->value(), 5e5);
    }

    void theEnvironmentSwatchShowsItsColour() {
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave-env")));
        w->document()->open(QDir(sourceDir()).filePath(QStringLiteral("scenes/dof/scene.json")),
                            false);
        QVERIFY(waitFor([&] { return !w->document()->look().empty(); }));
        settle();
        QWidget* colour = w->lookPanel()->findChild<QWidget*>(QStringLiteral("environment/color"));
        QVERIFY(colour);
        auto* swatch = colour->findChild<QPushButton*>(QStringLiteral("swatch"));
        QVERIFY(swatch);
        const QString style = swatch->styleSheet();
        const qsizetype at = style.indexOf(QLatin1Char('#'));
        QVERIFY(at >= 0);
        const QColor shown(style.mid(at, 7));
        QVERIFY2(shown.lightness() > 60, qPrintable(style));  // the scene's grey-blue sky
        QVERIFY(shown.blue() > shown.red());
    }

    void anOutOfRangeColourIsRefusedWithAMessage() {
        auto w = openScene();
        QVERIFY(w);
        QDoubleSpinBox* red = nullptr;
        for (QWidget* c : w->lookPanel()->findChildren<QWidget*>())
            if (c->objectName().endsWith(QStringLiteral("/albedo")))
                red = c->findChild<QDoubleSpinBox*>(QStringLiteral("c0"));
        QVERIFY(red);
        const double before = red->value();
        const int steps = w->session()->undoStack()->count();
        red->setValue(1.5);  // as if typed: the albedo's range is 0 to 1
        QVERIFY2(w->lastError().contains(QStringLiteral("albedo")), qPrintable(w->lastError()));
        QCOMPARE(w->session()->undoStack()->count(), steps);
        QCOMPARE(red->value(), before);
    }

    void aColourFieldEditKeepsTheOtherChannelsAtFullPrecision() {
        auto w = openScene();
        QVERIFY(w);
        std::string item;
        QWidget* field = nullptr;
        for (QWidget* c : w->lookPanel()->findChildren<QWidget*>())
            if (c->objectName().endsWith(QStringLiteral("/albedo"))) {
                field = c;
                item = c->objectName().section(QLatin1Char('/'), 0, -2).toStdString();
            }
        QVERIFY(field);
        // A colour with more digits than the fields show (a scene's or a picked one).
        w->lookPanel()->edit(item, "albedo", {0.12345, 0.23456, 0.34567});
        QVERIFY(waitFor([&] { return !w->document()->rendering(); }));
        auto* green = field->findChild<QDoubleSpinBox*>(QStringLiteral("c1"));
        QVERIFY(green);
        green->setValue(0.5);  // as if typed
        const std::array<double, 3> value = w->document()->lookValue(item, "albedo");
        QCOMPARE(value[1], 0.5);
        QCOMPARE(value[0], 0.12345);  // not 0.123
        QCOMPARE(value[2], 0.34567);  // not 0.346
    }

    void theRenderBarDescribesTheFrameShown() {
        auto w = openScene();
        QVERIFY(w);
        auto* info = w->renderBar()->findChild<QLabel*>();
        auto* progress = w->renderBar()->findChild<QProgressBar*>();
        QVERIFY(info && progress);
        QVERIFY(info->text().contains(QStringLiteral("16 spp")));
        // Nor has a session: it opens its scene without rendering.
        const QString session = m_dir.filePath(QStringLiteral("bar/shown.glint-session.json"));
        QDir().mkpath(QFileInfo(session).path());
        QVERIFY(w->saveSession(session));
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));  // written on a worker
        bool loaded = false;
        connect(w->session(), &SessionAdapter::loaded, this, [&] { loaded = true; });
        w->openFile(session);
        QVERIFY(waitFor([&] { return loaded && !w->session()->busy(); }));
        settle();
        QCOMPARE(info->text(), QString());
        w->document()->render();
        QVERIFY(waitIdle(*w));
        QVERIFY(info->text().contains(QStringLiteral("16 spp")));
        // An EXR has no render of ours: the scene's figures go.
        const QString exr = m_dir.filePath(QStringLiteral("shown.exr"));
        w->session()->session().exportExr(exr.toStdString());
        w->openFile(exr);
        QVERIFY(waitFor([&] { return w->document()->kind() == Document::Kind::Exr; }));
        QVERIFY(waitIdle(*w));
        QCOMPARE(info->text(), QString());
        QCOMPARE(progress->value(), 0);
    }

    void pausedTimeIsNotRenderTimeAndACancelledBarStaysPut() {
        auto w = openScene();
        QVERIFY(w);
        render::Settings s = w->document()->settings();
        s.spp = 1 << 14;
        w->document()->setSettings(s);
        const FramePtr before = w->document()->finishedFrame();
        QElapsedTimer wall;
        wall.start();
        w->document()->render();
        QVERIFY(waitFor([&] { return w->document()->frame() != before; }));
        w->renderBar()->pauseButton()->click();
        QTest::qWait(1500);
        w->renderBar()->pauseButton()->click();
        w->renderBar()->cancelButton()->click();
        QVERIFY(waitFor([&] { return !w->document()->rendering(); }, 30000));
        const double elapsed = wall.elapsed() / 1000.0;
        QVERIFY(w->document()->lastStats().cancelled);
        QVERIFY2(w->document()->lastStats().seconds < elapsed - 1.0,
                 qPrintable(QStringLiteral("%1 s of %2 s")
                                .arg(w->document()->lastStats().seconds)
                                .arg(elapsed)));
        QVERIFY2(w->renderBar()->findChild<QProgressBar*>()->value() < 1000,
                 qPrintable(w->renderBar()->findChild<QLabel*>()->text()));
    }

    void theSidePreviewFollowsTheDisplay() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        QVERIFY(waitIdle(*w));
        w->setStage(3);
        QLabel* side = nullptr;
        for (QLabel* l : w->paintView()->findChildren<QLabel*>())
            if (l->toolTip().contains(QStringLiteral("applied everywhere"))) side = l;
        QVERIFY(side);
        auto shown = [&] { return side->pixmap().toImage(); };
        QVERIFY(waitFor([&] { return !shown().isNull(); }));
        const QImage before = shown();
        w->viewer()->setExposure(3.0);
        QVERIFY(waitFor([&] { return shown() != before; }));
    }

    void aReferenceOfAnotherLookIsFlagged() {
        auto w = openScene();
        QVERIFY(w);
        w->document()->renderReference(16);
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }, 60000));
        QVERIFY(w->compareView()->lookWarning().isEmpty());
        const std::string wall = firstAlbedoMaterial(*w->document());
        w->lookPanel()->edit(wall, "albedo", {0.2, 0.3, 0.7});
        QVERIFY(w->compareView()->lookWarning().contains(QStringLiteral("another look")));
        QVERIFY(w->statusBar()->currentMessage().contains(QStringLiteral("another look")));
        w->session()->undoStack()->undo();  // back to the reference's look
        QVERIFY(w->compareView()->lookWarning().isEmpty());
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioFitTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_fit_test.moc"
