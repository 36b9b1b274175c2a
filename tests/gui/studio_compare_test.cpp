// Studio.Compare (issue 48): Navigate is readable — previews labelled by what differs between
// them, near-identical ones said so, the choice in user terms, filters by their display names in
// the Tune menu, stage 3 opening on the current result's filter — and comparisons that do not
// mislead: a reference of another scene or look marks the metrics stale, the raw render's metrics
// beside the result's, and the plot saying what it measures; FLIP in the table and its map over the
// canvas (issue 50).
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QLabel>
#include <QSet>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTableWidget>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>
#include <cmath>

#include <set>

#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/flip.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "model/first_denoise.h"
#include "model/layer_names.h"
#include "model/option_labels.h"
#include "model/reference_info.h"
#include "studio_fixture.h"
#include "views/compare_view.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/navigate_view.h"
#include "views/tune_view.h"
#include "widget_reach.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// An image of `value` everywhere, with a checkerboard of `amplitude` on top (detail).
Image checker(int size, float value, float amplitude) {
    Image im(size, size, 3, value);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) im(x, y, c) = value + ((x + y) % 2 ? amplitude : 0.0f);
    return im;
}

}  // namespace

class StudioCompareTest : public QObject {
    Q_OBJECT

    QTemporaryDir m_dir;
    QString m_scene;
    int m_windows = 0;

    std::unique_ptr<MainWindow> openScene() {
        return openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave%1").arg(m_windows++)));
    }

    // Renders a reference of the open scene at 16 spp (the render's: its own seed makes it
    // another image) and waits for its metrics.
    static bool renderReference(MainWindow& w) {
        w.document()->renderReference(16);
        return waitFor([&] { return w.document()->reference() != nullptr; }, 60000) &&
               waitFor([&] { return w.compareView()->measurement().haveReference; });
    }

    static bool allCells(const CompareView& c, const std::function<bool(const QString&)>& pred) {
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 4; ++col)
                if (!pred(c.cellText(row, col))) return false;
        return true;
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    // --- Navigate is readable -----------------------------------------------------------------

    void aChoiceIsNamedInUserTermsWithRoundedValues() {
        QCOMPARE(choiceName("nlmeans", {{"strength", 0.439111959}}),
                 QStringLiteral("Non-local means, strength 0.44"));
        QCOMPARE(choiceName("cross-bilateral", {{"sigmaS", 4.0}}),
                 QStringLiteral("Cross-bilateral, spatial sigma 4"));
        QCOMPARE(choiceName("unet", {{"quality", 1.0}}),
                 QStringLiteral("Learned (unet), balanced"));
        // One display name for a filter everywhere: the palette's layer name starts with it.
        for (const denoise::Filter* f : denoise::allFilters()) {
            const std::string id(f->name());
            QVERIFY2(layerName(id, {}).startsWith(filterTitle(id)), id.c_str());
        }
        QCOMPARE(filterTitle("bilateral-mc"), QStringLiteral("Bilateral (sampled)"));
        QCOMPARE(filterTitle("nfor"), QStringLiteral("NFOR (regression)"));
    }

    void previewsAreLabelledByWhatDiffersBetweenThem() {
        // One filter: the parameter that differs, rounded to two digits, and nothing that does
        // not differ.
        auto labels = distinguishingLabels(
            {{"nlmeans", {{"strength", 0.2013}}}, {"nlmeans", {{"strength", 0.7988}}}});
        QCOMPARE(labels.size(), std::size_t(2));
        QCOMPARE(labels[0],
                 (QStringList{QStringLiteral("Non-local means"), QStringLiteral("strength 0.2")}));
        QCOMPARE(labels[1],
                 (QStringList{QStringLiteral("Non-local means"), QStringLiteral("strength 0.8")}));
        // Values two digits cannot tell apart get a third.
        labels = distinguishingLabels({{"gaussian", {{"sigma", 2.41}}},
                                       {"gaussian", {{"sigma", 2.44}}},
                                       {"gaussian", {{"sigma", 8.0}}}});
        QCOMPARE(labels[0].last(), QStringLiteral("sigma 2.41"));
        QCOMPARE(labels[1].last(), QStringLiteral("sigma 2.44"));
        QCOMPARE(labels[2].last(), QStringLiteral("sigma 8"));
        // Different filters: each by its display name and main parameter.
        labels = distinguishingLabels(
            {{"gaussian", {{"sigma", 2.0}}}, {"cross-bilateral", {{"sigmaS", 4.0}}}});
        QCOMPARE(labels[0], (QStringList{QStringLiteral("Gaussian"), QStringLiteral("sigma 2")}));
        QCOMPARE(labels[1], (QStringList{QStringLiteral("Cross-bilateral"),
                                         QStringLiteral("spatial sigma 4")}));
        // The same settings say so.
        labels =
            distinguishingLabels({{"gaussian", {{"sigma", 2.0}}}, {"gaussian", {{"sigma", 2.0}}}});
        QCOMPARE(labels[0].last(), QStringLiteral("same settings"));
    }

