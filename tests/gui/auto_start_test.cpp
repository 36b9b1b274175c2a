// Auto Start on another renderer's frame: a Cycles EXR has neither a variance layer nor half
// buffers, so the studio's auto composite falls back to the image-only noise estimator (as
// `glint-denoise auto` does) and says so on the status bar.
#include <QStatusBar>
#include <QStringList>
#include <QTemporaryDir>
#include <QTest>

#include <algorithm>
#include <cmath>

#include "glint/image/io.h"
#include "model_test.h"
#include "studio_fixture.h"

using namespace glint;
using namespace glint::studio;
using namespace glint::studio::testing;

class StudioAutoStartTest : public QObject {
    Q_OBJECT
  private:
    QTemporaryDir m_dir;

    // Triggers Auto Start on `w`, whose session has no layer yet, and waits for its result layer
    // (or an error), the status bar's messages meanwhile going to `messages`. Empty when the
    // layer came, else why not.
    QString autoStart(MainWindow& w, QStringList& messages) {
        connect(w.statusBar(), &QStatusBar::messageChanged, this, [&messages](const QString& m) {
            if (!m.isEmpty()) messages << m;
        });
        const denoise::Session& s = w.session()->session();
        if (s.layerCount() != 0) return QStringLiteral("the session has layers before Auto Start");
        w.actions().autoStart->trigger();
        const bool settled = waitFor(
            [&] {
                return (s.layerCount() > 0 || !w.lastError().isEmpty()) && !w.session()->busy();
            },
            180000);
        if (!w.lastError().isEmpty()) return w.lastError();
        return settled && s.layerCount() > 0 ? QString() : QStringLiteral("no result layer");
    }

    // A 48 × 40 render with its variance and half buffers (16 samples, 8 in half B).
    static FrameBuffers renderWithHalves() {
        const int w = 48, h = 40;
        FrameBuffers f(w, h);
        Image& variance = f.ensure(Layer::Variance);
        Image& half = f.ensure(Layer::HalfColor);
        f.ensure(Layer::HalfVariance);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const float v = 0.2f + 0.01f * float(x) + 0.1f * float((x * 7 + y * 13) % 5);
                    f.color()(x, y, c) = v;
                    half(x, y, c) = v + (((x + y + c) % 2) != 0 ? 0.05f : -0.05f);
                    variance(x, y, c) = 0.001f;
                }
        for (float& n : f.ensure(Layer::SampleCount).data()) n = 16.0f;
        for (float& n : f.ensure(Layer::HalfSampleCount).data()) n = 8.0f;
        return f;
    }

  private slots:
    void initTestCase() { QVERIFY(m_dir.isValid()); }

    void autoStartOnACyclesFrameUsesTheImageOnlyEstimator() {
        const QString exr =
            sourceDir() + QStringLiteral("/tests/data/cycles/cornell_8spp_seed1.exr");
        auto w = openAndWait(exr, m_dir.filePath(QStringLiteral("autosave-cycles")));
        QVERIFY(w);
        QCOMPARE(w->document()->kind(), Document::Kind::Exr);
        const FramePtr frame = w->session()->input();
        QVERIFY(!frame->has(Layer::Variance));
        QVERIFY(!frame->has(Layer::HalfColor));
        QStringList messages;
        const QString failed = autoStart(*w, messages);
        QVERIFY2(failed.isEmpty(), qPrintable(failed));
        const denoise::Session& s = w->session()->session();
        // A composite of the frame's size, finite, and not the noisy input.
        const Image& composite = s.composite();
        QCOMPARE(composite.width(), frame->width());
        QCOMPARE(composite.height(), frame->height());
        double changed = 0.0;
        for (std::size_t i = 0; i < composite.data().size(); ++i) {
            QVERIFY(std::isfinite(composite.data()[i]));
            changed += std::fabs(composite.data()[i] - frame->color().data()[i]);
        }
        QVERIFY(changed > 0.0);
        // The status bar names the estimator that ran.
        QVERIFY2(messages.filter(QStringLiteral("Auto start")).size() == 1,
                 qPrintable(messages.join(QStringLiteral(" | "))));
        QVERIFY2(messages.filter(QStringLiteral("image-only noise estimate")).size() == 1,
                 qPrintable(messages.join(QStringLiteral(" | "))));
    }

    void autoStartOnAnAlreadyDenoisedImageEstimatesFromTheImageAlone() {
        // glint-final's output: a denoised colour beside the render's variance and half buffers
        // (metadata denoiseFilter). Auto refuses the halves and SURE there (its statistics are
        // the render's); the studio's auto start takes the image-only estimate and says why.
        FrameBuffers f = renderWithHalves();
        f.metadata().extra["denoiseFilter"] = "auto";
        const QString exr = m_dir.filePath(QStringLiteral("final.exr"));
        writeExr(f, exr.toStdString());
        auto win = openAndWait(exr, m_dir.filePath(QStringLiteral("autosave-final")));
        QVERIFY(win);
        QStringList messages;
        const QString failed = autoStart(*win, messages);
        QVERIFY2(failed.isEmpty(), qPrintable(failed));
        QVERIFY2(messages.filter(QStringLiteral("the image is already denoised")).size() == 1,
                 qPrintable(messages.join(QStringLiteral(" | "))));
    }

    void aDenoisedImageThatKeepsItsRenderOpensAsTheRender() {
        // glint-final's output keeps the render's colour as its noisy layer: the studio opens
        // that render (the colour its variance and halves describe), says so on the status bar,
        // and Auto Start runs with the halves as on the render itself.
        FrameBuffers f = renderWithHalves();
        const Image noisy = f.color();
        f.set(Layer::Noisy, noisy);
        f.color().fill(0.3f);  // the denoised colour: flat
        f.metadata().extra["denoiseFilter"] = "auto";
        const QString exr = m_dir.filePath(QStringLiteral("kept.exr"));
        writeExr(f, exr.toStdString());
        auto win = openAndWait(exr, m_dir.filePath(QStringLiteral("autosave-kept")));
        QVERIFY(win);
        const FramePtr input = win->session()->input();
        QVERIFY(input);
        QVERIFY(!input->has(Layer::Noisy));
        QVERIFY(std::equal(input->color().data().begin(), input->color().data().end(),
                           noisy.data().begin()));
        QVERIFY2(win->lastStatus().contains(QStringLiteral("Opened the render kept in kept.exr")),
                 qPrintable(win->lastStatus()));
        QStringList messages;
        const QString failed = autoStart(*win, messages);
        QVERIFY2(failed.isEmpty(), qPrintable(failed));
        QVERIFY2(messages.filter(QStringLiteral("already denoised")).isEmpty(),
                 qPrintable(messages.join(QStringLiteral(" | "))));
    }
};

std::unique_ptr<QObject> makeStudioAutoStartTest() {
    return std::make_unique<StudioAutoStartTest>();
}

#include "auto_start_test.moc"
