#include "model/document.h"

#include <QFileInfo>

#include <cmath>
#include <filesystem>

#include "glint/denoise/denoised_frame.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/render/scene.h"
#include "glint/render/settings_codec.h"
#include "model/openable_files.h"
#include "model/progressive_render.h"
#include "model/session_state.h"

namespace glint::studio {

namespace {

std::filesystem::path toPath(const QString& path) {
    return std::filesystem::path(path.toStdString());
}

// The settings a user chooses in the render bar, compared (render::Settings has no ==).
bool sameUserSettings(const render::Settings& a, const render::Settings& b) {
    return render::encodeSettings(a, userSettingNames()) ==
           render::encodeSettings(b, userSettingNames());
}

// A scene with a renderer, loaded on a worker thread.
Document::Loaded loadRenderer(const std::filesystem::path& path) {
    render::Scene scene = render::loadScene(path);
    Document::Loaded out;
    out.kind = Document::Kind::Scene;
    out.settings = scene.settings();
    out.look = scene.look();
    out.camera = sceneCamera(path);
    out.renderer = std::make_shared<render::Renderer>(std::move(scene));
    return out;
}

}  // namespace

FrameBuffers mergeRegion(const FrameBuffers& base, const FrameBuffers& part, const Rect& region) {
    GLINT_CHECK(base.width() == part.width() && base.height() == part.height());
    FrameBuffers out = base;
    const Rect r = intersect(region, Rect{0, base.width(), 0, base.height()});
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        const Image* src = part.find(layer);
        if (!src) continue;
        Image& dst = out.ensure(layer);
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x)
                for (int c = 0; c < src->channels(); ++c) dst(x, y, c) = (*src)(x, y, c);
    }
    // Half buffers must cover the whole frame consistently: when only one of the two renders
    // has them, the merged frame has none (its halves would not add up to its colour).
    if (base.has(Layer::HalfColor) != part.has(Layer::HalfColor))
        for (int l = 0; l < kLayerCount; ++l)
            if (isHalfLayer(Layer(l))) out.remove(Layer(l));
    return out;
}

Document::Document(QObject* parent) : QObject(parent) {
    connect(&m_job, &RenderJob::passDone, this, &Document::onPass);
    connect(&m_job, &RenderJob::finished, this, &Document::onFinished);
    connect(&m_job, &RenderJob::progress, this,
            [this](std::uint64_t id, int pass, double fraction, double seconds) {
                if (id == m_job.currentId())
                    emit renderProgress(pass, fraction, m_frame ? m_frame->metadata().spp : 0,
                                        seconds);
            });
    connect(&m_job, &RenderJob::failed, this, [this](std::uint64_t, const QString& message) {
        emit failed(tr("Render failed"), message);
    });
    connect(&m_job, &RenderJob::busyChanged, this, [this] { emit renderingChanged(rendering()); });
    // An editor saves a file in several writes: reload once it has settled.
    m_reloadTimer.setSingleShot(true);
    m_reloadTimer.setInterval(200);
    connect(&m_reloadTimer, &QTimer::timeout, this, &Document::sceneFileChanged);
    connect(&m_watcher, &QFileSystemWatcher::fileChanged, this, [this] { m_reloadTimer.start(); });
}

Document::~Document() = default;

Document::Loaded Document::load(const QString& path) {
    const std::filesystem::path file = toPath(path);
    Loaded out;
    if (isScenePath(path)) {
        out = loadRenderer(file);
        out.settings.threads = 0;
        return out;
    }
    // A denoised EXR that keeps its render (glint-final's, glint-denoise's, an export; layer
    // noisy) opens as that render: every filter and Auto Start work from the samples the
    // variance and halves describe.
    const FrameBuffers read = readExr(file);
    if (denoise::keepsRender(read))
        out.note = tr("Opened the render kept in %1 (its colour was denoised%2): filters and "
                      "Auto Start work from the render")
                       .arg(QFileInfo(path).fileName(),
                            read.metadata().extra.count("denoiseFilter")
                                ? tr(" by %1").arg(QString::fromStdString(
                                      read.metadata().extra.at("denoiseFilter")))
                                : QString());
    FrameBuffers frame = denoise::renderOf(read);
    out.kind = Kind::Exr;
    out.settings.spp = frame.metadata().spp > 0 ? frame.metadata().spp : out.settings.spp;
    out.frame = std::make_shared<const FrameBuffers>(std::move(frame));
    return out;
}

