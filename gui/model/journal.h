// The autosave journal: every edit of the session (and of the look) appended as one JSON line to
// a folder of its own, with the images it needs (weight maps, fill masks, renders) as EXR files
// beside it, so that a crash loses at most the edit being made. Replaying the journal into a
// fresh session rebuilds the same weights, composite and undo history.
#pragma once

#include <QObject>
#include <QString>

#include <functional>
#include <memory>
#include <vector>

#include "model/session_adapter.h"
#include "model/task_runner.h"

namespace glint::studio {

class Journal : public QObject {
    Q_OBJECT
  public:
    /// A journal in `folder` (created; an existing journal there is replaced).
    explicit Journal(const QString& folder, QObject* parent = nullptr);
    ~Journal() override;

    QString folder() const { return m_folder; }
    /// Appends an entry: its line at once, its images and render written in the background.
    void append(const JournalEntry& entry);
    /// Waits until every file of the entries appended so far is on disk.
    void flush();
    /// Runs `fn` (on the UI thread, without waiting here) once every file of the entries
    /// appended so far is on disk.
    void afterWrites(std::function<void()> fn);
    /// Removes the folder (a clean exit: nothing to restore).
    void discard();
    /// Makes the journal in `folder` — a crashed studio's, just restored from its first `entries`
    /// entries (read) — this journal, continued from there: the folder moves into this one's
    /// place, a line cut by the crash dropped, so that a later crash replays the restored
    /// history too. False when it cannot (this journal then holds what it held).
    bool adopt(const QString& folder, int entries);
    /// While paused, appended entries are dropped (what the adopted journal already holds is
    /// being applied).
    void setPaused(bool paused) { m_paused = paused; }

    /// The entries of the journal in `folder`, up to the first one that cannot be read (a line
    /// cut short by the crash, a missing side file): `complete` tells whether all were read.
    /// "input" entries other than the latest whose render is on disk come without a render (the
    /// final state depends only on the latest): replay skips them.
    static std::vector<JournalEntry> read(const QString& folder, bool* complete = nullptr);

  private:
    QString m_folder;
    TaskRunner m_writes;
    int m_next = 0;            // numbers the side files
    QString m_previousInput;   // the render of the last "input" entry (superseded by the next)
    QString m_previousPixels;  // the render of the last "pixels" entry since the last "open"
    int m_pendingWrites = 0;
    bool m_paused = false;
    std::vector<std::function<void()>> m_afterWrites;
    void written();
};

}  // namespace glint::studio
