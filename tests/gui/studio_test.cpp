// The studio driven as a user would, on Qt's offscreen platform: open a tiny scene, change the
// look, lasso, navigate, paint with the mouse, undo, save and reopen, survive a crash, refuse
// bad files. Renders are deterministic (fixed seed), so results are compared bit for bit.
#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QListWidget>
#include <QMessageBox>
#include <QProcess>
#include <QPushButton>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>

#include <csignal>
#include <cstring>
#include <random>

#include "cli_auto.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/io.h"
#include "glint/render/scene.h"
#include "heavy_actions.h"
#include "model/document.h"
#include "model/region.h"
#include "model_test.h"
#include "run_tests.h"
#include "studio_fixture.h"
#include "views/help_overlay.h"
#include "views/image_canvas.h"
#include "views/look_panel.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/render_bar.h"
#include "views/tune_view.h"
#include "views/viewer.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// Drags the mouse on the canvas through image points `path` with `button`.
void drag(ImageCanvas* canvas, const QVector<QPointF>& path,
          Qt::MouseButton button = Qt::LeftButton, Qt::KeyboardModifiers modifiers = {}) {
    auto at = [&](const QPointF& p) { return canvas->toWidget(p).toPoint(); };
    QTest::mousePress(canvas, button, modifiers, at(path.first()));
    for (qsizetype i = 1; i < path.size(); ++i) QTest::mouseMove(canvas, at(path[i]), 1);
    QTest::mouseRelease(canvas, button, modifiers, at(path.last()));
}

double sum(const Image& image) {
    double s = 0.0;
    for (float v : image.data()) s += v;
    return s;
}

}  // namespace

class StudioTest : public QObject {
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

    void opensASceneAndRendersAtOnce() {
        auto w = openScene();
        QVERIFY(w);
        const FramePtr frame = w->document()->finishedFrame();
        QCOMPARE(frame->width(), 64);
        QCOMPARE(frame->height(), 48);
        QCOMPARE(frame->metadata().spp, 16);  // the render bar's low spp, not the file's 4
        QVERIFY(frame->has(Layer::Albedo) && frame->has(Layer::Normal) && frame->has(Layer::Depth));
        QVERIFY(sum(frame->color()) > 0.0);
        QVERIFY(w->viewer()->canvas()->hasImage());
        QCOMPARE(w->viewer()->canvas()->imageSize(), QSize(64, 48));
        QVERIFY(!w->document()->look().empty());
        QVERIFY(w->lastError().isEmpty());
    }