void Document::open(const QString& path, bool renderNow) {
    m_loading = true;
    m_tasks.run<std::shared_ptr<Loaded>>(
        QStringLiteral("open"),
        [path](const TaskRunner::CancelFlag&) { return std::make_shared<Loaded>(load(path)); },
        [this, path, renderNow](std::shared_ptr<Loaded> loaded) {
            adopt(path, std::move(*loaded), renderNow);
        },
        [this, path](const QString& message) {
            m_loading = false;
            emit failed(tr("Cannot open %1").arg(QFileInfo(path).fileName()), message);
        });
}

void Document::adopt(const QString& path, Loaded loaded, bool renderNow) {
    m_loading = false;
    if (!m_watcher.files().isEmpty()) m_watcher.removePaths(m_watcher.files());
    m_kind = loaded.kind;
    m_path = path;
    m_openNote = loaded.note;
    m_look = std::move(loaded.look);
    m_fileLook = m_look;
    m_camera = std::move(loaded.camera);
    m_settings = loaded.settings;
    m_reference.reset();
    m_referenceInfo.reset();
    m_curve.clear();
    m_continuable.reset();
    if (m_kind == Kind::Scene) {
        m_frame.reset();
        m_finished.reset();
        m_job.setRenderer(loaded.renderer);
        m_watcher.addPath(path);
    } else {
        m_job.cancel();
        m_tasks.cancel(QStringLiteral("merge"));
        m_merging = false;
        m_job.setRenderer(nullptr);
        m_frame = loaded.frame;
        m_finished = loaded.frame;
    }
    emit opened();
    emit lookChanged();
    emit referenceChanged();
    // What was opened (and restored while it opened) is the saved state.
    markSaved();
    if (m_kind == Kind::Exr)
        emit frameChanged(true);
    else if (renderNow)
        render();
}

void Document::setSettings(const render::Settings& settings) {
    render::validate(settings);
    const bool changed = !sameUserSettings(settings, m_settings);
    m_settings = settings;
    if (!changed) return;
    emit settingsChanged();
    emit modifiedChanged();
}

bool Document::modified() const {
    return !sameUserSettings(m_settings, m_savedSettings) || !sameLook(m_look, m_savedLook) ||
           m_reference != m_savedReference;
}

void Document::markSaved() {
    m_savedLook = m_look;
    m_savedSettings = m_settings;
    m_savedReference = m_reference;
    emit modifiedChanged();
}

void Document::render() {
    if (m_kind != Kind::Scene) return;
    m_mergeRegion.reset();
    m_mergeBase.reset();
    render::Settings s = m_settings;
    s.region.reset();
    if (m_progressive && m_progressive->enabled() && ProgressiveRender::applies(s)) {
        render::Settings refining = ProgressiveRender::refining(s);
        // The finished render of these settings goes on (Keep Refining turned on after it)
        // rather than rendering the bar's spp again.
        const bool goOn = m_finished && m_continuable &&
                          ProgressiveRender::continues(*m_continuable, s, *m_finished);
        if (goOn) refining.continueFrom = m_finished;
        startRender(refining, m_progressive->steer([job = &m_job] { return job->stopping(); }));
        m_refineSpp = s.spp;
        m_refineReached = goOn;
        m_renderBar = s;
        return;
    }
    startRender(s);
    m_renderBar = s;
}

void Document::renderRegion(const std::optional<Rect>& region) {
    if (m_kind != Kind::Scene) return;
    if (!region || !m_finished || m_settings.integrator != render::Integrator::Path) {
        render();
        return;
    }
    m_mergeRegion = region;
    m_mergeBase = m_finished;
    render::Settings s = m_settings;
    s.region = region;
    startRender(s);
    m_renderBar = s;
}

void Document::startRender(const render::Settings& settings, RenderJob::Steering steering) {
    // A merge of the previous render's frame is stale.
    m_tasks.cancel(QStringLiteral("merge"));
    m_merging = false;
    m_refineSpp = 0;
    m_refineReached = false;
    m_curve.clear();
    emit curveChanged();
    m_job.start(settings, std::move(steering));
}

void Document::cancelRender() {
    m_job.cancel();
}

void Document::setPaused(bool paused) {
    m_job.setPaused(paused);
}

