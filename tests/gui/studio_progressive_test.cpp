// Keep refining (model/progressive_render.h, docs/studio.md): the render goes on past the bar's
// spp steered by auto's per-pixel error of the denoised image, the denoised image on screen
// refreshed as it goes; Cancel and a look edit stop and restart it; the session's layers, weights
// and undo history are untouched by its refreshes; a pass that came during a re-application of
// the layers is shown when it ends; the toggle is kept with the session. (How often the screen
// refreshes and how long the UI thread stalls are measured by
// lab/bench/bench_studio_progressive.cpp, never here.)
#include <QApplication>
#include <QCheckBox>
#include <QDir>
#include <QFile>
#include <QSignalSpy>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cmath>
#include <functional>
#include <tuple>
#include <vector>

#include "glint/denoise/session.h"
#include "glint/pipeline/steering.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "model/progressive_render.h"
#include "studio_fixture.h"
#include "views/look_panel.h"
#include "views/render_bar.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

namespace {

// The largest sample count of a frame.
float maxSamples(const FrameBuffers& frame) {
    const auto& n = frame.layer(Layer::SampleCount).data();
    return *std::max_element(n.begin(), n.end());
}

// What of the session a refresh must not change: layers (filter, parameters' count, name),
// their weights' bits, the undo history.
struct SessionShape {
    std::vector<std::string> filters;
    std::vector<Image> weights;
    int undoCount = 0, undoIndex = 0;

    static SessionShape of(MainWindow& w) {
        SessionShape s;
        const denoise::Session& session = w.session()->session();
        for (std::size_t i = 0; i < session.layerCount(); ++i) {
            s.filters.push_back(session.layer(i).filter);
            s.weights.push_back(session.layer(i).weights);
        }
        s.undoCount = w.session()->undoStack()->count();
        s.undoIndex = w.session()->undoStack()->index();
        return s;
    }
    bool operator==(const SessionShape& o) const {
        if (filters != o.filters || undoCount != o.undoCount || undoIndex != o.undoIndex)
            return false;
        for (std::size_t i = 0; i < weights.size(); ++i)
            if (!sameBits(weights[i], o.weights[i])) return false;
        return true;
    }
};

// Whether every pixel of `frame` has at least the samples it has in `before`.
bool atLeast(const FrameBuffers& frame, const FrameBuffers& before) {
    const auto& n = frame.layer(Layer::SampleCount).data();
    const auto& m = before.layer(Layer::SampleCount).data();
    return n.size() == m.size() &&
           std::equal(n.begin(), n.end(), m.begin(), std::greater_equal<>());
}

}  // namespace

class StudioProgressiveTest : public QObject {
    Q_OBJECT

    QTemporaryDir m_dir;
    QString m_scene;

    // A window with the small Cornell box rendered and a Gaussian layer everywhere, then Keep
    // Refining switched on (which renders again, refining).
    std::unique_ptr<MainWindow> refining(const QString& name) {
        auto w = openAndWait(m_scene, m_dir.filePath(name));
        if (!w || !addGaussian(*w, true) || !waitIdle(*w)) return nullptr;
        w->actions().keepRefining->setChecked(true);
        if (!waitFor([&] { return w->document()->refining(); })) return nullptr;
        return w;
    }
    // Cancels the refinement and waits for the window to settle (before it is destroyed).
    static bool stop(MainWindow& w) {
        w.document()->cancelRender();
        return waitIdle(w);
    }

  private slots:
    void initTestCase() {
        QStandardPaths::setTestModeEnabled(true);
        QVERIFY(m_dir.isValid());
        m_scene = writeSmallCornell(m_dir);
    }