    void opensABareGltfAssetAndRendersItWithItsCamera() {
        // The fuzz seed's triangle (tests/fuzz/seeds/gltf): a .gltf opens as a scene does, with
        // the asset's camera (aspect 1: a square film) and its metallic-roughness material in
        // the Look panel.
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave-gltf")));
        w->openFile(QStringLiteral(GLINT_SOURCE_DIR "/tests/fuzz/seeds/gltf/triangle.gltf"));
        QVERIFY(waitIdle(*w));
        QVERIFY2(w->lastError().isEmpty(), qPrintable(w->lastError()));
        const FramePtr frame = w->document()->finishedFrame();
        QVERIFY(frame);
        QCOMPARE(frame->width(), 640);
        QCOMPARE(frame->height(), 640);
        QVERIFY(sum(frame->color()) > 0.0);
        QVERIFY(!w->document()->look().empty());
        // Its factors are in the Look panel, as a JSON material's are, and editing one renders
        // again with it.
        for (const char* key : {"m/albedo", "m/metallic", "m/roughness", "m/ior"})
            QVERIFY2(w->lookPanel()->findChild<QWidget*>(QString::fromLatin1(key)), key);
        QCOMPARE(w->document()->lookValue("m", "metallic")[0], 0.5);
        w->lookPanel()->edit("m", "metallic", {1.0, 0.0, 0.0});
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != frame; }));
        QVERIFY(waitIdle(*w));
        QCOMPARE(w->document()->lookValue("m", "metallic")[0], 1.0);
        QVERIFY(!sameBits(w->document()->finishedFrame()->color(), frame->color()));
    }

    void aLookChangeRendersAgainAndReappliesTheLayers() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, true));  // weight 1 everywhere (the whole image is the region)
        const FramePtr before = w->document()->finishedFrame();
        const std::string material = firstAlbedoMaterial(*w->document());
        QVERIFY(!material.empty());
        w->lookPanel()->edit(material, "albedo", {0.9, 0.1, 0.1});
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));
        const FramePtr after = w->document()->finishedFrame();
        QVERIFY(!sameBits(after->color(), before->color()));
        // The layer was re-applied to the new render: the composite is the Gaussian of it.
        const denoise::Session& s = w->session()->session();
        QCOMPARE(s.layerCount(), std::size_t(1));
        const Image expected =
            denoise::applyFilter(denoise::findFilter("gaussian"), *after, s.layer(0).params);
        QVERIFY(sameBits(*s.layer(0).output, expected));
        QVERIFY(sameBits(s.composite(), expected));
        QCOMPARE(w->document()->lookValue(material, "albedo")[0], 0.9);
        // The look edit is an undo step: undo renders the old look again (same bits: same seed).
        w->session()->undoStack()->undo();
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != after; }));
        QVERIFY(waitIdle(*w));
        QVERIFY(sameBits(w->document()->finishedFrame()->color(), before->color()));
    }

    void aValueOutsideItsRangeIsRefusedWithoutAnUndoStep() {
        auto w = openScene();
        QVERIFY(w);
        const std::string material = firstAlbedoMaterial(*w->document());
        const int steps = w->session()->undoStack()->count();
        w->lookPanel()->edit(material, "albedo", {2.0, 0.0, 0.0});
        QVERIFY(w->lastError().contains(QStringLiteral("albedo")));
        QCOMPARE(w->session()->undoStack()->count(), steps);
    }

    void aLassoMakesTheRegion() {
        auto w = openScene();
        QVERIFY(w);
        w->setStage(1);
        QCOMPARE(w->viewer()->canvas()->tool(), ImageCanvas::Tool::Lasso);
        drag(w->viewer()->canvas(), {{10, 10}, {40, 8}, {50, 30}, {30, 40}, {12, 35}});
        QVERIFY(!w->region()->wholeImage());
        const Rect r = w->region()->bounds(64, 48);
        QVERIFY(r.x0 >= 9 && r.x1 <= 51 && r.y0 >= 7 && r.y1 <= 41);
        const Image mask = w->region()->mask(64, 48);
        QCOMPARE(mask(30, 20, 0), 1.0f);  // inside
        QCOMPARE(mask(2, 2, 0), 0.0f);    // outside
        // The region stage's count of its pixels is the mask's, made without the mask: random
        // lassos (self-crossing, partly off the image; seed fixed).
        std::mt19937 random(7);
        std::uniform_real_distribution<double> x(-20.0, 84.0), y(-20.0, 68.0);
        for (int k = 0; k < 50; ++k) {
            RegionOfInterest lasso;
            QVector<QPointF> points;
            for (int i = 3 + k % 6; i > 0; --i) points.push_back({x(random), y(random)});
            lasso.setPolygon(points);
            const Image inside = lasso.mask(64, 48);
            double sum = 0.0;
            for (float v : inside.data()) sum += v;
            QCOMPARE(lasso.pixelCount(64, 48), qint64(sum));
        }
        QCOMPARE(RegionOfInterest().pixelCount(64, 48), qint64(64 * 48));
        // "Whole image" (W) undoes it.
        QTest::keyClick(w.get(), Qt::Key_W);
        QVERIFY(w->region()->wholeImage());
    }

    void navigatingTwoLevelsPicksABankMember() {
        auto w = openScene();
        QVERIFY(w);
        w->navigateView()->setBankSize(8);
        w->setStage(2, true);  // entering navigation builds the bank
        QVERIFY(waitFor([&] { return w->navigateView()->ready(); }));
        QVERIFY(w->navigateView()->optionCount() >= 2);
        // Click the first preview twice: two levels down.
        for (int level = 1; level <= 2; ++level) {
            auto* option = w->navigateView()->findChild<QToolButton*>(QStringLiteral("option0"));
            QVERIFY(option && option->isEnabled());
            QTest::mouseClick(option, Qt::LeftButton);
            QCOMPARE(w->navigateView()->depth(), level);
        }
        // Back one level, then "they look the same" picks a member.
        w->navigateView()->back();
        QCOMPARE(w->navigateView()->depth(), 1);
        w->navigateView()->same();
        QVERIFY(w->navigateView()->chosen().has_value());
        const denoise::BankMember chosen = *w->navigateView()->chosen();
        w->navigateView()->choose(true);
        QVERIFY(waitFor([&] { return w->session()->session().layerCount() == 1; }));
        QCOMPARE(w->session()->session().layer(0).filter, chosen.filter);
        QCOMPARE(w->stage(), 3);  // on to painting
    }

    void paintingWithTheMouseChangesWeightsAndCompositeAndUndoes() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));  // weight 0: nothing shows yet
        QCOMPARE(w->stage(), 3);
        const denoise::Session& s = w->session()->session();
        const Image compositeBefore = s.composite();
        QCOMPARE(sum(s.layer(0).weights), 0.0);
        w->paintView()->setBrushSize(12.0);
        ImageCanvas* canvas = w->viewer()->canvas();
        QCOMPARE(canvas->tool(), ImageCanvas::Tool::Brush);
        drag(canvas, {{10, 24}, {20, 24}, {30, 24}, {40, 24}});
        const Image weightsAfter = s.layer(0).weights;
        const Image compositeAfter = s.composite();
        QVERIFY(weightsAfter(25, 24, 0) > 0.9f);  // on the stroke
        QCOMPARE(weightsAfter(60, 2, 0), 0.0f);   // far from it
        QVERIFY(!sameBits(compositeAfter, compositeBefore));
        // The canvas shows the new composite where the stroke went.
        QCOMPARE(w->session()->undoStack()->count(), 2);  // add layer, stroke
        // The right button paints out.
        drag(canvas, {{20, 24}, {30, 24}}, Qt::RightButton);
        QVERIFY(s.layer(0).weights(25, 24, 0) < weightsAfter(25, 24, 0));
        QCOMPARE(w->session()->undoStack()->count(), 3);
        // Undo twice: back to no weight; redo: the first stroke again, bit for bit.
        w->session()->undoStack()->undo();
        QVERIFY(sameBits(s.layer(0).weights, weightsAfter));
        w->session()->undoStack()->undo();
        QCOMPARE(sum(s.layer(0).weights), 0.0);
        QVERIFY(sameBits(s.composite(), compositeBefore));
        QTest::keyClick(w.get(), Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
        QVERIFY(sameBits(s.layer(0).weights, weightsAfter));
        QVERIFY(sameBits(s.composite(), compositeAfter));
        // F1 shows the shortcut sheet, and hides it again.
        auto* help = w->findChild<HelpOverlay*>();
        QVERIFY(help && !help->isVisible());
        QTest::keyClick(w.get(), Qt::Key_F1);
        QVERIFY(help->isVisible());
        QTest::keyClick(w.get(), Qt::Key_F1);
        QVERIFY(!help->isVisible());
        // [ and ] resize the brush.
        QTest::keyClick(w.get(), Qt::Key_BracketRight);
        QCOMPARE(w->paintView()->brush().size, 15.0);
    }

    void theWandAndDiffusionAreUndoSteps() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        w->viewer()->canvas()->setTool(ImageCanvas::Tool::Wand);
        const QPoint at = w->viewer()->canvas()->toWidget(QPointF(32.5, 24.5)).toPoint();
        QTest::mouseClick(w->viewer()->canvas(), Qt::LeftButton, {}, at);
        // The wand's mask is computed on a worker: the fill is the next undo step.
        QVERIFY(waitFor([&] { return w->session()->undoStack()->count() == 2; }));
        const denoise::Session& s = w->session()->session();
        QCOMPARE(s.layer(0).weights(32, 24, 0), 1.0f);
        const double filled = sum(s.layer(0).weights);
        QVERIFY(filled > 1.0 && filled < 64.0 * 48.0);  // bounded by the features
        w->paintView()->diffuse();
        QVERIFY(waitFor([&] { return !w->session()->locked(); }));
        QCOMPARE(w->session()->undoStack()->count(), 3);  // add, fill, diffuse
        QCOMPARE(s.layer(0).weights(32, 24, 0), 1.0f);    // painted pixels keep their weight
    }

    void autoStartAddsOneResultLayerInOneUndoStep() {
        auto w = openScene();
        QVERIFY(w);
        const denoise::Session& s = w->session()->session();
        QCOMPARE(s.layerCount(), std::size_t(0));
        const Image noisy = s.composite();
        w->actions().autoStart->trigger();
        QVERIFY(waitFor([&] { return s.layerCount() > 0 && !w->session()->busy(); }, 60000));
        QCOMPARE(w->session()->undoStack()->count(), 1);
        // One layer, not the bank's members: auto's result over what lay beneath, weight 1.
        QCOMPARE(s.layerCount(), std::size_t(1));
        QVERIFY(s.layer(0).correction);
        QVERIFY(!sameBits(s.composite(), noisy));
        for (float v : s.layer(0).weights.data()) QCOMPARE(v, 1.0f);
        // The result is glint-denoise auto's on the same render, bit for bit.
        QString error;
        const std::optional<Image> cli = cliAutoColour(
            *w->session()->input(), m_dir.filePath(QStringLiteral("cli-sure")), error);
        QVERIFY2(cli, qPrintable(error));
        QVERIFY(sameBits(s.composite(), *cli));
        w->session()->undoStack()->undo();
        QCOMPARE(s.layerCount(), std::size_t(0));
        QVERIFY(sameBits(s.composite(), noisy));
        QVERIFY(w->lastError().isEmpty());
    }

    void aRegionMergeKeepsHalfBuffersOnlyWhenBothRendersHaveThem() {
        FrameBuffers base(8, 6), part(8, 6);
        base.ensure(Layer::HalfColor);
        part.ensure(Layer::HalfColor);
        QVERIFY(mergeRegion(base, part, Rect{0, 4, 0, 3}).has(Layer::HalfColor));
        part.remove(Layer::HalfColor);
        QVERIFY(!mergeRegion(base, part, Rect{0, 4, 0, 3}).has(Layer::HalfColor));
        QVERIFY(!mergeRegion(part, base, Rect{0, 4, 0, 3}).has(Layer::HalfColor));
    }

    void theHalvesBoxIsOnByDefaultAndRendersHalfBuffersThatAutoStartUses() {
        auto w = openScene();
        QVERIFY(w);
        // On by default: the scene (whose render block has no halfBuffers) renders with them.
        QCheckBox* halves = w->renderBar()->halvesBox();
        QVERIFY(halves->isEnabled());
        QVERIFY(halves->isChecked());
        QVERIFY(w->document()->finishedFrame()->has(Layer::HalfColor));
        // Unticked, a render has none, and the choice stays when a scene is opened again (as
        // the spp does); ticked, they are back.
        halves->setChecked(false);
        w->renderBar()->renderButton()->click();
        QVERIFY(waitFor([&] {
            const FramePtr f = w->document()->finishedFrame();
            return !w->document()->rendering() && f && !f->has(Layer::HalfColor);
        }));
        const FramePtr unticked = w->document()->finishedFrame();
        w->openFile(m_scene);
        QVERIFY(waitFor([&] {
            const FramePtr f = w->document()->finishedFrame();
            return !w->document()->loading() && !w->document()->rendering() && f && f != unticked;
        }));
        QVERIFY(!halves->isChecked());
        QVERIFY(!w->document()->settings().halfBuffers);
        QVERIFY(!w->document()->finishedFrame()->has(Layer::HalfColor));
        halves->setChecked(true);
        w->renderBar()->renderButton()->click();
        QVERIFY(waitFor([&] {
            const FramePtr f = w->document()->finishedFrame();
            return !w->document()->rendering() && f && f->has(Layer::HalfColor);
        }));
        const FramePtr frame = w->document()->finishedFrame();
        QVERIFY(frame->has(Layer::HalfSampleCount));
        QCOMPARE(frame->layer(Layer::HalfSampleCount)(10, 10, 0), 8.0f);  // 16 spp, odd half
        QCOMPARE(denoise::resolveEstimator(denoise::AutoEstimator::Auto, *frame),
                 denoise::AutoEstimator::Halves);
        // The session takes the new render in the background: wait until it has, so that
        // Auto Start works on the half-buffer input (and the session is not replaced under it).
        QVERIFY(waitFor([&] {
            const FramePtr input = w->session()->input();
            return !w->session()->busy() && input && input->has(Layer::HalfColor);
        }));
        w->actions().autoStart->trigger();
        QVERIFY(waitFor(
            [&] { return w->session()->session().layerCount() > 0 && !w->session()->busy(); },
            60000));
        QVERIFY(w->session()->input()->has(Layer::HalfColor));
        QVERIFY(w->lastError().isEmpty());
        // The halves stack, as glint-denoise auto does by default: the members, then auto's
        // correction on top, one undo step; the result is the CLI's on the same render, bit for
        // bit.
        const denoise::Session& s = w->session()->session();
        QVERIFY(s.layer(s.layerCount() - 1).correction);
        QCOMPARE(w->session()->undoStack()->count(), 1);
        QString error;
        const std::optional<Image> cli = cliAutoColour(
            *w->session()->input(), m_dir.filePath(QStringLiteral("cli-halves")), error);
        QVERIFY2(cli, qPrintable(error));
        QVERIFY(sameBits(s.composite(), *cli));
        // Saved and opened again, the correction is a layer of the list; restored from that
        // window's journal (its start entry carries the correction), the same composite.
        const Image composite = s.composite();
        const std::size_t layers = s.layerCount();
        QVERIFY(saveSession(*w, m_dir.filePath(QStringLiteral("halves/auto.glint-session.json"))));
        auto again = makeWindow(m_dir.filePath(QStringLiteral("autosave-halves")));
        again->openFile(m_dir.filePath(QStringLiteral("halves/auto.glint-session.json")));
        QVERIFY(
            waitFor([&] { return again->session()->hasSession() && !again->session()->busy(); }));
        QCOMPARE(again->session()->session().layerCount(), layers);
        QVERIFY(sameBits(again->session()->session().composite(), composite));
        auto* list = again->paintView()->findChild<QListWidget*>();
        QVERIFY(list && list->count() == int(layers));
        QVERIFY2(list->item(int(layers) - 1)->text().endsWith(QStringLiteral("Auto's correction")),
                 qPrintable(list->item(int(layers) - 1)->text()));
        const QString crashed = m_dir.filePath(QStringLiteral("crashed-halves"));
        QVERIFY(copyAsCrashed(*again, crashed));
        auto restored = makeWindow(crashed);
        QVERIFY(restore(*restored));
        QCOMPARE(restored->session()->session().layerCount(), layers);
        QVERIFY(restored->session()->session().layer(layers - 1).correction);
        QVERIFY(sameBits(restored->session()->session().composite(), composite));
        // Metropolis has no half buffers: the box is disabled with it.
        auto* integrator = w->renderBar()->findChild<QComboBox*>();
        QVERIFY(integrator);
        integrator->setCurrentIndex(integrator->findData(int(render::Integrator::Mlt)));
        QVERIFY(!halves->isEnabled());
        w->renderBar()->applySettings();
        QVERIFY(!w->document()->settings().halfBuffers);
    }

    void aSavedSessionReopensBitForBit() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, false));
        w->paintView()->setBrushSize(16.0);
        drag(w->viewer()->canvas(), {{8, 8}, {30, 20}, {50, 40}});
        w->region()->setPolygon({{5, 5}, {40, 5}, {40, 30}});
        const QString path = m_dir.filePath(QStringLiteral("saved/look.glint-session.json"));
        QDir().mkpath(QFileInfo(path).path());
        QVERIFY(w->saveSession(path));
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));  // written on a worker
        QVERIFY(w->session()->undoStack()->isClean());
        const Image weights = w->session()->session().layer(0).weights;
        const Image composite = w->session()->session().composite();
        const QString lasso = w->region()->toString();
        w->close();
        w.reset();

        auto again = makeWindow(m_dir.filePath(QStringLiteral("autosave2")));
        again->openFile(path);
        QVERIFY(
            waitFor([&] { return again->session()->hasSession() && !again->session()->busy(); }));
        const denoise::Session& s = again->session()->session();
        QCOMPARE(s.layerCount(), std::size_t(1));
        QVERIFY(sameBits(s.layer(0).weights, weights));
        QVERIFY(sameBits(s.composite(), composite));
        QCOMPARE(again->region()->toString(), lasso);
        // The scene came back too (not rendered): a look change renders and re-applies.
        QVERIFY(waitFor([&] { return again->document()->kind() == Document::Kind::Scene; }));
    }

    void aKilledStudioIsRestoredFromItsAutosave() {
        const QString base = m_dir.filePath(QStringLiteral("crash"));
        QDir(base).removeRecursively();
        QProcess child;
        child.setProcessChannelMode(QProcess::ForwardedChannels);
        child.start(QCoreApplication::applicationFilePath(),
                    {QStringLiteral("--crash-child"), base, m_scene});
        QVERIFY(child.waitForFinished(120000));
        // It killed itself: the journal is left, and its expected session beside it.
        QCOMPARE(child.exitStatus(), QProcess::CrashExit);
        const QString expected = QDir(base).filePath(QStringLiteral("expected.glint-session.json"));
        QVERIFY(QFileInfo::exists(expected));
        QCOMPARE(Autosave::crashed(base).size(), 1);

        StudioOptions options;
        options.autosaveBase = base;
        options.offerRestore = false;
        options.confirmDiscard = false;
        MainWindow w(options);
        w.show();
        w.offerRestore(false);
        QVERIFY(waitFor([&] { return !w.autosave()->restoring(); }, 60000));
        QVERIFY(w.lastError().isEmpty());
        QVERIFY(waitFor([&] { return w.session()->hasSession() && !w.session()->busy(); }));
        const denoise::Session want = denoise::Session::load(expected.toStdString());
        const denoise::Session& got = w.session()->session();
        QCOMPARE(got.layerCount(), want.layerCount());
        for (std::size_t i = 0; i < want.layerCount(); ++i) {
            QCOMPARE(got.layer(i).filter, want.layer(i).filter);
            QVERIFY(sameBits(got.layer(i).weights, want.layer(i).weights));
        }
        QVERIFY(sameBits(got.composite(), want.composite()));
        // The undo history comes back with it: the layer added and the stroke; undoing the
        // stroke leaves the layer unpainted, and redoing it paints it again bit for bit.
        QVERIFY(sum(got.layer(0).weights) > 0.0);
        QCOMPARE(w.session()->undoStack()->count(), 2);
        QCOMPARE(w.session()->undoStack()->index(), 2);
        const Image painted = got.layer(0).weights;
        w.session()->undoStack()->undo();
        QCOMPARE(sum(w.session()->session().layer(0).weights), 0.0);
        w.session()->undoStack()->redo();
        QVERIFY(sameBits(w.session()->session().layer(0).weights, painted));
        // Restored folders go (once this studio's journal holds the restored state).
        QVERIFY(waitFor([&] { return Autosave::crashed(base).isEmpty(); }));
    }

    void badFilesGetOneClearErrorAndTheStudioLives() {
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave3")));
        // A truncated EXR.
        const QString exr = m_dir.filePath(QStringLiteral("broken.exr"));
        {
            QFile f(exr);
            QVERIFY(f.open(QIODevice::WriteOnly));
            // The magic number, version 2, then the header cut inside its first attribute
            // (split literals: a hex escape would swallow the 'c' of "channels").
            static const char header[] =
                "\x76\x2f\x31\x01"
                "\x02\x00\x00\x00"
                "channels\0chlist\0";
            f.write(header, sizeof header - 1);
        }
        w->openFile(exr);
        QVERIFY(waitFor([&] { return !w->lastError().isEmpty(); }));
        QVERIFY(w->lastError().contains(QStringLiteral("broken.exr")));
        QVERIFY(w->findChild<QMessageBox*>(QStringLiteral("errorDialog")));
        // A malformed scene names its line.
        const QString scene = m_dir.filePath(QStringLiteral("bad/scene.json"));
        QDir().mkpath(QFileInfo(scene).path());
        {
            QFile f(scene);
            QVERIFY(f.open(QIODevice::WriteOnly));
            f.write("{\n  \"camera\": {\"position\": [0, 0, 0],\n  oops\n}\n");
        }
        w->openFile(scene);
        QVERIFY(waitFor([&] { return w->lastError().contains(QStringLiteral("scene.json")); }));
        // A missing file.
        w->openFile(m_dir.filePath(QStringLiteral("nowhere.exr")));
        QVERIFY(w->lastError().contains(QStringLiteral("no such file")));
        // Still alive: a good scene opens after all that.
        w->openFile(m_scene);
        QVERIFY(waitIdle(*w));
    }

    void editingTheSceneFileOnDiskRendersAgain() {
        const QString folder = m_dir.filePath(QStringLiteral("watched"));
        const QString scene = writeCornell(folder, 64, 48, 4);
        auto w = makeWindow(m_dir.filePath(QStringLiteral("autosave4")));
        w->openFile(scene);
        QVERIFY(waitIdle(*w));
        const FramePtr before = w->document()->finishedFrame();
        // A text editor makes the light stronger.
        QFile f(scene);
        QVERIFY(f.open(QIODevice::ReadOnly));
        QByteArray json = f.readAll();
        f.close();
        json.replace("[17, 12, 4]", "[34, 24, 8]");
        QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Truncate));
        f.write(json);
        f.close();
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));
        QVERIFY(sum(w->document()->finishedFrame()->color()) > 1.5 * sum(before->color()));
    }

    void exportsTheResultAndSavesTheScene() {
        auto w = openScene();
        QVERIFY(w);
        QVERIFY(addGaussian(*w, true));
        const std::filesystem::path exr =
            m_dir.filePath(QStringLiteral("out/result.exr")).toStdString();
        const std::filesystem::path png =
            m_dir.filePath(QStringLiteral("out/result.png")).toStdString();
        std::filesystem::create_directories(exr.parent_path());
        w->session()->session().exportExr(exr);
        w->session()->session().exportPng(png);
        const FrameBuffers back = readExr(exr);
        QVERIFY(sameBits(back.color(), w->session()->session().composite()));
        QVERIFY(back.has(Layer::Albedo));
        QCOMPARE(readImage(png).width(), 64);
        // The look edit is written back as JSON and loads again with the new value.
        const std::string material = firstAlbedoMaterial(*w->document());
        w->lookPanel()->edit(material, "albedo", {0.25, 0.5, 0.75});
        const QString saved = m_dir.filePath(QStringLiteral("out/scene.json"));
        w->document()->saveScene(saved);
        QVERIFY(waitFor([&] { return QFileInfo::exists(saved); }));
        QVERIFY(waitIdle(*w));
        const render::Scene reloaded = render::loadScene(saved.toStdString());
        bool found = false;
        for (const auto& item : reloaded.look())
            for (const auto& p : item.properties)
                if (item.name == material && p.name == "albedo") {
                    found = true;
                    QCOMPARE(p.value[2], 0.75);
                }
        QVERIFY(found);
    }

    void aRenderRegionRendersOnlyItsPixels() {
        auto w = openScene();
        QVERIFY(w);
        const FramePtr before = w->document()->finishedFrame();
        render::Settings s = w->document()->settings();
        s.seed = 7;  // different samples, so the region shows
        w->document()->setSettings(s);
        w->document()->renderRegion(Rect{16, 32, 8, 24});
        QVERIFY(waitFor([&] { return w->document()->finishedFrame() != before; }));
        QVERIFY(waitIdle(*w));
        const Image& a = before->color();
        const Image& b = w->document()->finishedFrame()->color();
        bool insideDiffers = false;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 64; ++x) {
                const bool inside = x >= 16 && x < 32 && y >= 8 && y < 24;
                if (inside)
                    insideDiffers |= a(x, y, 0) != b(x, y, 0);
                else
                    QCOMPARE(b(x, y, 0), a(x, y, 0));
            }
        QVERIFY(insideDiffers);
    }

    void cancelStopsARenderAndKeepsWhatItHas() {
        auto w = openScene();
        QVERIFY(w);
        render::Settings s = w->document()->settings();
        s.spp = 1 << 14;
        w->document()->setSettings(s);
        const FramePtr before = w->document()->finishedFrame();
        w->document()->render();
        QVERIFY(waitFor([&] { return w->document()->frame() != before; }));  // a pass arrived
        QTest::keyClick(w.get(), Qt::Key_Escape);
        QVERIFY(waitFor([&] { return !w->document()->rendering(); }, 30000));
        QVERIFY(w->document()->lastStats().cancelled);
        QVERIFY(w->document()->finishedFrame() != before);
    }
};

