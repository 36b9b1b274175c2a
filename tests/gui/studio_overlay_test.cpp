// Issue 48, "see what you did": the selected layer's weight over the image (O), the magic wand's
// selection and its tolerance, a change map that shows on any material, statistics channels that
// read at EV 0; Auto Start's one result layer with its
// choice map and a progress bar that stays until the work ends; the first denoise chosen by
// measurement (docs/lab/first-denoise.md).
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QListWidget>
#include <QProgressBar>
#include <QSet>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <random>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "model/first_denoise.h"
#include "model/learned_member.h"
#include "studio_fixture.h"
#include "views/display.h"
#include "views/paint_view.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// Mean squared error of `a` against `b` (3 channels).
double mse(const Image& a, const Image& b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        const double d = double(a.data()[i]) - double(b.data()[i]);
        sum += d * d;
    }
    return sum / double(a.data().size());
}

// A 96² frame whose colour holds fine detail its features do not (thin dark lines on a lit
// panel, as decals seen in a visor's reflection): flat albedo, normal and depth, Gaussian noise
// of σ = 0.02 (seed 7) with its variance layer, as a 16-spp render's. The clean colour in `clean`.
FrameBuffers detailFrame(Image& clean) {
    const int n = 96;
    clean = Image(n, n, 3, 0.0f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // Lines one pixel wide every 4 pixels, and a finer checker in the lower half.
            const bool line = x % 4 == 0 || (y > n / 2 && (x + y) % 3 == 0);
            const float v = line ? 0.25f : 0.6f;
            clean(x, y, 0) = v;
            clean(x, y, 1) = 0.9f * v;
            clean(x, y, 2) = 0.8f * v;
        }
    FrameBuffers frame(n, n);
    Image noisy = clean;
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    for (float& v : noisy.data()) v += noise(rng);
    frame.set(Layer::Color, noisy);
    frame.set(Layer::Variance, Image(n, n, 3, 0.02f * 0.02f));
    frame.set(Layer::Albedo, Image(n, n, 3, 0.5f));
    Image normal(n, n, 3, 0.0f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) normal(x, y, 2) = 1.0f;
    frame.set(Layer::Normal, normal);
    frame.set(Layer::Depth, Image(n, n, 1, 1.0f));
    return frame;
}

// A 96² textured frame at a 16-spp render's noise: the albedo holds the fine detail (one-pixel
// dark lines every 4 pixels above, 2×2 glyph-like blocks a pixel apart below, as printed decals
// and panel lines), the colour is that albedo under smooth light with Gaussian noise of σ = 0.05
// (seed 11) and its variance layer, the features nearly noise-free (variance 1e-5, as a 16-spp
// render's first-hit albedo on a plain diffuse texture). The clean colour in `clean`.
FrameBuffers texturedFrame(Image& clean) {
    const int n = 96;
    Image albedo(n, n, 3, 0.0f);
    clean = Image(n, n, 3, 0.0f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const bool dark =
                y < n / 2 ? x % 4 == 0 : (x % 3 < 2 && y % 3 < 2 && (x * 7 + y * 13) % 5 != 0);
            const float a = dark ? 0.1f : 0.6f;
            const float light = 0.6f + 0.4f * float(x + y) / float(2 * n);  // smooth shading
            for (int c = 0; c < 3; ++c) {
                albedo(x, y, c) = a * (1.0f - 0.1f * float(c));
                clean(x, y, c) = albedo(x, y, c) * light;
            }
        }
    FrameBuffers frame(n, n);
    Image noisy = clean;
    std::mt19937 rng(11);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    for (float& v : noisy.data()) v += noise(rng);
    frame.set(Layer::Color, noisy);
    frame.set(Layer::Variance, Image(n, n, 3, 0.05f * 0.05f));
    frame.set(Layer::Albedo, albedo);
    frame.set(Layer::AlbedoVariance, Image(n, n, 3, 1e-5f));
    Image normal(n, n, 3, 0.0f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) normal(x, y, 2) = 1.0f;
    frame.set(Layer::Normal, normal);
    frame.set(Layer::NormalVariance, Image(n, n, 3, 1e-5f));
    frame.set(Layer::Depth, Image(n, n, 1, 1.0f));
    frame.set(Layer::DepthVariance, Image(n, n, 1, 0.0f));
    return frame;
}