void Document::onPass(std::uint64_t id, FramePtr frame, int spp, double seconds) {
    if (id != m_job.currentId()) return;
    if (m_refineSpp > 0 && !m_refineReached && spp >= m_refineSpp) {
        // A refining render at the bar's spp: the render as it would have finished; it goes on.
        m_refineReached = true;
        m_continuable = m_renderBar;
        render::RenderStats stats;
        stats.completedSpp = spp;
        stats.seconds = seconds;
        m_stats = stats;
        m_frame = frame;
        m_finished = frame;
        emit frameChanged(true);
        if (m_reference) addCurvePoint(frame, spp, seconds);
        return;
    }
    mergeThen(id, frame, false, [this, spp, seconds](FramePtr merged) {
        m_frame = merged;
        emit frameChanged(false);
        if (m_reference) addCurvePoint(merged, spp, seconds);
    });
}

void Document::onFinished(std::uint64_t id, FramePtr frame, const render::RenderStats& stats) {
    if (id != m_job.currentId()) return;
    // Stopped before anything was rendered; but a render that went on from the finished frame
    // (Keep Refining turned on after it) holds that frame, and its end is a refinement's end.
    const bool wentOn = m_refineSpp > 0 && m_refineReached;
    if (stats.passes == 0 && stats.cancelled && !wentOn) return;
    mergeThen(id, frame, true, [this, stats](FramePtr merged) {
        // Every pixel of a whole frame at the bar's spp at least: a refinement may go on from it.
        const bool whole = !m_mergeRegion && !m_renderBar.region;
        if (whole && (m_refineSpp > 0 ? m_refineReached : !stats.cancelled))
            m_continuable = m_renderBar;
        else
            m_continuable.reset();
        m_refineSpp = 0;  // a refining render ends here
        m_refineReached = false;
        m_stats = stats;
        m_frame = merged;
        m_finished = merged;
        emit frameChanged(true);
    });
}

void Document::mergeThen(std::uint64_t id, FramePtr frame, bool final,
                         std::function<void(FramePtr)> apply) {
    if (!m_mergeRegion || !m_mergeBase) {
        apply(frame);
        return;
    }
    // Copying a frame (every layer, about 100 MB at 1024²) takes longer than a frame: on a
    // worker. A newer pass supersedes an older one still merging; the final one is the last.
    const Rect region = *m_mergeRegion;
    FramePtr base = m_mergeBase;
    if (final) m_merging = true;  // rendering() holds until the merged frame is in place
    m_tasks.run<FramePtr>(
        QStringLiteral("merge"),
        [base, frame, region](const TaskRunner::CancelFlag&) {
            return FramePtr(
                std::make_shared<const FrameBuffers>(mergeRegion(*base, *frame, region)));
        },
        [this, id, final, apply = std::move(apply)](FramePtr merged) {
            if (id != m_job.currentId()) return;
            if (final) m_merging = false;
            apply(merged);
            if (final) emit renderingChanged(rendering());
        });
}

void Document::setFinishedFrame(FramePtr frame) {
    m_continuable.reset();
    m_frame = frame;
    m_finished = frame;
    emit frameChanged(true);
}

void Document::addCurvePoint(FramePtr frame, int spp, double seconds) {
    FramePtr reference = m_reference;
    if (!reference || reference->width() != frame->width() ||
        reference->height() != frame->height())
        return;
    // One task per pass (distinct keys): every point of the curve is kept.
    m_tasks.run<double>(
        QStringLiteral("curve-%1").arg(spp),
        [frame, reference](const TaskRunner::CancelFlag&) {
            return relMse(frame->color(), reference->color()).value;
        },
        [this, spp, seconds](double value) {
            m_curve.push_back({seconds, spp, value});
            std::sort(m_curve.begin(), m_curve.end(),
                      [](const CurvePoint& a, const CurvePoint& b) { return a.spp < b.spp; });
            emit curveChanged();
        });
}

std::array<double, 3> Document::lookValue(const std::string& item,
                                          const std::string& property) const {
    for (const render::LookItem& i : m_look)
        if (i.name == item)
            for (const render::LookProperty& p : i.properties)
                if (p.name == property) return p.value;
    throw Error(ErrorKind::InvalidArgument, "no look property " + item + "/" + property);
}

