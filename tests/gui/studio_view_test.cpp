// What artists expect of a render view (Blender's, Nuke's viewer, tev): a wipe dragged on the
// image and toggled by a key, a label saying what the canvas shows, false colour with a legend and
// an automatic range, and the first image of a scene denoised, with no flash of raw 1-spp noise
// while a look change re-renders.
#include <QApplication>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <vector>

#include "glint/denoise/session.h"
#include "glint/image/io.h"
#include "model/first_denoise.h"
#include "model/learned_member.h"
#include "studio_fixture.h"
#include "views/image_canvas.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

Image solid(int w, int h, float r, float g, float b) {
    Image image(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            image(x, y, 0) = r;
            image(x, y, 1) = g;
            image(x, y, 2) = b;
        }
    return image;
}

// The colour the canvas shows at image pixel (x, y) (its centre), read from a grab.
QColor shownAt(ImageCanvas& canvas, int x, int y) {
    const QImage grab = canvas.grab().toImage();
    const QPoint at = canvas.toWidget(QPointF(x + 0.5, y + 0.5)).toPoint();
    return grab.pixelColor(at * grab.devicePixelRatio());
}

}  // namespace

class StudioViewTest : public QObject {
    Q_OBJECT

    QTemporaryDir m_dir;
    QString m_scene;

    // A window (the default layer on) with the small Cornell box open, rendered and denoised.
    std::unique_ptr<MainWindow> openDenoised(const QString& name) {
        auto w = openAndWait(m_scene, m_dir.filePath(name), true);
        if (!w) return nullptr;
        if (!waitFor(
                [&] { return w->session()->session().layerCount() == 1 && !w->session()->busy(); }))
            return nullptr;
        return w;
    }

