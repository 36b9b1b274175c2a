// Shared by the studio's tests, screenshot tour and speed benchmark: a tiny copy of the Cornell
// box, a studio window that asks nothing, and waiting for the model to settle.
#pragma once

#include <QCoreApplication>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QString>
#include <QTemporaryDir>
#include <QTest>

#include <functional>
#include <memory>
#include <string>

#include "app/main_window.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "views/tune_view.h"

namespace glint::studio::testing {

/// The source tree (set by CMake), for scenes/.
inline QString sourceDir() {
    return QStringLiteral(GLINT_SOURCE_DIR);
}

/// Writes a copy of scenes/cornell with a width × height film and `spp` to `folder`/scene.json
/// (the mesh is referenced by absolute path). Returns its path.
inline QString writeCornell(const QString& folder, int width, int height, int spp = 4) {
    QDir().mkpath(folder);
    const QString obj =
        QDir(sourceDir()).filePath(QStringLiteral("scenes/cornell/cornell_box.obj"));
    const QString json = QStringLiteral(R"({
  "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "up": [0, 1, 0], "fovY": 39.3},
  "film": {"width": %1, "height": %2},
  "materials": {"light": {"type": "diffuse", "albedo": [0, 0, 0], "emission": [17, 12, 4]}},
  "shapes": [{"obj": "%3"}],
  "render": {"spp": %4, "maxDepth": 8, "rrDepth": 3, "mis": "power", "seed": 1}
})")
                             .arg(width)
                             .arg(height)
                             .arg(obj)
                             .arg(spp);
    const QString path = QDir(folder).filePath(QStringLiteral("scene.json"));
    QFile f(path);
    if (f.open(QIODevice::WriteOnly | QIODevice::Truncate)) f.write(json.toUtf8());
    return path;
}

/// The small Cornell box most studio tests share (64 × 48 at 4 spp), written to `dir`/scene.
inline QString writeSmallCornell(const QTemporaryDir& dir) {
    return writeCornell(dir.filePath(QStringLiteral("scene")), 64, 48, 4);
}

/// A studio window journalling into `autosave`, asking no questions. The tests written before
/// the default layer (model/first_denoise.h) start from a session without layers.
inline std::unique_ptr<MainWindow> makeWindow(const QString& autosave,
                                              bool denoiseFirstImage = false) {
    StudioOptions options;
    options.denoiseFirstImage = denoiseFirstImage;
    options.autosaveBase = autosave;
    options.offerRestore = false;
    options.confirmDiscard = false;
    auto window = std::make_unique<MainWindow>(options);
    window->resize(1280, 800);
    window->show();
    // Shortcuts reach an active window only (an X server without a window manager activates
    // nothing by itself).
    window->activateWindow();
    (void)QTest::qWaitForWindowActive(window.get(), 2000);
    return window;
}

/// Processes events until `done()` or `ms` pass; returns done().
// The default bound only ends a wait that would never end (see waitIdle): nothing asserts that a
// condition stays false.
inline bool waitFor(const std::function<bool()>& done, int ms = 120000) {
    QElapsedTimer t;
    t.start();
    while (!done() && t.elapsed() < ms) {
        QCoreApplication::processEvents(QEventLoop::AllEvents, 5);
        QTest::qWait(2);
    }
    return done();
}

/// Waits until the window has a finished render, a session on it, and nothing running.
// The bound only ends a wait that would never end: a slow machine (the sanitizer build, two
// test programs on two cores) may take minutes where this one takes seconds.
inline bool waitIdle(MainWindow& w, int ms = 180000) {
    return waitFor(
        [&] {
            return w.document()->finishedFrame() && w.session()->hasSession() &&
                   !w.document()->rendering() && !w.session()->busy() &&
                   w.session()->input() == w.document()->finishedFrame();
        },
        ms);
}

/// A window (makeWindow, journalling into `autosave`) with `file` open and settled (waitIdle:
/// a scene rendered, an EXR read, a session on it). Null when it does not settle in time.
inline std::unique_ptr<MainWindow> openAndWait(const QString& file, const QString& autosave,
                                               bool denoiseFirstImage = false, int ms = 30000) {
    auto window = makeWindow(autosave, denoiseFirstImage);
    window->openFile(file);
    if (!waitIdle(*window, ms)) return nullptr;
    return window;
}

/// The first material of the document's look with an albedo that is no light (a diffuse wall of
/// the Cornell box); "" when there is none.
inline std::string firstAlbedoMaterial(const Document& d) {
    for (const auto& item : d.look())
        for (const auto& p : item.properties)
            if (p.name == "albedo" && !item.light) return item.name;
    return {};
}

/// Adds a Gaussian layer through the tune stage (weight 1 everywhere when `fill`, else 0) and
/// waits up to `ms` for it.
inline bool addGaussian(MainWindow& w, bool fill, int ms = 20000) {
    w.setStage(2);
    w.tuneView()->setFilter("gaussian");
    const std::size_t before = w.session()->session().layerCount();
    w.tuneView()->choose(fill);
    return waitFor([&] { return w.session()->session().layerCount() == before + 1; }, ms);
}

/// Bit-exact equality of two images.
inline bool sameBits(const Image& a, const Image& b) {
    return a.sameShape(b) &&
           std::equal(a.data().begin(), a.data().end(), b.data().begin(),
                      [](float x, float y) { return std::memcmp(&x, &y, sizeof x) == 0; });
}

}  // namespace glint::studio::testing
