// The learned filter (unet, docs/learned.md) everywhere the filters are in the studio (issue 46):
// Navigate pins its result as a preview down to its pick, the Tune panel lists it with its
// parameters and "Paint with it" makes a brush of it. (The first render's denoise by it is
// Studio.View's aScenesFirstImageIsDenoised; its speed is measured by lab/bench/bench_studio.cpp,
// never asserted here.)
#include <QApplication>
#include <QComboBox>
#include <QPushButton>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>

#include "glint/denoise/session.h"
#include "model/layer_names.h"
#include "model/learned_member.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/tune_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

template <class T>
T* childWithText(QWidget* parent, const QString& text) {
    for (T* w : parent->findChildren<T*>())
        if (w->text() == text) return w;
    return nullptr;
}

}  // namespace

class StudioLearnedTest : public QObject {
    Q_OBJECT

    QTemporaryDir m_dir;
    QString m_scene;
    int m_windows = 0;

    std::unique_ptr<MainWindow> openScene() {
        return openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave%1").arg(m_windows++)));
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
        // The build holds the weights (denoise/weights/oidn/): the learned filter runs.
        QVERIFY2(learnedFilterAvailable(), learnedFilterUnavailable().c_str());
    }

    // At every level the option leading to the learned member shows its result (hovered, it is
    // shown on the image), until it is picked; "Paint with it" adds it as a layer.
    void navigationPinsTheLearnedResultDownToItsPick() {
        auto w = openScene();
        QVERIFY(w);
        NavigateView* nav = w->navigateView();
        nav->setBankSize(16);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return nav->ready(); }));
        int levels = 0;
        while (!nav->chosen()) {
            const int i = nav->learnedOption();
            QVERIFY2(
                i >= 0,
                qPrintable(QStringLiteral("level %1 shows no learned result").arg(levels + 1)));
            auto* button = nav->findChild<QToolButton*>(QStringLiteral("option%1").arg(i));
            QVERIFY(button && button->isVisible());
            QVERIFY2(button->text().startsWith(filterTitle(kLearnedFilter)),
                     qPrintable(button->text()));
            QVERIFY(button->toolTip().startsWith(filterTitle(kLearnedFilter)));
            nav->hoverOption(i);  // shows it large on the image
            nav->chooseOption(i);
            QVERIFY(++levels < 16);
        }
        QCOMPARE(nav->chosen()->filter, std::string(kLearnedFilter));
        auto* paint = childWithText<QPushButton>(nav, QStringLiteral("Paint with it"));
        QVERIFY(paint && paint->isEnabled());
        paint->click();
        QVERIFY(waitFor(
            [&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); }));
        QCOMPARE(w->session()->session().layer(0).filter, std::string(kLearnedFilter));
        QCOMPARE(w->stage(), 3);
    }

    // The Tune panel lists the learned filter with its few parameters (three choices and the
    // memory budget) and previews it; "Paint with it" makes it the brush, and a stroke paints
    // its output in.
    void theTunePanelMakesABrushOfTheLearnedFilter() {
        auto w = openScene();
        QVERIFY(w);
        w->setStage(2);
        TuneView* tune = w->tuneView();
        QComboBox* filters = nullptr;
        for (QComboBox* box : tune->findChildren<QComboBox*>())
            if (box->findData(QStringLiteral("gaussian")) >= 0) filters = box;
        // Listed by its display name, the palette's (the registry name is the item's data).
        QVERIFY(filters && filters->findData(QString::fromUtf8(kLearnedFilter)) >= 0);
        QCOMPARE(filters->itemText(filters->findData(QString::fromUtf8(kLearnedFilter))),
                 filterTitle(kLearnedFilter));
        tune->setFilter(kLearnedFilter);
        QCOMPARE(tune->filter(), std::string(kLearnedFilter));
        for (const char* name : {"features", "aux", "quality", "memoryMB"})
            QVERIFY2(tune->findChild<QWidget*>(QString::fromUtf8(name)), name);
        auto* quality = tune->findChild<QComboBox*>(QStringLiteral("quality"));
        QVERIFY(quality);
        QCOMPARE(quality->currentText(), QStringLiteral("balanced"));
        QVERIFY(waitFor([&] { return tune->previewReady(); }));
        quality->setCurrentText(QStringLiteral("fast"));
        QVERIFY(waitFor([&] { return tune->previewReady(); }));
        auto* paint = childWithText<QPushButton>(tune, QStringLiteral("Paint with it"));
        QVERIFY(paint);
        paint->click();
        QVERIFY(waitFor(
            [&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); }));
        const denoise::Session& s = w->session()->session();
        QCOMPARE(s.layer(0).filter, std::string(kLearnedFilter));
        QCOMPARE(s.layer(0).params.at("quality"), 0.0);  // fast
        QCOMPARE(w->stage(), 3);
        QCOMPARE(w->paintView()->currentLayer(), 0);
        // A stroke across the middle paints the learned output in: at the stroke's centre the
        // composite is the layer's output (weight 1 under a brush of softness 1).
        w->paintView()->setBrushSize(12.0);
        const denoise::Brush brush{12.0, 1.0};
        w->session()->beginStroke(0, brush, denoise::BrushMode::Add);
        w->session()->dab(32.0, 24.0);
        w->session()->endStroke();
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));
        QCOMPARE(s.layer(0).weights(32, 24, 0), 1.0f);
        for (int c = 0; c < 3; ++c)
            QCOMPARE(s.composite()(32, 24, c), (*s.layer(0).output)(32, 24, c));
        QVERIFY(!sameBits(s.composite(), s.input().color()));
        // The learned output is not the raw render.
        QVERIFY(!sameBits(*s.layer(0).output, s.input().color()));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioLearnedTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_learned_test.moc"