void setLookValue(std::vector<render::LookItem>& look, const std::string& item,
                  const std::string& property, const std::array<double, 3>& value,
                  const std::string& file) {
    render::LookProperty* target = nullptr;
    for (render::LookItem& i : look)
        if (i.name == item)
            for (render::LookProperty& p : i.properties)
                if (p.name == property) target = &p;
    if (!target)
        throw Error(ErrorKind::InvalidArgument, "no look property " + item + "/" + property, file);
    const int n = target->isColour ? 3 : 1;
    for (int c = 0; c < n; ++c)
        if (!(value[std::size_t(c)] >= target->min && value[std::size_t(c)] <= target->max))
            throw Error(ErrorKind::InvalidArgument,
                        target->label + " must lie in [" + std::to_string(target->min) + ", " +
                            std::to_string(target->max) + "]",
                        file, item + "/" + property);
    target->value = value;
}

void Document::setLook(const std::string& item, const std::string& property,
                       const std::array<double, 3>& value, bool renderNow) {
    setLookValue(m_look, item, property, value, m_path.toStdString());
    m_continuable.reset();  // the finished frame is of the scene before the edit
    emit modifiedChanged();
    m_job.withScene(
        [item, property, value](render::Scene& scene) { scene.setLook(item, property, value); },
        [this](const QString& error) {
            if (!error.isEmpty()) emit failed(tr("The scene refused the change"), error);
        });
    emit lookChanged();
    if (renderNow) render();
}

void Document::saveScene(const QString& path) {
    const std::filesystem::path file = toPath(path);
    const bool same = QFileInfo(path) == QFileInfo(m_path);
    // Our own write must not trigger a reload.
    if (same) m_watcher.removePath(m_path);
    const std::vector<render::LookItem> look = m_look;
    m_job.withScene([file](render::Scene& scene) { render::saveScene(scene, file); },
                    [this, path, same, look](const QString& error) {
                        if (same) m_watcher.addPath(m_path);
                        // The file holds this look now (what glint-render renders of it).
                        if (same && error.isEmpty()) m_fileLook = look;
                        if (!error.isEmpty()) emit failed(tr("Cannot save %1").arg(path), error);
                    });
}

void Document::sceneFileChanged() {
    if (m_kind != Kind::Scene) return;
    // Editors replace the file: watch the new one.
    if (!m_watcher.files().contains(m_path) && QFileInfo::exists(m_path)) m_watcher.addPath(m_path);
    const std::filesystem::path file = toPath(m_path);
    m_tasks.run<Loaded>(
        QStringLiteral("reload"),
        [file](const TaskRunner::CancelFlag&) { return loadRenderer(file); },
        [this](Loaded loaded) {
            m_look = std::move(loaded.look);
            m_fileLook = m_look;
            m_camera = std::move(loaded.camera);
            m_job.setRenderer(loaded.renderer);
            m_continuable.reset();  // the finished frame is of the file before the edit
            emit lookChanged();
            markSaved();  // the file on disk is the look now
            render();
        },
        [this](const QString& message) {
            emit failed(tr("The edited scene cannot be loaded"), message);
        });
}

void Document::openReference(const QString& path) {
    readReference(path, std::nullopt, false);
}

void Document::restoreReference(const ReferenceInfo& info, FramePtr frame, bool saved) {
    if (frame) {
        setReference(frame, info, saved);
        return;
    }
    if (info.source == ReferenceInfo::Source::File) {
        readReference(QString::fromStdString(info.file), info.identity, saved);
        return;
    }
    emit failed(tr("The reference was not restored"),
                tr("The pixels of the reference rendered for %1 were not kept")
                    .arg(QString::fromStdString(info.scene)));
}

void Document::readReference(const QString& path, std::optional<std::uint64_t> expected,
                             bool saved) {
    const std::filesystem::path file = toPath(path);
    struct Read {
        FramePtr frame;
        std::uint64_t identity = 0;
    };
    m_tasks.run<Read>(
        QStringLiteral("reference"),
        [file](const TaskRunner::CancelFlag&) {
            FrameBuffers frame = readExr(file);
            const std::uint64_t identity = referenceIdentity(frame);
            return Read{std::make_shared<const FrameBuffers>(std::move(frame)), identity};
        },
        [this, path, expected, saved](Read read) {
            const QString name = QFileInfo(path).fileName();
            if (expected && read.identity != *expected) {
                emit failed(tr("The reference %1 was not restored").arg(name),
                            tr("%1: the file changed since it was opened as the reference (its "
                               "content is not the one the session compared with)")
                                .arg(path));
                return;
            }
            const FrameBuffers& frame = *read.frame;
            if (m_finished &&
                (frame.width() != m_finished->width() || frame.height() != m_finished->height())) {
                emit failed(tr("Cannot use %1 as the reference").arg(name),
                            tr("%1: the reference is %2x%3, the image %4x%5")
                                .arg(path)
                                .arg(frame.width())
                                .arg(frame.height())
                                .arg(m_finished->width())
                                .arg(m_finished->height()));
                return;
            }
            ReferenceInfo info;
            info.source = ReferenceInfo::Source::File;
            info.file = QFileInfo(path).absoluteFilePath().toStdString();
            info.identity = read.identity;
            // What the file says it was rendered from (glint-render's glint:scene).
            info.scene = frame.metadata().scene;
            setReference(read.frame, info, saved);
        },
        [this, path](const QString& message) {
            emit failed(tr("Cannot open the reference %1").arg(QFileInfo(path).fileName()),
                        message);
        });
}

