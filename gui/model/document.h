// What the studio has open: a scene (rendered, its look editable) or a layered EXR, the render
// settings, the latest frame, and an optional reference. Loading and rendering run on worker
// threads; the document's signals arrive on the UI thread. No widgets here.
#pragma once

#include <QFileSystemWatcher>
#include <QObject>
#include <QString>
#include <QTimer>

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/render/look.h"
#include "glint/render/renderer.h"
#include "glint/render/settings.h"
#include "model/reference_info.h"
#include "model/render_eta.h"
#include "model/render_job.h"
#include "model/task_runner.h"

namespace glint::studio {

class ProgressiveRender;

/// Sets one property of `look` to `value`. Throws glint::Error(InvalidArgument) naming `file`
/// for a property it lacks or a value out of the property's range (nothing changes then).
void setLookValue(std::vector<render::LookItem>& look, const std::string& item,
                  const std::string& property, const std::array<double, 3>& value,
                  const std::string& file = {});

/// One point of the convergence plot: a pass of the running render against the reference.
struct CurvePoint {
    double seconds = 0.0;
    int spp = 0;
    double relMse = 0.0;
};

class Document : public QObject {
    Q_OBJECT
  public:
    enum class Kind { None, Scene, Exr };

    explicit Document(QObject* parent = nullptr);
    ~Document() override;

    /// A file as opening it loads it (touching no document: safe on a worker thread): a scene
    /// with its renderer, look and settings, or a layered EXR's frame.
    struct Loaded {
        Kind kind = Kind::None;
        std::shared_ptr<render::Renderer> renderer;
        std::vector<render::LookItem> look;
        render::Settings settings;
        std::shared_ptr<const FrameBuffers> frame;
        std::string camera;  // sceneCamera() of a scene; empty for an EXR
        /// What the open did that the artist should know (the render kept in a denoised EXR
        /// opened instead of its colour); empty otherwise.
        QString note;
    };
    /// Loads `path` (a scene.json, glTF or OBJ asset, or layered EXR). Throws glint::Error.
    static Loaded load(const QString& path);

    /// Opens a scene.json (renders at once) or a layered EXR, in the background. `render`
    /// false opens a scene without rendering (a restored session brings its own frame).
    void open(const QString& path, bool render = true);
    /// Makes `loaded` (load(path), e.g. on a worker) the open file, as open() does once loaded.
    void adopt(const QString& path, Loaded loaded, bool render = true);
    Kind kind() const { return m_kind; }
    QString path() const { return m_path; }
    /// Loaded::note of the open file (for the status bar), empty for most files.
    QString openNote() const { return m_openNote; }
    bool isOpen() const { return m_kind != Kind::None; }
    bool loading() const { return m_loading; }

    /// Render settings (spp, seed, integrator, MIS; region). Changing them does not render.
    const render::Settings& settings() const { return m_settings; }
    /// Throws glint::Error for settings out of range; emits settingsChanged when they change.
    void setSettings(const render::Settings& settings);

    /// The look, the render settings the user sets (spp, seed, integrator, MIS, half buffers) or
    /// the reference differ from those last opened or saved.
    bool modified() const;
    /// The present look, settings and reference are saved (a session file carries them now).
    void markSaved();
    /// Renders the scene with the settings (cancels a running render).
    void render();
    /// Renders only `region` and merges it into the current frame (nullopt: the whole frame).
    void renderRegion(const std::optional<Rect>& region);
    void cancelRender();
    void setPaused(bool paused);
    bool paused() const { return m_job.paused(); }
    /// True while a render runs (or its last frame is being merged into the frame it renders
    /// a region of).
    bool rendering() const { return m_job.busy() || m_merging; }
    /// True while the render running is of a region (its passes are merged into the frame).
    bool renderingRegion() const { return rendering() && m_mergeRegion.has_value(); }
    /// Keep refining: with `progressive` enabled, a whole-frame render goes on past the bar's
    /// spp, steered by it (model/progressive_render.h); null or disabled: renders stop at spp.
    void setProgressive(ProgressiveRender* progressive) { m_progressive = progressive; }
    /// True while the render refines past the bar's spp (its frame at that spp is the finished
    /// frame already).
    bool refining() const { return m_job.busy() && m_refineSpp > 0 && m_refineReached; }

    /// The look of the scene as last edited (materials, lights, environment).
    const std::vector<render::LookItem>& look() const { return m_look; }
    /// The value of one look property (throws glint::Error for an unknown one).
    std::array<double, 3> lookValue(const std::string& item, const std::string& property) const;
    /// Edits one look property and re-renders (unless `render` is false). Throws
    /// glint::Error(InvalidArgument) for a value outside the property's range (nothing changes).
    void setLook(const std::string& item, const std::string& property,
                 const std::array<double, 3>& value, bool render = true);
    /// Writes the scene with its look edits as JSON (atomically).
    void saveScene(const QString& path);

    /// The latest frame (a pass of the running render, or the last finished one).
    FramePtr frame() const { return m_frame; }
    /// The last finished (or cancelled) render's frame: what the session filters.
    FramePtr finishedFrame() const { return m_finished; }
    /// Adopts a frame from elsewhere (a restored session's input) as the finished frame.
    void setFinishedFrame(FramePtr frame);