    void aChoiceMapsLegendNamesNoTwoMembersAlike() {
        // Two strong non-local means of other strengths, two cross-bilaterals of one spatial
        // sigma and other colour sigmas, two identical Gaussians, and a member alone of its name.
        const std::vector<OptionMember> members{
            {"nlmeans", {{"strength", 0.8}}},
            {"nlmeans", {{"strength", 1.6}}},
            {"cross-bilateral", {{"sigmaS", 4.0}, {"sigmaColor", 0.05}}},
            {"cross-bilateral", {{"sigmaS", 4.0}, {"sigmaColor", 0.4}}},
            {"gaussian", {{"sigma", 2.0}}},
            {"gaussian", {{"sigma", 2.0}}},
            {"gaussian", {{"sigma", 8.0}}}};
        // Without help the layer names repeat (what the legend showed).
        QCOMPARE(layerName("nlmeans", members[0].params), layerName("nlmeans", members[1].params));
        const QStringList names = distinctNames(members);
        QCOMPARE(names.size(), qsizetype(members.size()));
        QCOMPARE(QSet<QString>(names.begin(), names.end()).size(), names.size());
        // Each starts with its layer name and adds what differs, as Navigate's labels word it.
        for (std::size_t i = 0; i < members.size(); ++i)
            QVERIFY2(
                names[qsizetype(i)].startsWith(layerName(members[i].filter, members[i].params)),
                qPrintable(names[qsizetype(i)]));
        QVERIFY2(names[0].endsWith(QStringLiteral("(strength 0.8)")), qPrintable(names[0]));
        QVERIFY2(names[1].endsWith(QStringLiteral("(strength 1.6)")), qPrintable(names[1]));
        QVERIFY2(names[2].endsWith(QStringLiteral(" 0.05)")), qPrintable(names[2]));
        QVERIFY2(names[3].endsWith(QStringLiteral(" 0.4)")), qPrintable(names[3]));
        QCOMPARE(names[4], layerName("gaussian", members[4].params) + QStringLiteral(" #5"));
        QCOMPARE(names[5], layerName("gaussian", members[5].params) + QStringLiteral(" #6"));
        QCOMPARE(names[6], layerName("gaussian", members[6].params));  // alone: as it was
    }

    void nearIdenticalPreviewsAndTheSmoothestAreFound() {
        const Image flat = checker(64, 0.5f, 0.0f), busy = checker(64, 0.45f, 0.1f);
        const Image almost = checker(64, 0.5f, 0.002f);
        OptionContrast c = contrastOf({&flat, &almost});
        QVERIFY2(c.nearIdentical, qPrintable(QString::number(c.maxDifference)));
        QVERIFY(c.words[0].isEmpty() && c.words[1].isEmpty());
        c = contrastOf({&flat, &busy});
        QVERIFY(!c.nearIdentical);
        QCOMPARE(c.words[0], QStringLiteral("smoothest"));
        QCOMPARE(c.words[1], QStringLiteral("most detail"));
    }

    // Thumbnails show where the options differ: a window around the one spot that differs.
    void theThumbnailsShowWhereTheOptionsDiffer() {
        Image a(512, 400, 3, 0.5f), b(512, 400, 3, 0.5f);
        for (int y = 300; y < 320; ++y)
            for (int x = 40; x < 60; ++x)
                for (int c = 0; c < 3; ++c) b(x, y, c) = 0.9f;
        const Rect r = mostDifferentWindow({&a, &b}, 100);
        QCOMPARE(r.width(), 100);
        QCOMPARE(r.height(), 100);
        QVERIFY(r.x0 <= 40 && r.x1 >= 60 && r.y0 <= 300 && r.y1 >= 320);
        // An image no larger than the window is shown whole.
        const Rect whole = mostDifferentWindow({&a, &b}, 600);
        QCOMPARE(whole, (Rect{0, 512, 0, 400}));
    }