void Document::setReference(FramePtr frame, std::optional<ReferenceInfo> info, bool saved) {
    m_reference = std::move(frame);
    m_referenceInfo = std::move(info);
    if (saved) m_savedReference = m_reference;
    emit referenceChanged();
    emit modifiedChanged();
}

void Document::renderReference(int spp) {
    if (m_kind != Kind::Scene) return;
    render::Settings s = m_settings;
    s.spp = spp;
    s.seed = referenceSeed(s.seed);  // independent of the render's samples
    s.halfBuffers = false;           // compared against, never denoised: one sequence is less noisy
    s.region.reset();
    s.timeLimit = 0.0;
    render::validate(s);
    const std::filesystem::path file = toPath(m_path);
    // What it is rendered for: saved with the session beside its pixels.
    ReferenceInfo info;
    info.source = ReferenceInfo::Source::Rendered;
    info.scene = QFileInfo(m_path).absoluteFilePath().toStdString();
    info.look = m_look;
    info.camera = m_camera;
    info.settings = s;
    const std::vector<render::LookItem> look = m_look;
    m_referenceJob = std::make_unique<RenderJob>();
    m_referenceEta.reset();
    connect(m_referenceJob.get(), &RenderJob::progress, this,
            [this, spp](std::uint64_t, int pass, double fraction, double seconds) {
                const std::optional<double> left = m_referenceEta.update(pass, fraction, seconds);
                emit referenceProgress(fraction, int(std::lround(fraction * spp)), spp,
                                       left ? *left : -1.0);
            });
    connect(m_referenceJob.get(), &RenderJob::finished, this,
            [this, info](std::uint64_t, FramePtr frame, const render::RenderStats& stats) {
                if (stats.cancelled) return;
                setReference(frame, info, false);
            });
    connect(m_referenceJob.get(), &RenderJob::failed, this,
            [this](std::uint64_t, const QString& m) {
                emit failed(tr("The reference render failed"), m);
            });
    RenderJob* job = m_referenceJob.get();
    // The reference has its own renderer: the scene is loaded again and given the current look.
    m_tasks.run<Loaded>(
        QStringLiteral("reference"),
        [file, look](const TaskRunner::CancelFlag&) {
            Loaded loaded = loadRenderer(file);
            for (const render::LookItem& item : look)
                for (const render::LookProperty& p : item.properties)
                    loaded.renderer->scene().setLook(item.name, p.name, p.value);
            return loaded;
        },
        [this, job, s](Loaded loaded) {
            if (job != m_referenceJob.get()) return;
            job->setRenderer(loaded.renderer);
            job->start(s);
            emit referenceChanged();
        },
        [this](const QString& message) {
            emit failed(tr("The reference render failed"), message);
        });
}

ReferenceMismatch Document::referenceMismatch() const {
    if (!m_reference || !m_referenceInfo) return ReferenceMismatch::None;
    ReferenceTarget now;
    // An open EXR shows the scene its glint:scene names (its look and camera the file's own).
    now.scene = m_kind == Kind::Scene ? QFileInfo(m_path).absoluteFilePath().toStdString()
                : m_finished          ? m_finished->metadata().scene
                                      : std::string();
    now.look = m_look;
    now.fileLook = m_fileLook;
    now.camera = m_camera;
    return glint::studio::referenceMismatch(*m_referenceInfo, now);
}

bool Document::referenceLookDiffers() const {
    const ReferenceMismatch m = referenceMismatch();
    return m != ReferenceMismatch::None && m != ReferenceMismatch::Unknown;
}

void Document::clearReference() {
    m_referenceJob.reset();
    m_curve.clear();
    setReference(nullptr, std::nullopt, false);
    emit curveChanged();
}

}  // namespace glint::studio