    /// The reference, if any (opened or rendered in the background).
    FramePtr reference() const { return m_reference; }
    /// What the reference was rendered for, or the file it was read from (nullopt: none).
    const std::optional<ReferenceInfo>& referenceInfo() const { return m_referenceInfo; }
    void openReference(const QString& path);
    /// Adopts the reference a saved session or the autosave describes: `frame` when its pixels
    /// were kept (a rendered one); else the info's file is read again (in the background) and
    /// used only if its content is what was opened then (emits failed() otherwise). `saved`: it
    /// is what the open session file holds, so it does not make the document modified.
    void restoreReference(const ReferenceInfo& info, FramePtr frame, bool saved);
    /// Renders a reference at `spp` in the background with its own renderer.
    void renderReference(int spp);
    void clearReference();
    /// Whether the reference was rendered for what is open now: its scene, look and camera
    /// (model/reference_info.h); None without a reference.
    ReferenceMismatch referenceMismatch() const;
    /// The reference was rendered for another scene, look or camera than the current one
    /// (referenceMismatch() is Scene, Look or Camera; not Unknown).
    bool referenceLookDiffers() const;
    bool referenceRendering() const { return m_referenceJob && m_referenceJob->busy(); }

    /// relMSE of each pass of the current render against the reference.
    const std::vector<CurvePoint>& curve() const { return m_curve; }

    /// Statistics of the last finished render.
    const render::RenderStats& lastStats() const { return m_stats; }

  signals:
    void opened();
    /// A pass arrived (final = false) or the render finished (final = true).
    void frameChanged(bool final);
    void renderProgress(int pass, double fraction, int spp, double seconds);
    void renderingChanged(bool rendering);
    void lookChanged();
    void settingsChanged();
    /// modified() may have changed.
    void modifiedChanged();
    void referenceChanged();
    /// The reference render did `fraction` of its work: `spp` of `totalSpp` samples, the time
    /// left in `secondsLeft` (negative before there is an estimate, model/render_eta.h).
    void referenceProgress(double fraction, int spp, int totalSpp, double secondsLeft);
    void curveChanged();
    /// Something failed: `title` says what was attempted, `message` names the file and place.
    void failed(const QString& title, const QString& message);

  private:
    void startRender(const render::Settings& settings, RenderJob::Steering steering = {});
    void onPass(std::uint64_t id, FramePtr frame, int spp, double seconds);
    void onFinished(std::uint64_t id, FramePtr frame, const render::RenderStats& stats);
    void sceneFileChanged();
    void addCurvePoint(FramePtr frame, int spp, double seconds);
    /// Reads the reference `path` on a worker; `expected`: its content must have that identity.
    void readReference(const QString& path, std::optional<std::uint64_t> expected, bool saved);
    void setReference(FramePtr frame, std::optional<ReferenceInfo> info, bool saved);
    /// `apply(frame)` on the UI thread, the frame merged first (on a worker) when the render
    /// covers a region.
    void mergeThen(std::uint64_t id, FramePtr frame, bool final,
                   std::function<void(FramePtr)> apply);

    TaskRunner m_tasks;
    RenderJob m_job;
    std::unique_ptr<RenderJob> m_referenceJob;
    RemainingTime m_referenceEta;
    QFileSystemWatcher m_watcher;
    QTimer m_reloadTimer;

    Kind m_kind = Kind::None;
    QString m_path;
    QString m_openNote;
    bool m_loading = false;
    render::Settings m_settings;
    std::vector<render::LookItem> m_look;
    std::vector<render::LookItem> m_savedLook;  // as last opened or saved (modified())
    render::Settings m_savedSettings;
    FramePtr m_frame;
    FramePtr m_finished;
    std::string m_camera;                      // sceneCamera() of the scene open
    std::vector<render::LookItem> m_fileLook;  // the look of the file as opened (its own)
    FramePtr m_reference;
    std::optional<ReferenceInfo> m_referenceInfo;
    FramePtr m_savedReference;          // as last opened or saved (modified())
    std::optional<Rect> m_mergeRegion;  // the running render covers only this region
    FramePtr m_mergeBase;               // and is merged into this frame
    bool m_merging = false;             // the final frame of a region render is being merged
    std::vector<CurvePoint> m_curve;
    render::RenderStats m_stats;
    ProgressiveRender* m_progressive = nullptr;
    int m_refineSpp = 0;           // the bar's spp of the refining render running (0: none)
    bool m_refineReached = false;  // and its frame at that spp is the finished frame
    render::Settings m_renderBar;  // the bar's settings of the render running
    // The bar's settings of the whole-frame render the finished frame came from, while a refining
    // render may go on from it (ProgressiveRender::continues): none after a scene edit, another
    // frame adopted, a region merged, or a render stopped before the bar's spp.
    std::optional<render::Settings> m_continuable;
};

/// Copies every layer of `part` inside `region` into a copy of `base` (same size).
FrameBuffers mergeRegion(const FrameBuffers& base, const FrameBuffers& part, const Rect& region);

}  // namespace glint::studio