// The child of aKilledStudioIsRestoredFromItsAutosave: paint, save what it should restore to,
// and die without cleaning up.
static int crashChild(const QString& base, const QString& scene) {
    StudioOptions options;
    options.autosaveBase = base;
    options.offerRestore = false;
    options.confirmDiscard = false;
    // No default layer here: the child's one layer is the bilateral it paints. The restoring
    // window keeps the default on, and its replay must not add one.
    options.denoiseFirstImage = false;
    MainWindow w(options);
    w.resize(1000, 700);
    w.show();
    w.openFile(scene);
    if (!waitIdle(w)) return 3;
    w.setStage(2);
    w.tuneView()->setFilter("bilateral");
    w.tuneView()->choose(false);
    if (!waitFor([&] { return w.session()->session().layerCount() == 1; })) return 4;
    w.paintView()->setBrushSize(14.0);
    drag(w.viewer()->canvas(), {{6, 6}, {20, 18}, {40, 30}, {58, 42}});
    bool saved = false;
    w.session()->save(QDir(base).filePath(QStringLiteral("expected.glint-session.json")),
                      std::nullopt, {}, {}, [&](const QString& error) { saved = error.isEmpty(); });
    if (!waitFor([&] { return saved; })) return 6;
    w.autosave()->flush();
    std::raise(SIGKILL);
    return 5;
}

int main(int argc, char** argv) {
    if (argc == 4 && std::strcmp(argv[1], "--crash-child") == 0) {
        QApplication app(argc, argv);
        return crashChild(QString::fromLocal8Bit(argv[2]), QString::fromLocal8Bit(argv[3]));
    }
    QApplication app(argc, argv);
    QApplication::setOrganizationName(QStringLiteral("GlintTests"));
    QStandardPaths::setTestModeEnabled(true);
    StudioTest test;
    const std::unique_ptr<QObject> model = makeStudioModelTest();
    const std::unique_ptr<QObject> autoStart = makeStudioAutoStartTest();
    return runTests({&test, model.get(), autoStart.get()}, argc, argv);
}

#include "studio_test.moc"