// The mean luminance gradient (forward differences) of `image`: its fine detail.
double gradientEnergy(const Image& image) {
    auto lum = [&](int x, int y) {
        return 0.2126 * image(x, y, 0) + 0.7152 * image(x, y, 1) + 0.0722 * image(x, y, 2);
    };
    double sum = 0.0;
    for (int y = 0; y + 1 < image.height(); ++y)
        for (int x = 0; x + 1 < image.width(); ++x)
            sum += std::hypot(lum(x + 1, y) - lum(x, y), lum(x, y + 1) - lum(x, y));
    return sum / double((image.width() - 1) * (image.height() - 1));
}

Image defaultsOf(const std::string& filter, const FrameBuffers& frame) {
    const denoise::Filter& f = denoise::findFilter(filter);
    return denoise::applyFilter(f, frame, denoise::resolveParams(f, {}));
}

}  // namespace

class StudioOverlayTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;
    QString m_scene;

    // The small Cornell box open with one Gaussian layer (weight 1 inside the left half), in the
    // paint stage.
    std::unique_ptr<MainWindow> openWithHalfLayer(const QString& name) {
        auto w = openAndWait(m_scene, m_dir.filePath(name));
        if (!w) return nullptr;
        Image mask(64, 48, 1, 0.0f);
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 32; ++x) mask(x, y, 0) = 1.0f;
        w->session()->addLayer("gaussian", {}, mask);
        if (!waitFor(
                [&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); }))
            return nullptr;
        w->setStage(3);
        return w;
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void theFirstDenoiseKeepsFineDetailTheCrossBilateralFilterErases() {
        Image clean;
        const FrameBuffers frame = detailFrame(clean);
        const double crossBilateral = mse(defaultsOf("cross-bilateral", frame), clean);
        // Without the learned filter (a machine without its weights), measured on the frame.
        const std::vector<std::string> candidates = FirstDenoise::classicalCandidates();
        const FirstDenoiseChoice choice = FirstDenoise::choose(frame, candidates);
        QCOMPARE(choice.estimates.size(), candidates.size());
        const double chosen = mse(defaultsOf(choice.filter, frame), clean);
        QVERIFY2(chosen < 0.5 * crossBilateral,
                 qPrintable(QStringLiteral("%1: %2 against cross-bilateral's %3")
                                .arg(QString::fromStdString(choice.filter))
                                .arg(chosen)
                                .arg(crossBilateral)));
    }

    void theLearnedFilterIsChosenWhenItRuns() {
        QVERIFY2(learnedFilterAvailable(), learnedFilterUnavailable().c_str());
        // The lab measured it best at the studio's spp on every scene (docs/lab/first-denoise.md):
        // on a 16-spp render with albedo and normal it is the first layer.
        const QString scene = writeCornell(m_dir.filePath(QStringLiteral("cornell16")), 96, 72, 16);
        auto w = openAndWait(scene, m_dir.filePath(QStringLiteral("autosave-learned")));
        QVERIFY(w);
        const FrameBuffers& frame = *w->document()->finishedFrame();
        QCOMPARE(FirstDenoise::candidatesFor(frame).front(), std::string(kLearnedFilter));
        QCOMPARE(FirstDenoise::choose(frame).filter, std::string(kLearnedFilter));
        // Without a render's guides nothing is a candidate: the frame stays raw.
        Image clean;
        FrameBuffers noGuides = detailFrame(clean);
        noGuides.remove(Layer::Normal);
        QVERIFY(FirstDenoise::candidatesFor(noGuides).empty());
    }

    void theFirstDenoiseKeepsTheTextureDetailTheAlbedoHolds() {
        QVERIFY2(learnedFilterAvailable(), learnedFilterUnavailable().c_str());
        Image clean;
        const FrameBuffers frame = texturedFrame(clean);
        // What the studio adds, applied as its layer is (its parameters over the defaults).
        const FirstDenoiseChoice choice = FirstDenoise::choose(frame);
        QCOMPARE(choice.filter, std::string(kLearnedFilter));
        const denoise::Filter& unet = denoise::findFilter(kLearnedFilter);
        const Image chosen =
            denoise::applyFilter(unet, frame, denoise::resolveParams(unet, choice.params));
        // unet at its defaults (weights for noisy features) blurs the lines and blocks.
        const Image plain = defaultsOf(kLearnedFilter, frame);
        const double chosenMse = mse(chosen, clean), plainMse = mse(plain, clean);
        const double detail = gradientEnergy(clean);
        const QString figures = QStringLiteral(
                                    "MSE %1 (defaults %2), detail %3 (defaults %4, "
                                    "clean %5)")
                                    .arg(chosenMse)
                                    .arg(plainMse)
                                    .arg(gradientEnergy(chosen))
                                    .arg(gradientEnergy(plain))
                                    .arg(detail);
        qInfo("%s", qPrintable(figures));
        // Tolerances: half the defaults' error; 90 % of the clean image's gradient energy.
        QVERIFY2(chosenMse < 0.5 * plainMse, qPrintable(figures));
        QVERIFY2(gradientEnergy(chosen) > 0.9 * detail, qPrintable(figures));
        // Features as noisy as a depth-of-field render's keep the default weights.
        FrameBuffers blurred = frame;
        blurred.set(Layer::AlbedoVariance, Image(96, 96, 3, 2e-3f));
        QVERIFY(!FirstDenoise::featuresAreClean(blurred));
        QVERIFY(FirstDenoise::choose(blurred).params.empty());
    }

    void theWeightOverlayShowsWhereTheSelectedLayerShows() {
        auto w = openWithHalfLayer(QStringLiteral("autosave-weight"));
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        QVERIFY(!canvas->hasOverlay());
        // O, as the F1 sheet lists it.
        QTest::keyClick(canvas, Qt::Key_O);
        auto* box = w->paintView()->findChild<QCheckBox*>(QStringLiteral("showWeight"));
        QVERIFY(box && box->isChecked());
        QVERIFY(waitFor([&] { return canvas->hasOverlay(); }));
        // The F1 sheet lists every action with a shortcut: this one among them.
        QCOMPARE(w->actions().showWeight->shortcut(), QKeySequence(Qt::Key_O));
        QVERIFY(w->actions().all().contains(w->actions().showWeight));
        // Dimmed where the layer does not show (the right half), clear where it does.
        const QImage overlay = weightOverlay(w->session()->session().layer(0).weights);
        QCOMPARE(qAlpha(overlay.pixel(10, 20)), 0);
        QVERIFY(qAlpha(overlay.pixel(50, 20)) > 100);
        QTest::keyClick(canvas, Qt::Key_O);
        QVERIFY(!box->isChecked());
        QVERIFY(waitFor([&] { return !canvas->hasOverlay(); }));
    }

    void theWandShowsItsSelectionAndItsToleranceIsNamedSo() {
        auto w = openWithHalfLayer(QStringLiteral("autosave-wand"));
        QVERIFY(w);
        PaintView* paint = w->paintView();
        auto* tolerance = paint->findChild<QDoubleSpinBox*>(QStringLiteral("wandTolerance"));
        QVERIFY(tolerance);
        bool named = false;
        for (QFormLayout* form : paint->findChildren<QFormLayout*>())
            if (auto* label = qobject_cast<QLabel*>(form->labelForField(tolerance)))
                named = label->text() == QStringLiteral("Wand tolerance");
        QVERIFY(named);
        ImageCanvas* canvas = w->viewer()->canvas();
        QVERIFY(!canvas->hasSelection());
        QTest::keyClick(canvas, Qt::Key_M);
        const QPoint at = canvas->toWidget(QPointF(48.5, 24.5)).toPoint();
        QTest::mouseClick(canvas, Qt::LeftButton, {}, at);
        QVERIFY(waitFor([&] { return canvas->hasSelection() && !w->session()->busy(); }));
        // A stroke or another layer takes the selection away.
        paint->setCurrentLayer(-1);
        paint->setCurrentLayer(0);
        QVERIFY(!canvas->hasSelection());
    }

    void theChangeMapIsACyanAndMagentaCheckerAndTheOverlaysExcludeEachOther() {
        const QImage map = changeOverlay(Image(8, 8, 1, 1.0f));
        const QColor a = QColor::fromRgba(map.pixel(0, 0)), b = QColor::fromRgba(map.pixel(4, 0));
        QCOMPARE(a.red(), 0);  // cyan
        QVERIFY(a.green() > 200 && a.blue() > 200);
        QCOMPARE(b.green(), 0);  // magenta
        QVERIFY(b.red() > 200 && b.blue() > 200);
        QCOMPARE(qAlpha(changeOverlay(Image(8, 8, 1, 0.0f)).pixel(0, 0)), 0);
        auto w = openWithHalfLayer(QStringLiteral("autosave-change"));
        QVERIFY(w);
        auto* change = w->paintView()->findChild<QCheckBox*>(QStringLiteral("changeMap"));
        auto* weight = w->paintView()->findChild<QCheckBox*>(QStringLiteral("showWeight"));
        weight->setChecked(true);
        change->setChecked(true);
        QVERIFY(!weight->isChecked());
        QVERIFY(waitFor([&] { return w->viewer()->canvas()->hasOverlay(); }));
    }

    void statisticsChannelsReadAtEvZeroAndSaySo() {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave-stats")));
        QVERIFY(w);
        Viewer* v = w->viewer();
        QCOMPARE(v->exposure(), 0.0);
        v->setChannel(Viewer::Channel::ColorVariance);
        QVERIFY2(v->label().startsWith(QStringLiteral("Colour variance (normalised ÷ ")),
                 qPrintable(v->label()));
        // Not near black: the mean of the shown pixels is a tenth of white or more.
        const QImage shown = v->canvas()->shownImage();
        double mean = 0.0;
        for (int y = 0; y < shown.height(); ++y)
            for (int x = 0; x < shown.width(); ++x) mean += qGray(shown.pixel(x, y));
        mean /= double(shown.width() * shown.height());
        QVERIFY2(mean > 25.0, qPrintable(QString::number(mean)));
        // The read-out keeps the raw value.
        v->setChannel(Viewer::Channel::Albedo);
        QCOMPARE(v->label(), QStringLiteral("Albedo"));
    }

    void autoStartAddsOneResultLayerWithItsChoiceMap() {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("autosave-auto")));
        QVERIFY(w);
        auto* bar = w->statusBar()->findChild<QProgressBar*>();
        QVERIFY(bar);
        w->setStage(3);
        w->session()->autoStart(8);
        QVERIFY(w->session()->busy());
        // At 100 % of a stage with work still running the bar stays.
        emit w->session()->progress(QStringLiteral("Auto start: estimating each member's error"),
                                    1.0);
        QVERIFY(bar->isVisible());
        const denoise::Session& s = w->session()->session();
        QVERIFY(waitFor([&] { return s.layerCount() > 0 && !w->session()->busy(); }, 120000));
        QVERIFY(!bar->isVisible());
        QCOMPARE(s.layerCount(), std::size_t(1));
        QCOMPARE(w->session()->undoStack()->count(), 1);
        const SessionAdapter::AutoChoiceMap* map = w->session()->autoChoice(0);
        QVERIFY(map && map->choice && map->used >= 1);
        auto* list = w->paintView()->findChild<QListWidget*>();
        QVERIFY2(list->item(0)->text().startsWith(QStringLiteral("1. Auto result (")),
                 qPrintable(list->item(0)->text()));
        // The choice map: an overlay, and a legend naming members by their display names.
        auto* choice = w->paintView()->findChild<QCheckBox*>(QStringLiteral("choiceMap"));
        QVERIFY(choice->isEnabled());
        choice->setChecked(true);
        ImageCanvas* canvas = w->viewer()->canvas();
        QVERIFY(waitFor([&] { return canvas->hasOverlay() && !canvas->legend().isEmpty(); }));
        const int first = int((*map->choice)(0, 0, 0));
        bool named = false;
        for (const auto& entry : canvas->legend())
            named = named || entry.second.startsWith(map->members[first]);
        QVERIFY(named);
        QVERIFY(!map->members[first].contains(QLatin1Char('=')));  // a display name, not an id
        // No two members share a name (the legend showed "Non-local means, strong" thrice).
        QCOMPARE(QSet<QString>(map->members.begin(), map->members.end()).size(),
                 map->members.size());
        QStringList shown;
        for (const auto& entry : canvas->legend()) shown << entry.second;
        QCOMPARE(QSet<QString>(shown.begin(), shown.end()).size(), shown.size());
        // Undone, the map goes with the layer.
        w->session()->undoStack()->undo();
        QCOMPARE(s.layerCount(), std::size_t(0));
        QVERIFY(waitFor([&] { return !canvas->hasOverlay(); }));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioOverlayTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_overlay_test.moc"
