// Random sequences of what the paint stage offers, made through the studio as a user makes
// them, for the tests that hold an artist's work to come back whole: from the autosave journal
// after a crash (restore_test.cpp) and from a saved session (studio_session_test.cpp).
#pragma once

#include <QDir>
#include <QPointF>
#include <QSignalSpy>
#include <QVector>

#include <cmath>
#include <optional>
#include <random>
#include <string>

#include "studio_fixture.h"
#include "views/look_panel.h"

namespace glint::studio::testing {

/// What randomEdits did: the edits in order, and why it stopped early ("" when it did not).
struct RandomEdits {
    QStringList done;
    QString failure;
    QString text() const { return done.join(QStringLiteral(", ")); }
};

/// `count` edits drawn by `seed` on `w`'s session (settled: waitIdle), each waited for: layers of
/// gaussian (a random σ), bilateral or guided added with or without a fill, strokes of random
/// brushes with dabs partly off the image, fills, weights, the magic wand, Poisson diffusion
/// (of a layer with painted pixels), renames, removals, undo, redo, Auto Start on a bank of 4,
/// feature prefiltering turned on or off (a new session carrying the layers), a region rendered
/// again with another seed, a reference rendered at 8 spp or cleared, and look edits of the
/// material `wall`'s albedo (a new render, the layers re-applied), the region of interest (a
/// lasso partly off the image, or the whole image again), and the session saved into `folder` and
/// opened again in the same window (its look, region, settings and reference from the file).
inline RandomEdits randomEdits(MainWindow& w, unsigned seed, int count, const std::string& wall,
                               const QString& folder) {
    RandomEdits out;
    SessionAdapter& session = *w.session();
    const int width = session.session().composite().width();
    const int height = session.session().composite().height();
    std::mt19937 rng(seed);
    auto uniform = [&](double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    };
    auto below = [&](std::size_t n) {
        return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
    };
    auto mask = [&](bool binary) {
        Image m(width, height, 1);
        const double cx = uniform(0, width), cy = uniform(0, height), r = uniform(3, 20);
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const bool in = std::hypot(x - cx, y - cy) < r;
                m(x, y, 0) = binary ? (in ? 1.0f : 0.0f) : float(uniform(0, 1));
            }
        return m;
    };
    auto mode = [&] { return below(2) ? denoise::BrushMode::Add : denoise::BrushMode::Subtract; };
    auto painted = [&](std::size_t layer) {
        for (float v : session.session().layer(layer).painted.data())
            if (v != 0.0f) return true;
        return false;
    };
    for (int edit = 0; edit < count; ++edit) {
        const std::size_t layers = session.session().layerCount();
        const std::size_t kind = layers == 0 ? 0 : below(17);
        const std::size_t layer = layers == 0 ? 0 : below(layers);
        switch (kind) {
            case 0: {
                const std::size_t f = below(3);
                const std::string filter = f == 0 ? "gaussian" : f == 1 ? "bilateral" : "guided";
                denoise::ParamValues params;
                if (f == 0) params["sigma"] = uniform(0.5, 4.0);
                session.addLayer(filter, params,
                                 below(2) ? std::optional<Image>(mask(true)) : std::nullopt);
                out.done << QStringLiteral("add %1").arg(QString::fromStdString(filter));
                break;
            }
            case 1: {
                session.beginStroke(layer, {uniform(2, 30), uniform(0, 1)}, mode());
                const std::size_t dabs = 1 + below(6);
                for (std::size_t d = 0; d < dabs; ++d)
                    session.dab(uniform(-10, width + 10), uniform(-10, height + 10));
                session.endStroke();
                out.done << QStringLiteral("stroke %1").arg(layer);
                break;
            }
            case 2:
                session.fill(layer, mask(true), mode());
                out.done << QStringLiteral("fill %1").arg(layer);
                break;
            case 3:
                session.setWeights(layer, mask(false));
                out.done << QStringLiteral("weights %1").arg(layer);
                break;
            case 4:
                session.wand(layer, int(below(std::size_t(width))), int(below(std::size_t(height))),
                             {}, mode());
                out.done << QStringLiteral("wand %1").arg(layer);
                break;
            case 5:
                // Diffusion needs a painted pixel (the studio says so otherwise).
                if (!painted(layer)) continue;
                session.diffuse({layer});
                out.done << QStringLiteral("diffuse %1").arg(layer);
                break;
            case 6:
                session.renameLayer(layer, below(3) ? "layer " + std::to_string(edit) : "");
                out.done << QStringLiteral("rename %1").arg(layer);
                break;
            case 7:
                session.removeLayer(layer);
                out.done << QStringLiteral("remove %1").arg(layer);
                break;
            case 8:
                session.undoStack()->undo();
                out.done << QStringLiteral("undo");
                break;
            case 9:
                session.undoStack()->redo();
                out.done << QStringLiteral("redo");
                break;
            case 10:
                session.autoStart(4);
                out.done << QStringLiteral("auto start");
                if (!waitFor([&] { return session.session().layerCount() > layers; }, 180000)) {
                    out.failure = QStringLiteral("Auto Start added no layer");
                    return out;
                }
                break;
            case 11: {
                // Feature prefiltering turned on or off: a new session carrying the layers.
                denoise::SessionOptions options = session.options();
                options.prefilter = !options.prefilter;
                session.setOptions(options);
                out.done << QStringLiteral("prefilter %1").arg(options.prefilter ? "on" : "off");
                if (!waitFor(
                        [&] { return session.session().options().prefilter == options.prefilter; },
                        60000)) {
                    out.failure = QStringLiteral("the new session did not come");
                    return out;
                }
                break;
            }
            case 12: {
                // A region rendered again with another seed, merged into the frame.
                const FramePtr before = w.document()->finishedFrame();
                render::Settings settings = w.document()->settings();
                settings.seed = 1000 + edit;
                w.document()->setSettings(settings);
                const int x0 = int(below(std::size_t(width / 2))),
                          y0 = int(below(std::size_t(height / 2)));
                w.document()->renderRegion(Rect{x0, x0 + 1 + int(below(std::size_t(width - x0))),
                                                y0, y0 + 1 + int(below(std::size_t(height - y0)))});
                out.done << QStringLiteral("region render");
                if (!waitFor([&] { return w.document()->finishedFrame() != before; }, 60000)) {
                    out.failure = QStringLiteral("the region render finished nothing");
                    return out;
                }
                break;
            }
            case 13:
                // A reference rendered at 8 spp, or the one there cleared.
                if (w.document()->reference() && below(2)) {
                    w.document()->clearReference();
                    out.done << QStringLiteral("reference cleared");
                    break;
                }
                {
                    const FramePtr before = w.document()->reference();
                    w.document()->renderReference(8);
                    out.done << QStringLiteral("reference");
                    if (!waitFor(
                            [&] {
                                return w.document()->reference() &&
                                       w.document()->reference() != before;
                            },
                            60000)) {
                        out.failure = QStringLiteral("the reference render finished nothing");
                        return out;
                    }
                }
                break;
            case 14: {
                // A lasso of 3 to 6 points, partly off the image, or the whole image again.
                if (below(4) == 0) {
                    w.region()->clear();
                    out.done << QStringLiteral("whole image");
                    break;
                }
                QVector<QPointF> lasso;
                for (std::size_t n = 3 + below(4); lasso.size() < qsizetype(n);)
                    lasso.push_back(QPointF(uniform(-5, width + 5), uniform(-5, height + 5)));
                w.region()->setPolygon(lasso);
                out.done << QStringLiteral("lasso");
                break;
            }
            case 15: {
                // Saved, then opened again from the file in this window.
                const QString path = QDir(folder).filePath(
                    QStringLiteral("reopen-%1-%2.glint-session.json").arg(seed).arg(edit));
                if (!w.saveSession(path) ||
                    !waitFor([&] { return !session.busy() && !w.isModified(); }, 60000)) {
                    out.failure = QStringLiteral("the session was not saved");
                    return out;
                }
                QSignalSpy loaded(&session, &SessionAdapter::loaded);
                w.openFile(path);
                out.done << QStringLiteral("reopen");
                if (!waitFor([&] { return loaded.count() == 1 && !w.document()->loading(); },
                             60000)) {
                    out.failure = QStringLiteral("the saved session did not open");
                    return out;
                }
                break;
            }
            default: {
                const FramePtr before = w.document()->finishedFrame();
                w.lookPanel()->edit(wall, "albedo", {uniform(0, 1), uniform(0, 1), uniform(0, 1)});
                out.done << QStringLiteral("look");
                if (!waitFor([&] { return w.document()->finishedFrame() != before; }, 60000)) {
                    out.failure = QStringLiteral("the look edit rendered nothing");
                    return out;
                }
                break;
            }
        }
        if (!waitIdle(w, 60000)) {
            out.failure = QStringLiteral("the studio did not settle");
            return out;
        }
        if (!w.lastError().isEmpty()) {
            out.failure = w.lastError();
            return out;
        }
    }
    return out;
}