    void theDenoisedImageIsRefreshedMoreThanOnceAndTheMapComesFromAutosError() {
        auto w = refining(QStringLiteral("refresh"));
        QVERIFY(w);
        const int barSpp = w->document()->settings().spp;
        // Previews: the session filters passes past the bar's spp, each re-denoised.
        std::vector<int> shown;
        auto c = connect(w->session(), &SessionAdapter::inputChanged, [&] {
            const int spp = w->session()->input()->metadata().spp;
            if (spp > barSpp && (shown.empty() || spp > shown.back())) shown.push_back(spp);
        });
        QVERIFY(waitFor(
            [&] { return shown.size() >= 2 && w->progressive()->lastHanded().refreshes >= 2; }));
        disconnect(c);
        QVERIFY(maxSamples(*w->session()->input()) > float(barSpp));

        // The map handed to the renderer is auto's relative error of the denoised image made
        // into weights: 0 outside the worst tenth, √(relative / mean) (within [1/8, 8]) times
        // one scale inside.
        const ProgressiveRender::Handed handed = w->progressive()->lastHanded();
        QVERIFY(handed.map && handed.from);
        const Image& relative = handed.from->relative;
        QCOMPARE(handed.map->width(), w->document()->finishedFrame()->width());
        const Image unscaled = pipeline::importanceFromError(relative, 1.0);
        std::vector<float> sorted(relative.data().begin(), relative.data().end());
        std::sort(sorted.begin(), sorted.end());
        const std::size_t keep = std::size_t(std::ceil(0.1 * double(sorted.size())));
        const float cut = sorted[sorted.size() - keep];
        double scale = -1.0;
        std::size_t open = 0;
        for (std::size_t i = 0; i < relative.data().size(); ++i) {
            const float m = handed.map->data()[i];
            if (relative.data()[i] < cut) {
                QCOMPARE(m, 0.0f);
                continue;
            }
            ++open;
            const double ratio = double(m) / double(unscaled.data()[i]);
            if (scale < 0.0) scale = ratio;
            QVERIFY(std::abs(ratio - scale) <= 1e-5 * scale);
        }
        QVERIFY(open >= keep && open < relative.data().size());
        QVERIFY(scale >= 1.0);
        QVERIFY(stop(*w));
    }

    void cancelStopsItAndALookEditRestartsIt() {
        auto w = refining(QStringLiteral("cancel"));
        QVERIFY(w);
        // Cancel: the render stops, keeping what it has (at least the bar's spp).
        w->actions().cancelRender->trigger();
        QVERIFY(waitIdle(*w));
        QVERIFY(!w->document()->refining());
        QVERIFY(w->document()->lastStats().cancelled);
        QVERIFY(w->document()->finishedFrame()->metadata().spp >= w->document()->settings().spp);

        // A look edit renders the new look, refining again from the bar's spp.
        const FramePtr before = w->document()->finishedFrame();
        const std::string wall = firstAlbedoMaterial(*w->document());
        QVERIFY(!wall.empty());
        w->lookPanel()->edit(wall, "albedo", {0.2, 0.6, 0.3});
        QVERIFY(waitFor([&] { return w->document()->refining(); }));
        QVERIFY(w->document()->finishedFrame() != before);
        QCOMPARE(w->document()->finishedFrame()->metadata().spp, w->document()->settings().spp);
        // A second edit while it refines restarts it.
        const FramePtr first = w->document()->finishedFrame();
        w->lookPanel()->edit(wall, "albedo", {0.7, 0.2, 0.3});
        QVERIFY(waitFor(
            [&] { return w->document()->refining() && w->document()->finishedFrame() != first; }));
        // Switching it off stops the refinement under way.
        w->actions().keepRefining->setChecked(false);
        QVERIFY(waitIdle(*w));
        QVERIFY(!w->document()->refining());
    }

