// Autosave and crash recovery: each running studio journals its edits into a folder of its own
// under the autosave base (named by its process id); a clean exit removes the folder. At start,
// a folder whose process is gone is a crash: the studio offers to restore it by replaying it.
#pragma once

#include <QObject>
#include <QString>
#include <QStringList>

#include <functional>
#include <memory>

#include "model/document.h"
#include "model/journal.h"
#include "model/session_adapter.h"
#include "model/task_runner.h"

namespace glint::studio {

class Autosave : public QObject {
    Q_OBJECT
  public:
    /// Journals `session`'s edits under `base` (default: the user's application data folder).
    Autosave(const QString& base, SessionAdapter* session, QObject* parent = nullptr);
    ~Autosave() override;

    /// The default base: $GLINT_STUDIO_AUTOSAVE, else <AppLocalData>/autosave.
    static QString defaultBase();
    /// Folders under `base` left by studios that did not exit cleanly, newest first.
    static QStringList crashed(const QString& base);

    /// Records that `path` is open (the first entry of a restorable journal).
    void recordOpen(const QString& path);
    /// Journals `document`'s render settings whenever the user changes them (spp, seed,
    /// integrator, MIS, half buffers), as look edits are, and its reference whenever it changes
    /// (a rendered one with its pixels): a restore brings them back.
    void watch(Document* document);
    /// Waits for pending writes (tests and screenshots).
    void flush() { m_journal->flush(); }
    Journal* journal() { return m_journal.get(); }
    /// Removes this studio's journal (a clean exit).
    void discard();

    /// Replays the journal in `folder` into the document and session in the background (the
    /// journal of this studio records the replay, so a second crash is covered too), then
    /// removes `folder`. `done` gets the number of edits restored, whether the journal was
    /// complete (false when it ended in an unreadable entry: the edit being made at the crash),
    /// and "" or the error of an entry that does not apply (the folder is then kept).
    void restore(const QString& folder, Document* document,
                 std::function<void(int restored, bool complete, const QString& error)> done);
    /// True from restore() until its `done`.
    bool restoring() const { return m_restoring; }

  private:
    struct Restore;
    void step(const std::shared_ptr<Restore>& r);
    void finish(const std::shared_ptr<Restore>& r, const QString& error);

    SessionAdapter* m_session;
    FramePtr m_journalledReference;  // the reference the journal holds last
    std::unique_ptr<Journal> m_journal;
    TaskRunner m_tasks;
    bool m_restoring = false;
};

}  // namespace glint::studio
