// Autosave and crash recovery: each running studio journals its edits into a folder of its own
// under the autosave base (named by its process id); a clean exit removes the folder. At start,
// a folder whose process is gone is a crash: the studio offers to restore it by replaying it.
// A folder the user declined, or that could not be restored, is kept aside under another name
// (<pid>.kept-<time>): never offered again, never deleted.
#pragma once

#include <QObject>
#include <QString>
#include <QStringList>

#include <functional>
#include <memory>

#include "model/document.h"
#include "model/journal.h"
#include "model/recovery.h"
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

    /// Records that `document`'s file is open (the first entry of a restorable journal); an
    /// image received from a tev client, which no file holds, with its pixels.
    void recordOpen(const Document& document);
    /// Journals `document`'s render settings whenever the user changes them (spp, seed,
    /// integrator, MIS, half buffers), as look edits are, its reference whenever it changes
    /// (a rendered one with its pixels), and a received image's pixels whenever its client
    /// updates them: a restore brings them back.
    void watch(Document* document);
    /// Waits for pending writes (tests and screenshots).
    void flush() { m_journal->flush(); }
    Journal* journal() { return m_journal.get(); }
    /// Removes this studio's journal (a clean exit).
    void discard();

    /// Replays the journal in `folder` on a worker (model/recovery.h) and hands the result to
    /// `done` on the UI thread: the recovered state, or null and the error. Nothing of the
    /// studio changes here; the caller applies the result and then calls finishRestore().
    void restore(
        const QString& folder,
        std::function<void(std::shared_ptr<Recovered> recovered, const QString& error)> done);
    /// True from restore() until its `done`.
    bool restoring() const { return m_restoring; }
    /// After a restore was applied: removes `folder` once this studio's journal holds the
    /// restored state.
    void finishRestore(const QString& folder);
    /// Keeps `folder` aside so that it is not offered again (renamed, not deleted: nothing is
    /// lost), and returns its new path ("" when it cannot be renamed; it is then left as is).
    static QString setAside(const QString& folder);

  private:
    FramePtr m_journalledReference;  // the reference the journal holds last
    FramePtr m_journalledReceived;   // the received image's pixels the journal holds last
    std::unique_ptr<Journal> m_journal;
    TaskRunner m_tasks;
    bool m_restoring = false;
};

}  // namespace glint::studio