    // In the studio: no "alike" counts on the previews, labels that differ, the choice in user
    // terms (no registry name, no "key=value" with nine digits).
    void navigateLabelsItsPreviewsAndReportsTheChoiceInUserTerms() {
        auto w = openScene();
        QVERIFY(w);
        NavigateView* nav = w->navigateView();
        nav->setBankSize(16);
        w->setStage(2, true);
        QVERIFY(waitFor([&] { return nav->ready(); }));
        int levels = 0;
        while (!nav->chosen()) {
            QVERIFY(nav->optionCount() > 0);
            std::set<QString> texts;
            for (int i = 0; i < nav->optionCount(); ++i) {
                const QString text = nav->optionText(i);
                QVERIFY2(!text.contains(QStringLiteral("alike")), qPrintable(text));
                texts.insert(text);
            }
            // Told apart by their labels, or said to be near-identical.
            QVERIFY2(int(texts.size()) == nav->optionCount() || nav->contrast().nearIdentical,
                     qPrintable(nav->stateText()));
            if (nav->contrast().nearIdentical && nav->optionCount() > 1)
                QVERIFY2(nav->stateText().contains(QStringLiteral("near-identical")),
                         qPrintable(nav->stateText()));
            nav->chooseOption(0);
            QVERIFY(++levels < 16);
        }
        const denoise::BankMember m = *nav->chosen();
        QCOMPARE(nav->stateText(),
                 QStringLiteral("Chosen: %1").arg(choiceName(m.filter, m.params)));
        QVERIFY2(!nav->stateText().contains(QLatin1Char('=')), qPrintable(nav->stateText()));
    }

    // A figure to three significant digits, small and large ones in the exponent form without
    // its padding (the screenshot tour showed "0...." for 0.000594, then 0.00059 to two digits).
    void figuresShowThreeSignificantDigits() {
        QCOMPARE(compactNumber(0.00184), QStringLiteral("0.00184"));
        QCOMPARE(compactNumber(0.000594), QStringLiteral("5.94e-4"));
        QCOMPARE(compactNumber(5.9449e-6), QStringLiteral("5.94e-6"));
        QCOMPARE(compactNumber(2.01644), QStringLiteral("2.02"));
        QCOMPARE(compactNumber(36.6729), QStringLiteral("36.7"));
        QCOMPARE(compactNumber(0.0412), QStringLiteral("0.0412"));
        QCOMPARE(compactNumber(123456.0), QStringLiteral("1.23e5"));
        QCOMPARE(compactNumber(0.0), QStringLiteral("0"));
    }

