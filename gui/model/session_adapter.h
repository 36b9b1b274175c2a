// The studio's painting session: a glint::denoise::Session driven from the UI thread, with the
// slow parts (filter outputs over the whole frame, re-applying the layers to a new render,
// Poisson diffusion, loading) on worker threads, every edit one QUndoStack step, and every
// edit reported to the autosave journal. No widgets here.
#pragma once

#include <QJsonObject>
#include <QObject>
#include <QString>
#include <QStringList>
#include <QUndoStack>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/denoise/session.h"
#include "model/bank_service.h"
#include "model/journal_codec.h"
#include "model/render_job.h"
#include "model/session_build.h"
#include "model/task_runner.h"

namespace glint::studio {

class Document;
struct RestoredStep;

/// One edit as the journal records it: the operation and, for fills and weight maps, images.
struct JournalEntry {
    QJsonObject op;
    std::vector<Image> images;  ///< masks or weight maps the op refers to, in order
    FramePtr frame;             ///< a new input render ("input" and "start" ops)
};

class SessionAdapter : public QObject {
    Q_OBJECT
  public:
    explicit SessionAdapter(QObject* parent = nullptr);
    ~SessionAdapter() override;

    QUndoStack* undoStack() { return &m_undo; }
    bool hasSession() const { return m_session != nullptr; }
    /// The session (hasSession() must hold).
    const denoise::Session& session() const { return *m_session; }
    /// The render the session filters (shared with the document).
    FramePtr input() const { return m_input; }
    /// The filters' input: the render with its features prefiltered when the options say so.
    FramePtr filterInput() const { return m_filterInput; }
    const denoise::SessionOptions& options() const { return m_options; }
    /// The filter banks of the input (Navigate and Auto Start share them).
    BankService* banks() { return &m_banks; }
    /// The options of the studio's banks of the input (studioBankOptions): `size` members over
    /// `region` (the whole frame when empty), with the filters and fixed parameters of the bank
    /// folder the session names (Session::bankDir), if any.
    denoise::BankOptions bankOptions(int size, const std::optional<Rect>& region = {}) const;
    /// True while a background step (re-applying, adding a layer, diffusing, loading) runs.
    bool busy() const { return m_tasks.pending() > 0 || m_autoStartTicket != 0; }
    /// True while a worker reads the session (diffusion): edits wait, painting is refused.
    bool locked() const { return m_locked; }
    /// A layer's composite position changes counted since the session started: views cache by it.
    std::uint64_t revision() const { return m_revision; }

    /// A new render: starts a session on it, or re-applies the layers to it in the background
    /// (the painting stays; a render of another size starts a new session). `journal` false: a
    /// preview (a pass of a render still running) the journal does not record.
    void setInput(FramePtr frame, bool journal = true);
    /// Runs the layers again on the present render, in the background as for a new render: a
    /// layer that could not run (a program the user has just allowed) runs now.
    void rerunLayers();
    /// Turns feature prefiltering on or off for the filters (the layers are carried over, the
    /// undo history starts again).
    void setOptions(const denoise::SessionOptions& options);

