// The studio's main window: it owns the model (document, session, region, autosave), lays out
// the views (viewer in the centre, look panel left, stages and comparison right, render bar on
// top), wires the actions, and turns every failure into one clear dialog. The work is done by
// the views and the model.
#pragma once

#include <QMainWindow>

#include <functional>
#include <memory>
#include <optional>

#include "app/actions.h"
#include "app/autosave.h"
#include "model/document.h"
#include "model/region.h"
#include "model/session_adapter.h"
#include "views/viewer.h"

class QTabWidget;
class QLabel;
class QProgressBar;
class QMenu;

namespace glint::studio {

class RenderBar;
class LookPanel;
class FeaturesView;
class RegionView;
class TuneView;
class NavigateView;
class PaintView;
class CompareView;
class HelpOverlay;
class ElidedLabel;
class StageView;
class ProgramAllowance;
class TevListener;
class TevSender;
class ProgressiveRender;

/// Options of a studio window (from the command line, or a test).
struct StudioOptions {
    QString autosaveBase;  ///< empty: Autosave::defaultBase()
    bool offerRestore = true;
    bool confirmDiscard = true;  ///< ask before unsaved painting is dropped (tests say no)
    /// A newly opened file's first render gets a cross-bilateral layer (model/first_denoise.h).
    bool denoiseFirstImage = true;
    /// Listen for tev clients on this port (-1: do not; 0: any free one), on 127.0.0.1 unless
    /// `tevAnyInterface` (docs/studio.md, "Receiving images").
    int tevListenPort = -1;
    bool tevAnyInterface = false;
    /// Send each pass of a render to tev at HOST:PORT (empty: do not).
    QString tevDisplay;
};

class MainWindow : public QMainWindow {
    Q_OBJECT
  public:
    explicit MainWindow(const StudioOptions& options = {}, QWidget* parent = nullptr);
    ~MainWindow() override;

    /// Opens a scene.json, a layered EXR or a .glint-session.json.
    void openFile(const QString& path);
    /// Saves the session (with the region and view state) to `path` on a worker; false when it
    /// cannot start. An error is shown in a dialog; session()->busy() holds until it is written.
    bool saveSession(const QString& path);
    /// Unsaved painting, look edits or render settings (the title's asterisk; Quit asks).
    bool isModified() const;
    /// The start of glint-studio: opens `file` (when given) at once, then, when `offerRestore`,
    /// offers a crashed studio's autosave beside it without blocking anything.
    void start(const QString& file, bool offerRestore = true);
    /// Offers to restore a crashed studio's autosave: asks (a question that blocks nothing:
    /// "No" keeps the autosave aside, not offered again) unless `ask` is false.
    void offerRestore(bool ask = true);
    /// Restores the autosave in `folder`, all or nothing: the replay runs on a worker and the
    /// result replaces the document, look, settings and session at once; when any part does not
    /// restore, nothing changes, one error says why and the autosave is kept aside.
    void restoreFrom(const QString& folder);

    // The parts, for tests and the screenshot tour.
    Document* document() { return m_document; }
    SessionAdapter* session() { return m_session; }
    /// Keep refining's steering (Render ▸ Keep Refining).
    ProgressiveRender* progressive() { return m_progressive; }
    RegionOfInterest* region() { return m_region; }
    Viewer* viewer() { return m_viewer; }
    LookPanel* lookPanel() { return m_look; }
    FeaturesView* featuresView() { return m_features; }
    RegionView* regionView() { return m_regionView; }
    TuneView* tuneView() { return m_tune; }
    NavigateView* navigateView() { return m_navigate; }
    PaintView* paintView() { return m_paint; }
    CompareView* compareView() { return m_compare; }
    RenderBar* renderBar() { return m_renderBar; }
    Autosave* autosave() { return m_autosave.get(); }
    /// The question that allows an unavailable layer's program (app/program_allowance.h).
    ProgramAllowance* programAllowance() { return m_allowance; }
    const StudioActions& actions() const { return m_actions; }
    /// The tev listener (null unless StudioOptions::tevListenPort asked for one) and sender.
    TevListener* tevListener() { return m_tevListener; }
    TevSender* tevSender() { return m_tevSender; }
    /// Switches to stage 0–3 (features, region, filter, paint); `navigate` picks the navigation
    /// tab of the filter stage.
    void setStage(int stage, bool navigate = false);
    int stage() const;
    /// The last error shown (title and message), for tests.
    QString lastError() const { return m_lastError; }
    /// The last status-bar message, for tests.
    QString lastStatus() const { return m_lastStatus; }
    /// Where a save dialog of `filter` opens: a writable folder (app/file_naming.h) and a name
    /// from the scene's, with `suffix` and the filter's first extension.
    QString saveDialogStart(const QString& filter, const QString& suffix = {}) const;