/// How the reference `got` differs from `want` (both null: none): "" when it does not.
inline QString referenceDifference(const FramePtr& got, const FramePtr& want) {
    if (got && want)
        return sameBits(got->color(), want->color()) ? QString()
                                                     : QStringLiteral("another reference");
    if (got) return QStringLiteral("a reference where none was");
    if (want) return QStringLiteral("no reference where one was");
    return {};
}

/// How `got` differs from `want` in what the artist made (the layers' filters, parameters, names,
/// weights and auto's corrections, the composite; images bit for bit): "" when it does not.
inline QString sessionDifference(const denoise::Session& got, const denoise::Session& want) {
    if (got.layerCount() != want.layerCount())
        return QStringLiteral("%1 layers, expected %2")
            .arg(got.layerCount())
            .arg(want.layerCount());
    for (std::size_t i = 0; i < want.layerCount(); ++i) {
        const denoise::SessionLayer &g = got.layer(i), &w = want.layer(i);
        const QString at = QStringLiteral("layer %1: ").arg(i);
        if (g.filter != w.filter || g.params != w.params)
            return at +
                   QString::fromStdString(g.filter + " with other parameters than " + w.filter);
        if (g.name != w.name)
            return at + QString::fromStdString("named " + g.name + ", not " + w.name);
        if (!sameBits(g.weights, w.weights)) return at + QStringLiteral("other weights");
        if (bool(g.correction) != bool(w.correction) ||
            (w.correction && (!sameBits(g.correction->result, w.correction->result) ||
                              !sameBits(g.correction->blend, w.correction->blend))))
            return at + QStringLiteral("another correction");
    }
    return sameBits(got.composite(), want.composite()) ? QString()
                                                       : QStringLiteral("another composite");
}

}  // namespace glint::studio::testing