    /// Adds a layer of `filter` (its output over the whole frame is computed in the background)
    /// and, when `fillMask` is given, sets its weight to 1 there: one undo step.
    void addLayer(const std::string& filter, const denoise::ParamValues& params,
                  std::optional<Image> fillMask = std::nullopt);
    /// As addLayer with the filter and parameters (over the filter's defaults) `choose` names
    /// on the filters' input, on the same worker (busy() meanwhile); nothing when it names none.
    void addChosenLayer(
        std::function<std::pair<std::string, denoise::ParamValues>(const FrameBuffers&)> choose,
        std::optional<Image> fillMask = std::nullopt);
    void removeLayer(std::size_t index);
    /// Names a layer (empty: named after its filter again): one undo step, saved with the
    /// session.
    void renameLayer(std::size_t index, const std::string& name);
    /// Sets a layer's weight map (one undo step); `weights` is moved into the journal.
    void setWeights(std::size_t index, Image weights);
    void fill(std::size_t index, const Image& mask, denoise::BrushMode mode);
    /// The magic wand from pixel (x, y) of the filters' input (denoise::magicWand, on a worker),
    /// then fill() with its mask; clicks are filled in the order they came.
    void wand(std::size_t index, int x, int y, const denoise::WandOptions& options,
              denoise::BrushMode mode);
    /// Poisson-diffusion blending of `layers` (in the background; painting waits meanwhile).
    void diffuse(const std::vector<std::size_t>& layers);
    /// "Auto start": in the background, a bank of `bankSize` members over the input (from the
    /// bank service) and the per-pixel choice among them (glint/denoise/auto.h); then auto's
    /// result is added as one layer (auto's correction over the composite, weight 1: the result
    /// bit for bit), one undo step ("Auto start"); its choice map is kept (autoChoice).
    void autoStart(int bankSize = 64);
    /// What Auto Start chose per pixel for its result layer (for the choice map).
    struct AutoChoiceMap {
        std::shared_ptr<const Image> choice;  ///< 1 channel: the member index per pixel
        QStringList members;                  ///< distinct display names (distinctNames), by member
        int used = 0;                         ///< members with any weight in the blend
    };
    /// The choice map of layer `index` when it is the result layer of an Auto Start run in this
    /// studio; null otherwise (a session opened from a file does not carry it).
    const AutoChoiceMap* autoChoice(std::size_t index) const;

    /// A stroke: dabs update the composite at once (on the UI thread); the end is one undo step.
    void beginStroke(std::size_t layer, const denoise::Brush& brush, denoise::BrushMode mode);
    Rect dab(double x, double y);
    void endStroke();
    bool inStroke() const { return m_session && m_session->inStroke(); }

    /// Saves the session file (the region, view state and side frames — a reference, say —
    /// come from the caller) on a worker, atomically; the session is locked meanwhile. `done`
    /// gets "" or the error on the UI thread. Throws glint::Error when there is no session.
    void save(const QString& path, const std::optional<Rect>& region,
              const std::map<std::string, std::string>& viewState,
              const std::map<std::string, FramePtr>& frames,
              std::function<void(const QString&)> done = {});
    /// Writes the composite (EXR with the features, or PNG through `display`) on a worker, as
    /// save() does.
    void exportResult(const QString& path, bool exr, const DisplayOptions& display,
                      std::function<void(const QString&)> done = {});
    /// Loads a session file in the background; `loaded` is emitted when it is in place.
    void load(const QString& path);
    /// Replaces everything by `session` (an empty undo history); `input` and `filterInput` are
    /// shared copies of its render (made here when not given). Journalled (its layers' weights
    /// copied for the journal) unless `journalled` is false: a journal that holds it already.
    void install(denoise::Session session, FramePtr input = nullptr, FramePtr filterInput = nullptr,
                 bool journalled = true);
    /// Reports an edit made outside the session (a look edit, undo, redo) to the journal.
    void record(JournalEntry entry) { emit journal(entry); }
    /// Gives back the undo history a restore replayed (recover: `done` oldest first, `undone`
    /// with the next redo last) over the session just installed, which holds their edits; the
    /// look steps become LookCommands on `document`. Nothing is applied or journalled.
    void restoreHistory(const std::vector<RestoredStep>& done,
                        const std::vector<RestoredStep>& undone, Document* document);
    /// True while restoreHistory builds the stack: the commands do nothing then.
    bool restoringHistory() const { return m_restoringHistory; }
    /// Drops the session (journaled: a restore does not carry it over to the next file).
    void clear();

  signals:
    /// A new session (or none): views re-read everything.
    void sessionReset();
    /// The session filters a new render (a new session, or layers re-applied).
    void inputChanged();
    /// Part of the composite changed (the whole frame after a reapply or an undo).
    void compositeChanged(const glint::Rect& rect);
    /// Layers were added or removed, or anything may have changed (undo, redo, a new render).
    void layersChanged();
    /// Only weights changed (a stroke, a fill).
    void weightsChanged();
    void busyChanged(bool busy);
    void lockedChanged(bool locked);
    void progress(const QString& what, double fraction);
    void failed(const QString& title, const QString& message);
    /// A one-line note for the status bar (what Auto start made, and how it estimated the error).
    void status(const QString& message);
    /// The magic wand's selection (1 channel, 1 inside), before it fills the layer.
    void wandSelected(std::shared_ptr<const glint::Image> mask);
    /// A session file finished loading (its view state may be read now).
    void loaded(const QString& path);
    /// An edit happened (for the autosave journal).
    void journal(const glint::studio::JournalEntry& entry);