  private slots:
    void initTestCase() {
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void aWipeDraggedOnTheCanvasSplitsAFromB() {
        ImageCanvas canvas;
        canvas.resize(640, 480);
        canvas.show();
        QVERIFY(QTest::qWaitForWindowExposed(&canvas));
        const Image a = solid(64, 48, 1.0f, 0.0f, 0.0f), b = solid(64, 48, 0.0f, 0.0f, 1.0f);
        canvas.setImage(a);
        canvas.setCompareImage(&b);
        canvas.setWipe(0.5);
        canvas.setTool(ImageCanvas::Tool::Brush);  // the line is dragged whatever the tool
        canvas.setFocus();
        // Left of the line: A; right of it: B.
        QCOMPARE(shownAt(canvas, 28, 20), QColor(255, 0, 0));
        QCOMPARE(shownAt(canvas, 36, 20), QColor(0, 0, 255));
        // Drag the line from the middle to a quarter of the width.
        QSignalSpy moved(&canvas, &ImageCanvas::wipeMoved);
        const QPoint from(int(*canvas.wipeLineX()), 240);
        const QPoint to = canvas.toWidget(QPointF(16.0, 24.0)).toPoint();
        QTest::mousePress(&canvas, Qt::LeftButton, {}, from);
        QTest::mouseMove(&canvas, (from + to) / 2, 1);
        QTest::mouseMove(&canvas, to, 1);
        QTest::mouseRelease(&canvas, Qt::LeftButton, {}, to);
        QVERIFY(!moved.isEmpty());
        QVERIFY(canvas.wipe());
        QVERIFY2(std::abs(*canvas.wipe() - 0.25) < 0.02,
                 qPrintable(QString::number(*canvas.wipe())));
        QCOMPARE(shownAt(canvas, 8, 20), QColor(255, 0, 0));
        QCOMPARE(shownAt(canvas, 20, 20), QColor(0, 0, 255));  // was A before the drag
        QCOMPARE(shownAt(canvas, 60, 20), QColor(0, 0, 255));
    }

    void theWipeKeyTogglesTheWipe() {
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave-key")));
        w->openFile(m_scene);
        QVERIFY(waitIdle(*w));
        ImageCanvas* canvas = w->viewer()->canvas();
        canvas->setFocus();
        QVERIFY(!w->viewer()->wipe());
        QTest::keyClick(canvas, Qt::Key_V);
        QVERIFY(w->viewer()->wipe());
        QVERIFY(canvas->wipe());
        QTest::keyClick(canvas, Qt::Key_V);
        QVERIFY(!w->viewer()->wipe());
        QVERIFY(!canvas->wipe());
    }

    void theCanvasSaysWhatItShows() {
        auto w = openDenoised(QStringLiteral("autosave-label"));
        QVERIFY(w);
        Viewer* v = w->viewer();
        QCOMPARE(v->label(), QStringLiteral("Result (denoised, 16 spp)"));
        v->setChannel(Viewer::Channel::Albedo);
        QCOMPARE(v->label(), QStringLiteral("Albedo"));
        v->setChannel(Viewer::Channel::Result);
        w->document()->renderReference(32);
        QVERIFY(waitFor([&] { return w->document()->reference() != nullptr; }, 60000));
        QVERIFY(waitFor([&] { return v->label().startsWith(QStringLiteral("A: ")); }));
        QCOMPARE(v->label(), QStringLiteral("A: Result (denoised, 16 spp)"));
        v->setFlipped(true);
        QCOMPARE(v->label(), QStringLiteral("B: Reference (32 spp)"));
        v->setFlipped(false);
        v->setWipe(true);
        QCOMPARE(v->label(), QStringLiteral("Wipe: result | reference"));
        v->setWipe(false);
        v->setChannel(Viewer::Channel::Reference);
        QCOMPARE(v->label(), QStringLiteral("Reference (32 spp)"));
        // The label is drawn: the canvas's top-left corner is the label's dark plate.
        QCOMPARE(v->canvas()->label(), v->label());
    }

    void falseColourHasALegendAndAnAutomaticRange() {
        // A ramp of 0..99: numpy.percentile(range(100), [1, 99]) = [0.99, 98.01].
        Image ramp(100, 1, 1);
        for (int x = 0; x < 100; ++x) ramp(x, 0, 0) = float(x);
        ImageCanvas canvas;
        canvas.resize(400, 300);
        canvas.show();
        canvas.setImage(ramp);
        DisplaySettings d;
        d.mode = DisplayMode::FalseColor;
        QVERIFY(d.autoRange);  // on by default
        canvas.setDisplay(d);
        auto [lo, hi] = canvas.falseColorRange();
        QVERIFY2(std::abs(lo - 0.99f) < 1e-4f && std::abs(hi - 98.01f) < 1e-3f,
                 qPrintable(QStringLiteral("%1 %2").arg(lo).arg(hi)));
        // The legend's numbers are the range's.
        const QStringList labels = canvas.legendLabels();
        QCOMPARE(labels.size(), 2);
        QVERIFY(std::abs(labels[0].toDouble() - lo) <= 0.01 * std::abs(lo));
        QVERIFY(std::abs(labels[1].toDouble() - hi) <= 0.01 * std::abs(hi));
        // The ends of the ramp map to the ends of the colour map.
        QCOMPARE(canvas.shownImage().pixel(0, 0), falseColor(0.0f));
        QCOMPARE(canvas.shownImage().pixel(99, 0), falseColor(1.0f));
        QCOMPARE(canvas.shownImage().pixel(50, 0), falseColor((50.0f - lo) / (hi - lo)));
        // A new image gets its own range; turned off, the range is [0, 1].
        for (int x = 0; x < 100; ++x) ramp(x, 0, 0) = 0.01f * float(x);
        canvas.setImage(ramp);
        QVERIFY(std::abs(canvas.falseColorRange().second - 0.9801f) < 1e-5f);
        d.autoRange = false;
        canvas.setDisplay(d);
        QCOMPARE(canvas.falseColorRange(), std::make_pair(0.0f, 1.0f));
        QCOMPARE(canvas.legendLabels(), QStringList({QStringLiteral("0"), QStringLiteral("1")}));
        // The percentiles of a colour image are of its luminance.
        const auto [l, h] = luminancePercentiles(solid(8, 8, 1.0f, 1.0f, 1.0f), DisplaySettings{});
        QVERIFY(std::abs(l - 1.0f) < 1e-5f && std::abs(h - 1.0f) < 1e-5f);
    }

    void aScenesFirstImageIsDenoised() {
        auto w = openDenoised(QStringLiteral("autosave-first"));
        QVERIFY(w);
        const denoise::Session& s = w->session()->session();
        // The learned filter, whose weights the build has (a render has albedo and normal).
        QVERIFY2(learnedFilterAvailable(), learnedFilterUnavailable().c_str());
        QCOMPARE(s.layer(0).filter, std::string(kLearnedFilter));
        QCOMPARE(FirstDenoise::choose(*w->document()->finishedFrame()).filter,
                 std::string(kLearnedFilter));
        // The canvas shows the composite, which is not the raw render.
        QVERIFY(!sameBits(s.composite(), w->document()->finishedFrame()->color()));
        ImageCanvas* canvas = w->viewer()->canvas();
        QVERIFY(waitFor(
            [&] { return canvas->shownImage() == toQImage(s.composite(), canvas->display()); }));
        // It is an ordinary layer: one undo step.
        QVERIFY(w->session()->undoStack()->canUndo());
    }

    void anExrWithoutFeaturesStaysRawWithoutAnError() {
        // Colour only: the cross-bilateral filter has no guides and the learned filter is used
        // with albedo and normal only, so no default layer.
        FrameBuffers frame(32, 24);
        frame.set(Layer::Color, solid(32, 24, 0.5f, 0.25f, 0.125f));
        const QString path = m_dir.filePath(QStringLiteral("colour-only.exr"));
        writeExr(frame, path.toStdString());
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave-exr")), true);
        w->openFile(path);
        QVERIFY(waitIdle(*w));
        QTest::qWait(50);
        QVERIFY(!w->session()->busy());
        QCOMPARE(w->session()->session().layerCount(), std::size_t(0));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
    }

    void aLookChangeNeverFlashesTheRawFirstPass() {
        auto w = openDenoised(QStringLiteral("autosave-flash"));
        QVERIFY(w);
        ImageCanvas* canvas = w->viewer()->canvas();
        const FramePtr before = w->document()->finishedFrame();
        // Every image the canvas shows, and the new render's first (1-spp) pass.
        std::vector<QImage> shown;
        FramePtr firstPass;
        connect(canvas, &ImageCanvas::imageShown, this,
                [&] { shown.push_back(canvas->shownImage()); });
        connect(w->document(), &Document::frameChanged, this, [&](bool final) {
            if (!final && !firstPass) firstPass = w->document()->frame();
        });
        const std::string material = firstAlbedoMaterial(*w->document());
        QVERIFY(!material.empty());
        w->document()->setLook(material, "albedo", {0.9, 0.1, 0.1});
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));
        QVERIFY(firstPass);
        QCOMPARE(firstPass->metadata().spp, 1);
        QVERIFY(!shown.empty());
        const QImage raw = toQImage(firstPass->color(), canvas->display());
        for (std::size_t i = 0; i < shown.size(); ++i)
            QVERIFY2(
                shown[i] != raw,
                qPrintable(
                    QStringLiteral("image %1 of %2 is the raw pass").arg(i).arg(shown.size())));
        // It ends on the new render, denoised.
        const Image& composite = w->session()->session().composite();
        QVERIFY(waitFor(
            [&] { return canvas->shownImage() == toQImage(composite, canvas->display()); }));
        QVERIFY(!sameBits(composite, w->document()->finishedFrame()->color()));
    }

    void aLongRendersPassesShowDenoisedOnceTheyAreAsGood() {
        auto w = openDenoised(QStringLiteral("autosave-progressive"));
        QVERIFY(w);
        const int before = w->session()->input()->metadata().spp;
        QVERIFY(before > 0);
        // The session's input each time it changes while the render runs (a pass denoised).
        std::vector<int> previews;
        connect(w->session(), &SessionAdapter::inputChanged, this, [&] {
            if (w->document()->rendering())
                previews.push_back(w->session()->input()->metadata().spp);
        });
        render::Settings settings = w->document()->settings();
        settings.spp = 512;
        w->document()->setSettings(settings);
        w->document()->render();
        QVERIFY(waitFor([&] { return !w->document()->rendering(); }, 60000));
        QVERIFY(waitIdle(*w));
        QVERIFY2(!previews.empty(), "no pass was shown denoised before the render finished");
        // Never a pass noisier than the denoised image it replaced, each better than the last.
        int last = before;
        for (int spp : previews) {
            QVERIFY2(spp >= last, qPrintable(QStringLiteral("%1 spp after %2").arg(spp).arg(last)));
            QVERIFY(spp <= 512);
            last = spp;
        }
        // It ends on the finished render, denoised; its layers and undo history are kept.
        QCOMPARE(w->session()->input(), w->document()->finishedFrame());
        QCOMPARE(w->session()->session().layerCount(), std::size_t(1));
        QVERIFY(w->session()->undoStack()->canUndo());
        ImageCanvas* canvas = w->viewer()->canvas();
        const Image& composite = w->session()->session().composite();
        QVERIFY(waitFor(
            [&] { return canvas->shownImage() == toQImage(composite, canvas->display()); }));
    }
};

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioViewTest test;
    return QTest::qExec(&test, argc, argv);
}

#include "studio_view_test.moc"