    // Cancelled before its first pass, a refinement that went on from the finished render
    // (Halves on, the default) ends as any cancelled render does: not refining, the cancel in its
    // stats, the finished frame the render's, and it goes on from there when turned on again.
    // (It was dropped as "nothing rendered": the document stayed refining and the cancel lost.)
    void cancelledBeforeItsFirstPassAContinuedRefinementEndsAndGoesOnAgain() {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("cancel-first")));
        QVERIFY(w);
        Document& d = *w->document();
        const int barSpp = d.settings().spp;
        QVERIFY(d.finishedFrame()->has(Layer::HalfSampleCount));
        const FramePtr finished = d.finishedFrame();
        // Paused at once, it is held at its first tile (the worker has the frame to check and
        // the first map to make before it: microseconds here against milliseconds there).
        w->actions().keepRefining->setChecked(true);
        d.setPaused(true);
        QVERIFY(waitFor([&] { return d.rendering(); }));
        QVERIFY(d.refining());
        w->actions().cancelRender->trigger();
        d.setPaused(false);
        QVERIFY(waitIdle(*w));
        QVERIFY(!d.refining());
        QVERIFY(d.lastStats().cancelled);
        QVERIFY(d.finishedFrame()->metadata().spp >= barSpp);
        if (d.lastStats().passes == 0)  // the case the fix is for: the render's own colour
            QVERIFY(sameBits(d.finishedFrame()->color(), finished->color()));
        // Off and on again: it goes on from the render, past the bar's spp.
        int firstShown = 0;
        auto c = connect(&d, &Document::frameChanged, [&](bool final) {
            if (!final && firstShown == 0) firstShown = d.frame()->metadata().spp;
        });
        w->actions().keepRefining->setChecked(false);
        w->actions().keepRefining->setChecked(true);
        QVERIFY(waitFor([&] { return firstShown > 0; }));
        QVERIFY(firstShown > barSpp);
        disconnect(c);
        QVERIFY(stop(*w));
    }

    void refreshesLeaveTheSessionAsItWas() {
        // The session before Keep Refining is switched on, against the session after the
        // refinement's refreshes. (Taken once it refined, the refreshes could all be past on a
        // fast or loaded machine, and the wait for one more then never ended.)
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("session")));
        QVERIFY(w && addGaussian(*w, true) && waitIdle(*w));
        const SessionShape before = SessionShape::of(*w);
        const FramePtr first = w->session()->input();
        w->actions().keepRefining->setChecked(true);
        QVERIFY(waitFor([&] {
            return w->session()->input() != first &&
                   w->progressive()->lastHanded().refreshes >= 1 && !w->session()->busy();
        }));
        QVERIFY(SessionShape::of(*w) == before);
        QCOMPARE(w->session()->session().layerCount(), std::size_t(1));
        QVERIFY(stop(*w));
        QVERIFY(SessionShape::of(*w) == before);
    }

    void aPassThatArrivedDuringAReapplicationIsShownWhenItEnds() {
        auto w = refining(QStringLiteral("latest"));
        QVERIFY(w);
        const int barSpp = w->document()->settings().spp;
        // A pass past the bar's spp, then the render held: no pass arrives from here on.
        QVERIFY(waitFor([&] {
            return w->document()->frame() && w->document()->frame()->metadata().spp > barSpp;
        }));
        w->document()->setPaused(true);
        QVERIFY(waitFor([&] { return !w->session()->busy(); }));
        // The session re-applies its layers to an older render (the bar's); when that ends the
        // latest pass, which came before, is shown without waiting for another.
        w->session()->setInput(w->document()->finishedFrame(), false);
        QVERIFY(w->session()->busy());
        QVERIFY(waitFor(
            [&] {
                return !w->session()->busy() && w->session()->input() == w->document()->frame();
            },
            20000));
        QVERIFY(w->session()->input()->metadata().spp > barSpp);
        QVERIFY(w->document()->rendering());
        w->document()->setPaused(false);
        QVERIFY(stop(*w));
    }

    void theFirstAdaptivePassesTakeAQuarterThenHalfThenAllOfTheFocus() {
        // A 64 × 64 frame at 16 spp whose relative variance grows with x + 64 y (every value
        // different): the provisional maps open the worst by it, before auto's first map.
        constexpr int kSide = 64;
        FrameBuffers frame(kSide, kSide);
        frame.ensure(Layer::Color).fill(0.5f);
        frame.ensure(Layer::SampleCount).fill(16.0f);
        Image& variance = frame.ensure(Layer::Variance);
        for (int y = 0; y < kSide; ++y)
            for (int x = 0; x < kSide; ++x)
                for (int c = 0; c < 3; ++c) variance(x, y, c) = 1e-4f * float(1 + x + kSide * y);
        auto openPixels = [](const std::shared_ptr<const Image>& map) {
            return map ? std::count_if(map->data().begin(), map->data().end(),
                                       [](float v) { return v > 0.0f; })
                       : std::ptrdiff_t(-1);
        };
        ProgressiveRender progressive;
        {
            // Auto's refresh, started by the first call, is told to stop at once: no map of
            // its comes in between.
            const RenderJob::ImportanceFn steer = progressive.steer([] { return true; }).importance;
            const double focus = ProgressiveRender::refreshOptions().focus * kSide * kSide;
            double share = ProgressiveRender::kFirstPassShare;
            QCOMPARE(share, 0.25);
            for (int pass = 1; pass <= 3; ++pass, share *= 2.0) {
                const auto map = steer(pass, frame);
                QCOMPARE(openPixels(map), std::ptrdiff_t(std::ceil(share * focus)));
                // The worst pixel (the last) is open in each.
                QVERIFY((*map)(kSide - 1, kSide - 1, 0) > 0.0f);
            }
            // Then the renderer keeps the last.
            QVERIFY(!steer(4, frame));
        }
    }

    void withNoPixelOpenTheRenderWaitsForTheRefreshUnderWayAndGoesOnWithItsMap() {
        // When the passes steered so far leave no pixel open, the render does not end while
        // auto's refresh is under way (on a fast machine it ended before auto's first map ever
        // came): it waits, takes the map and goes on; the frame unchanged since, it ends.
        render::Renderer renderer(render::loadScene(m_scene.toStdString()));
        render::Settings s = renderer.scene().settings();
        s.spp = 16;
        s.halfBuffers = true;
        s.threads = 2;
        const FrameBuffers frame = renderer.render(s).frame;
        ProgressiveRender progressive;
        const RenderJob::Steering steer = progressive.steer([] { return false; });
        QVERIFY(steer.importance(1, frame));  // the provisional map; auto starts on a worker
        const std::shared_ptr<const Image> map = steer.converged(2, frame);
        QVERIFY(map);
        QCOMPARE(progressive.lastHanded().refreshes, 1);
        QVERIFY(progressive.lastHanded().map == map);
        QVERIFY(!steer.converged(2, frame));
        QCOMPARE(progressive.activity().started, 1);
        QCOMPARE(progressive.activity().finished, 1);
    }

    void turnedOnAfterARenderWithHalvesItGoesOnFromItAndOffAndOnAgainFromWhereItStopped() {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("goes-on")));
        QVERIFY(w && waitIdle(*w));
        Document& d = *w->document();
        const int barSpp = d.settings().spp;
        // The spp of each pass shown, and whether the finished frame was still `finished` when
        // the first came.
        std::vector<int> shown;
        FramePtr finished, finishedAtFirst;
        auto c = connect(&d, &Document::frameChanged, [&](bool final) {
            if (final) return;
            if (shown.empty()) finishedAtFirst = d.finishedFrame();
            shown.push_back(d.frame()->metadata().spp);
        });
        auto turnOn = [&] {
            shown.clear();
            finished = d.finishedFrame();
            w->actions().keepRefining->setChecked(true);
            return waitFor([&] { return !shown.empty() || !d.rendering(); });
        };
        // Without half buffers (Halves unticked) auto's error has nothing to go on from: the
        // refinement renders again from its first pass, below the bar's spp.
        w->renderBar()->halvesBox()->setChecked(false);
        d.render();
        QVERIFY(waitFor([&] { return d.rendering(); }));
        QVERIFY(waitIdle(*w));
        QVERIFY(!d.finishedFrame()->has(Layer::HalfSampleCount));
        QVERIFY(turnOn());
        QVERIFY(!shown.empty() && shown.front() < barSpp);
        w->actions().keepRefining->setChecked(false);
        QVERIFY(waitIdle(*w));

        // A render with them, then the toggle: the first pass shown is past the bar's spp, the
        // finished frame stays the render's, and no pixel has fewer samples than it had.
        render::Settings s = d.settings();
        s.halfBuffers = true;
        d.setSettings(s);
        d.render();
        QVERIFY(waitIdle(*w));
        QVERIFY(d.finishedFrame()->has(Layer::HalfSampleCount));
        QCOMPARE(d.finishedFrame()->metadata().spp, barSpp);
        QVERIFY(turnOn());
        QVERIFY(!shown.empty());
        QVERIFY(*std::min_element(shown.begin(), shown.end()) > barSpp);
        QVERIFY(finishedAtFirst == finished);
        QVERIFY(atLeast(*d.frame(), *finished));

        // Off, then on again: it goes on from where it stopped.
        w->actions().keepRefining->setChecked(false);
        QVERIFY(waitIdle(*w));
        const FramePtr stopped = d.finishedFrame();
        QVERIFY(stopped != finished && maxSamples(*stopped) > float(barSpp));
        QVERIFY(turnOn());
        for (int spp : shown) QVERIFY(spp > barSpp);
        QVERIFY(waitFor([&] { return d.frame() != stopped; }));
        QVERIFY(atLeast(*d.frame(), *stopped));
        disconnect(c);
        QVERIFY(stop(*w));
        QVERIFY(w->lastError().isEmpty());
    }

    void theToggleIsSavedWithTheSessionAndComesBackWithoutRendering() {
        auto w = openAndWait(m_scene, m_dir.filePath(QStringLiteral("persist")));
        QVERIFY(w && waitIdle(*w));
        auto save = [&](const QString& name) {
            const QString path = m_dir.filePath(name);
            return w->saveSession(path) && waitFor([&] { return !w->session()->busy(); })
                       ? path
                       : QString();
        };
        w->viewer()->setExposure(1.5);
        w->setStage(3);
        w->actions().keepRefining->setChecked(true);
        QVERIFY(waitFor([&] { return w->document()->refining(); }));
        QVERIFY(stop(*w));
        const QString on = save(QStringLiteral("on.glint-session.json"));
        QVERIFY(!on.isEmpty());
        w->actions().keepRefining->setChecked(false);
        w->setStage(1);
        QVERIFY(waitIdle(*w));
        const QString off = save(QStringLiteral("off.glint-session.json"));
        QVERIFY(!off.isEmpty());
        w->close();
        w.reset();

        // A new window starts with it off; the first session turns it on, the second off again,
        // neither rendering.
        auto again = makeWindow(m_dir.filePath(QStringLiteral("persist-again")));
        QVERIFY(!again->actions().keepRefining->isChecked());
        for (const auto& [path, expected, stage] :
             {std::tuple{on, true, 3}, std::tuple{off, false, 1}}) {
            again->openFile(path);
            QVERIFY(waitFor([&] {
                return again->session()->hasSession() && !again->session()->busy() &&
                       again->document()->kind() == Document::Kind::Scene &&
                       !again->document()->loading() && again->document()->finishedFrame() &&
                       again->actions().keepRefining->isChecked() == expected;
            }));
            QCOMPARE(again->progressive()->enabled(), expected);
            QCOMPARE(again->viewer()->exposure(), 1.5);
            QCOMPARE(again->stage(), stage);
            QVERIFY(!again->document()->rendering());
        }
        QVERIFY(again->lastError().isEmpty());
        // Each session journals its view once, with every value as it came back (the exposure's
        // signal and the stage would each journal one of their own, the toggle as it was before).
        again->autosave()->flush();
        QFile journal(
            QDir(again->autosave()->journal()->folder()).filePath(QStringLiteral("journal.jsonl")));
        QVERIFY(journal.open(QIODevice::ReadOnly));
        QStringList views;
        for (const QByteArray& line : journal.readAll().split('\n'))
            if (line.contains("\"op\":\"view\"")) views << QString::fromUtf8(line);
        QCOMPARE(
            views,
            (QStringList{
                QStringLiteral(
                    R"({"channel":"result","exposure":1.5,"keepRefining":true,"op":"view","stage":3})"),
                QStringLiteral(
                    R"({"channel":"result","exposure":1.5,"keepRefining":false,"op":"view","stage":1})")}));
    }
};

QTEST_MAIN(StudioProgressiveTest)
#include "studio_progressive_test.moc"