  private:
    friend class SessionCommand;
    void startSession(FramePtr frame, std::vector<denoise::LayerSpec> carry,
                      std::vector<Image> carryWeights, std::vector<std::string> carryNames = {});
    void reapplyInBackground();
    void installReapply(FramePtr frame, Reapplied& reapplied, bool journal);
    /// One undo step of `steps` session edits, named after `op` (editText).
    void pushEdit(const journal_codec::Op& op, int steps = 1);
    // A layer's filter, parameters and output, computed on a worker.
    struct NewLayer {
        std::string filter;
        denoise::ParamValues params;
        std::shared_ptr<Image> output;  // null: nothing to add
    };
    void runAddLayer(
        std::function<NewLayer(const FrameBuffers&, const TaskRunner::CancelFlag&)> work,
        std::optional<Image> fillMask);
    void doAddLayer(const std::string& filter, const denoise::ParamValues& params, Image output,
                    const std::optional<Image>& fillMask);
    void autoChoose(BankService::BankPtr bank, FramePtr in, const denoise::SessionOptions& options,
                    std::uint64_t generation);
    void whenUnlocked(std::function<void()> fn);
    /// Locks the session while a worker reads it (counted: reads may overlap).
    void lock();
    void unlock();
    /// Runs `read` on a worker with the session locked, then `done("" or the error)`.
    void readInBackground(const QString& what, std::function<void(const denoise::Session&)> read,
                          std::function<void(const QString&)> done);
    void changedAll();
    denoise::ProgressFn progressFor(const QString& what, const TaskRunner::CancelFlag& cancel);

    TaskRunner m_tasks;
    BankService m_banks;
    BankService::Ticket m_autoStartTicket = 0;
    // The options of the bank folder the session names (its filters and fixed parameters).
    denoise::BankOptions m_bankFolder;
    QUndoStack m_undo;
    std::shared_ptr<denoise::Session> m_session;  // shared with the workers reading it
    denoise::SessionOptions m_options;
    FramePtr m_input;
    FramePtr m_filterInput;
    FramePtr m_pendingInput;         // a render waiting for the open stroke to end
    bool m_pendingJournal = true;    // whether the journal records it (not for a preview)
    std::uint64_t m_generation = 0;  // counts inputs: outputs computed on an older one are stale
    std::uint64_t m_revision = 0;
    bool m_locked = false;
    bool m_restoringHistory = false;
    int m_readers = 0;          // workers reading the session (it is locked while > 0)
    std::uint64_t m_reads = 0;  // numbers their tasks
    // Magic-wand masks computed so far, filled in click order.
    std::uint64_t m_wandNext = 0, m_wandApplied = 0;
    std::map<std::uint64_t, std::function<void()>> m_wandReady;
    std::vector<std::function<void()>> m_afterUnlock;
    // Auto Start's choice maps, by the result layer they belong to.
    std::vector<std::pair<std::weak_ptr<const denoise::SessionCorrection>, AutoChoiceMap>>
        m_autoChoices;
    // The open stroke, for the journal and to tell whether it changed anything.
    journal_codec::Stroke m_stroke;  ///< the stroke being made, recorded when it ends
    Image m_strokeBefore;
};

/// One edit of the session on the undo stack: the session already did it when it is pushed;
/// undo and redo call the session's own.
class SessionCommand : public QUndoCommand {
  public:
    /// `steps` session edits make this one step (a layer added and filled, for instance).
    SessionCommand(SessionAdapter* adapter, const QString& text, int steps = 1);
    void undo() override;
    void redo() override;

  private:
    SessionAdapter* m_adapter;
    int m_steps;
    bool m_first = true;
};

}  // namespace glint::studio