  signals:
    /// An error dialog was opened.
    void errorShown(const QString& title, const QString& message);

  protected:
    void closeEvent(QCloseEvent* event) override;
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;

  private:
    void buildMenus();
    void connectModel();
    void showError(const QString& title, const QString& message);
    void showStatus(const QString& message);
    /// True when unsaved painting may be dropped now; after "Save", false, and `again` runs once
    /// the save succeeded.
    bool maybeSave(std::function<void()> again);
    void updateTitle();
    void rebuildRecent();
    void stageChanged();
    StageView* activeStage() const;
    std::map<std::string, std::string> viewState() const;
    void applyViewState(const std::map<std::string, std::string>& state);
    /// The reference `state` describes, from the session's side frame or its file.
    void restoreReference(const std::map<std::string, std::string>& state);
    /// Journals (setLook) each look value that differs from `before`.
    void journalLookChanges(const std::vector<render::LookItem>& before);
    /// The exposure, Keep Refining, the stage and the channel, for the autosave (not an undo
    /// step).
    void journalView();
    /// Keep Refining on or off without rendering (a session or a restore sets it).
    void setKeepRefiningQuietly(bool on);
    /// What a session file or a restore sets of the view (each when given), without rendering,
    /// journalled as one line.
    void setView(std::optional<double> exposure, std::optional<bool> keepRefining,
                 std::optional<int> stage, std::optional<Viewer::Channel> channel);
    QString askPath(const QString& title, const QString& filter, bool save,
                    const QString& suffix = {});
    void exportResult(bool exr);
    /// Applies a restore; `withHistory`: its undo history too (the journal was adopted).
    void applyRecovered(Recovered& recovered, bool withHistory);
    QString autosaveBase() const;
    /// The tev listener and sender of the options, their log lines in the status bar.
    void connectTev();

    StudioOptions m_options;
    ProgressiveRender* m_progressive = nullptr;
    Document* m_document;
    SessionAdapter* m_session;
    RegionOfInterest* m_region;
    std::unique_ptr<Autosave> m_autosave;
    StudioActions m_actions;
    Viewer* m_viewer;
    RenderBar* m_renderBar;
    LookPanel* m_look;
    FeaturesView* m_features;
    RegionView* m_regionView;
    TuneView* m_tune;
    NavigateView* m_navigate;
    PaintView* m_paint;
    CompareView* m_compare;
    HelpOverlay* m_help;
    ProgramAllowance* m_allowance;
    QTabWidget* m_stages;
    QTabWidget* m_filterTabs;
    ElidedLabel* m_readout;
    QLabel* m_busy;
    QProgressBar* m_busyProgress;
    QMenu* m_recentMenu;
    QString m_sessionPath;
    QString m_lastError;
    QString m_lastStatus;
    StageView* m_activeStage = nullptr;
    bool m_restoring = false;
    bool m_viewJournalHeld = false;     // setView: one view line for all it sets
    std::function<void()> m_afterSave;  // what maybeSave() resumes once the save is written
    TevListener* m_tevListener = nullptr;
    TevSender* m_tevSender = nullptr;
};

}  // namespace glint::studio