    // Every figure and header of the metrics table whole on a 1280x720 laptop screen (its four
    // columns of 7-character figures showed "0...." there); the reach walk's table check.
    void theMetricsTableShowsEveryFigureWholeOnALaptop() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(renderReference(*w));
        QVERIFY(waitIdle(*w));
        auto* table = w->compareView()->findChild<QTableWidget*>();
        QVERIFY(table);
        for (const QSize& size : {QSize(1280, 720), QSize(1366, 768), QSize(1920, 1080)}) {
            w->resize(size);
            for (int i = 0; i < 5; ++i) QTest::qWait(10);
            QVERIFY2(table->isVisible(), "the compare panel shows its table");
            const QStringList cut = tableTextCut(table);
            QVERIFY2(cut.isEmpty(), qPrintable(cut.join(QLatin1Char('\n'))));
        }
        // Small figures in the exponent form, three digits.
        QVERIFY(waitFor([&] { return w->compareView()->measurement().haveRaw; }));
        const double relMse = w->compareView()->measurement().relMseImage;
        QCOMPARE(w->compareView()->cellText(1, 1), compactNumber(relMse));
    }

    void theFilterMenuNamesFiltersAsTheLayersDo() {
        auto w = openScene();
        QVERIFY(w);
        QComboBox* filters = nullptr;
        for (QComboBox* box : w->tuneView()->findChildren<QComboBox*>())
            if (box->findData(QStringLiteral("bilateral-mc")) >= 0) filters = box;
        QVERIFY(filters);
        QCOMPARE(filters->findText(QStringLiteral("bilateral-mc")), -1);
        for (int i = 0; i < filters->count(); ++i)
            QCOMPARE(filters->itemText(i),
                     filterTitle(filters->itemData(i).toString().toStdString()));
    }

    // Stage 3 opens on what the result shows (the top layer's filter and parameters), not on
    // the first filter of the registry (a Gaussian σ 2 that blurs the region).
    void theFilterStageOpensOnTheTopLayersFilter() {
        auto w = openScene();
        QVERIFY(w);
        w->setStage(2);
        const FramePtr input = w->session()->input();
        QVERIFY(input);
        const std::vector<std::string> candidates = FirstDenoise::candidatesFor(*input);
        QVERIFY(!candidates.empty());
        const std::string first = candidates.front();
        QCOMPARE(w->tuneView()->filter(), first);
        w->setStage(1);
        w->session()->addLayer("nlmeans", {{"strength", 0.3}});
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == 1; }));
        QVERIFY(waitIdle(*w));
        w->setStage(2);
        QCOMPARE(w->tuneView()->filter(), std::string("nlmeans"));
        QCOMPARE(w->tuneView()->values().at("strength"), 0.3);
        QVERIFY(waitFor([&] { return w->tuneView()->previewReady(); }));
        // A filter the user picks stays picked.
        w->tuneView()->setFilter("guided");
        w->setStage(1);
        w->setStage(2);
        QCOMPARE(w->tuneView()->filter(), std::string("guided"));
    }

    // "No filter (the render)" is a filter like any other: tuned, and painted over a blurring
    // layer it brings the render back where its weight is 1.
    void theRenderItselfPaintsTheRenderBack() {
        auto w = openScene();
        QVERIFY(w);
        w->setStage(2);
        w->tuneView()->setFilter("identity");
        QCOMPARE(w->tuneView()->filter(), std::string("identity"));
        QVERIFY(waitFor([&] { return w->tuneView()->previewReady(); }));
        const FramePtr input = w->session()->input();
        QVERIFY(input);
        Image mask(input->width(), input->height(), 1);
        for (int y = 0; y < input->height() / 2; ++y)
            for (int x = 0; x < input->width(); ++x) mask(x, y, 0) = 1.0f;
        QVERIFY(waitIdle(*w));
        const std::size_t before = w->session()->session().layerCount();
        w->session()->addLayer("gaussian", {{"sigma", 4.0}},
                               Image(mask.width(), mask.height(), 1, 1.0f));
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == before + 1; }));
        QVERIFY(waitIdle(*w));
        w->session()->addLayer("identity", {}, mask);
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == before + 2; }));
        QVERIFY(waitIdle(*w));
        // The top half is the render, bit for bit; the bottom half the blur.
        const Image& composite = w->session()->session().composite();
        const Image& render = w->session()->session().input().color();
        double moved = 0.0;
        for (int y = 0; y < input->height(); ++y)
            for (int x = 0; x < input->width(); ++x)
                for (int c = 0; c < 3; ++c) {
                    if (y < input->height() / 2)
                        QCOMPARE(composite(x, y, c), render(x, y, c));
                    else
                        moved += std::fabs(composite(x, y, c) - render(x, y, c));
                }
        QVERIFY(moved > 0.0);
        QCOMPARE(layerName("identity", {}), QStringLiteral("No filter (the render)"));
    }

    // --- Comparisons that do not mislead -----------------------------------------------------

    void theReferenceKnowsItsSceneFromTheFile() {
        QVERIFY(sameSceneFile("/a/scenes/cornell/scene.json", "scenes/cornell/scene.json"));
        QVERIFY(sameSceneFile("./cornell/scene.json", "/a/scenes/cornell/scene.json"));
        QVERIFY(!sameSceneFile("/a/scenes/dof/scene.json", "scenes/cornell/scene.json"));
        QVERIFY(!sameSceneFile("/a/x.json", "/b/x.json"));
        QVERIFY(!sameSceneFile("", "/b/x.json"));
        ReferenceInfo file;
        file.source = ReferenceInfo::Source::File;
        ReferenceTarget now;
        now.scene = "/a/scenes/cornell/scene.json";
        QCOMPARE(referenceMismatch(file, now), ReferenceMismatch::Unknown);
        file.scene = "scenes/cornell/scene.json";
        QCOMPARE(referenceMismatch(file, now), ReferenceMismatch::None);
        // glint-render renders the file's own look: an edited look is another.
        render::LookItem wall;
        wall.name = "wall";
        render::LookProperty albedo;
        albedo.name = "albedo";
        albedo.value = {0.5, 0.5, 0.5};
        wall.properties.push_back(albedo);
        now.fileLook = {wall};
        now.look = {wall};
        QCOMPARE(referenceMismatch(file, now), ReferenceMismatch::None);
        now.look[0].properties[0].value = {0.2, 0.3, 0.7};
        QCOMPARE(referenceMismatch(file, now), ReferenceMismatch::Look);
        file.scene = "scenes/dof/scene.json";
        QCOMPARE(referenceMismatch(file, now), ReferenceMismatch::Scene);
    }

    // After a look edit the metrics say "stale" beside a warning, instead of an SSIM that drops
    // silently; undoing the edit brings them back.
    void aReferenceOfAnotherLookMarksTheMetricsStale() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(renderReference(*w));
        CompareView* c = w->compareView();
        QVERIFY(!c->metricsStale());
        QVERIFY(allCells(*c, [](const QString& t) { return t != QStringLiteral("stale"); }));
        const std::string wall = firstAlbedoMaterial(*w->document());
        w->lookPanel()->edit(wall, "albedo", {0.2, 0.3, 0.7});
        QVERIFY(c->metricsStale());
        QVERIFY(allCells(*c, [](const QString& t) { return t == QStringLiteral("stale"); }));
        QVERIFY2(c->lookWarning().contains(QStringLiteral("another look")),
                 qPrintable(c->lookWarning()));
        QVERIFY(c->verdict().isEmpty());
        // The warning is beside the table: shown, right above it.
        QLabel* warning = nullptr;
        for (QLabel* l : c->findChildren<QLabel*>())
            if (l->text() == c->lookWarning()) warning = l;
        auto* table = c->findChild<QTableWidget*>();
        QVERIFY(warning && table && warning->isVisible());
        QVERIFY(warning->geometry().bottom() <= table->geometry().top());
        QVERIFY(table->geometry().top() - warning->geometry().bottom() < 20);
        w->session()->undoStack()->undo();
        QVERIFY(!c->metricsStale());
        QVERIFY(allCells(*c, [](const QString& t) { return t != QStringLiteral("stale"); }));
    }

    // A reference read from an EXR knows its scene by glint:scene: another scene's is flagged
    // and stale; one naming none is said to be unknown, its metrics shown.
    void aReferenceFileOfAnotherSceneMarksTheMetricsStale() {
        auto w = openScene();
        QVERIFY(w);
        FrameBuffers other = *w->document()->finishedFrame();
        other.metadata().scene = "/elsewhere/scenes/other/scene.json";
        const QString otherPath = m_dir.filePath(QStringLiteral("other.exr"));
        writeExr(other, otherPath.toStdString());
        w->document()->openReference(otherPath);
        QVERIFY(waitFor([&] { return w->compareView()->measurement().haveReference; }));
        CompareView* c = w->compareView();
        QVERIFY(c->metricsStale());
        QVERIFY2(c->lookWarning().contains(QStringLiteral("another scene")),
                 qPrintable(c->lookWarning()));
        QVERIFY(allCells(*c, [](const QString& t) { return t == QStringLiteral("stale"); }));

        FrameBuffers unnamed = other;
        unnamed.metadata().scene.clear();
        const QString unnamedPath = m_dir.filePath(QStringLiteral("unnamed.exr"));
        writeExr(unnamed, unnamedPath.toStdString());
        w->document()->openReference(unnamedPath);
        QVERIFY(waitFor([&] { return !c->metricsStale(); }));
        QVERIFY2(c->lookWarning().contains(QStringLiteral("Not known")),
                 qPrintable(c->lookWarning()));
        QVERIFY(allCells(*c, [](const QString& t) { return t != QStringLiteral("stale"); }));

        // This scene's own render as the reference fits, until the look is edited.
        FrameBuffers own = other;
        own.metadata().scene = QFileInfo(m_scene).absoluteFilePath().toStdString();
        const QString ownPath = m_dir.filePath(QStringLiteral("own.exr"));
        writeExr(own, ownPath.toStdString());
        w->document()->openReference(ownPath);
        QVERIFY(waitFor([&] { return c->lookWarning().isEmpty(); }));
        QVERIFY(!c->metricsStale());
        w->lookPanel()->edit(firstAlbedoMaterial(*w->document()), "albedo", {0.2, 0.3, 0.7});
        QVERIFY(c->metricsStale());
    }

    // The raw render beside the result, for the image and the region; a line says whether
    // denoising helped; the plot's last point is the table's raw figure and says so.
    void theTableShowsTheRawRenderBesideTheResult() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(renderReference(*w));
        // The render has half buffers (the bar's default); the reference, one sequence of
        // samples, has none: it is compared against, never denoised.
        QVERIFY(w->document()->finishedFrame()->has(Layer::HalfColor));
        QVERIFY(!w->document()->reference()->has(Layer::HalfColor));
        CompareView* c = w->compareView();
        QCOMPARE(c->columnTitle(0), QStringLiteral("Raw, image"));
        QCOMPARE(c->columnTitle(1), QStringLiteral("Result, image"));
        QCOMPARE(c->columnTitle(2), QStringLiteral("Raw, region"));
        QCOMPARE(c->columnTitle(3), QStringLiteral("Result, region"));
        // A layer over the whole image: the result differs from the raw render.
        QVERIFY(addGaussian(*w, true));
        QVERIFY(waitIdle(*w));
        // A new render with the reference there: the plot gets its passes.
        w->document()->render();
        QVERIFY(waitFor([&] { return w->document()->rendering(); }, 10000));
        QVERIFY(waitIdle(*w));
        const FramePtr reference = w->document()->reference();
        const Image& raw = w->session()->input()->color();
        const double rawRelMse = relMse(raw, reference->color()).value;
        QVERIFY(waitFor([&] {
            const Measurement& m = c->measurement();
            return m.haveRaw && m.rawImage.relMse == rawRelMse && m.relMseImage != rawRelMse;
        }));
        const Measurement& m = c->measurement();
        QCOMPARE(c->cellText(1, 0), compactNumber(m.rawImage.relMse));
        QCOMPARE(c->cellText(1, 1), compactNumber(m.relMseImage));
        QCOMPARE(c->cellText(0, 2), QString::number(m.rawRegion.ssim, 'f', 4));
        QVERIFY2(m.rawImage.relMse > 0.0, "the reference shares the render's samples");
        QVERIFY2(c->verdict().startsWith(QStringLiteral("Denoising ")), qPrintable(c->verdict()));
        // The plot: the raw render's relMSE, its last point the table's raw figure.
        QVERIFY(c->plotTitle().contains(QStringLiteral("raw render")));
        QVERIFY(waitFor([&] { return !w->document()->curve().empty(); }));
        const CurvePoint last = w->document()->curve().back();
        QCOMPARE(last.spp, w->document()->settings().spp);
        QCOMPARE(last.relMse, m.rawImage.relMse);
    }

    void aReferenceShowsFlipInTheTableAndItsMapOverTheCanvas() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(renderReference(*w));
        QVERIFY(waitIdle(*w));
        CompareView* c = w->compareView();
        const Image* result = w->viewer()->resultImage();
        QVERIFY(result);
        FlipOptions hdr;
        hdr.hdr = true;
        const double expected = flip(*result, w->document()->reference()->color(), hdr).mean;
        QVERIFY2(expected > 0.0, "the reference has its own seed: another image");
        QVERIFY(waitFor([&] { return c->measurement().flipImage == expected; }));
        QCOMPARE(c->cellText(3, 1), compactNumber(expected));
        // The map in magma over the canvas, on and off with its box.
        auto* box = c->findChild<QCheckBox*>(QStringLiteral("flipMap"));
        QVERIFY(box);
        ImageCanvas* canvas = w->viewer()->canvas();
        QVERIFY(!canvas->hasOverlay());
        box->click();
        QVERIFY(canvas->hasOverlay());
        QCOMPARE(c->measurement().flipMap.size(), QSize(result->width(), result->height()));
        box->click();
        QVERIFY(!canvas->hasOverlay());
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioCompareTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_compare_test.moc"
