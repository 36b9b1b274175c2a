// Recovering a crashed studio's autosave (docs/studio.md, "Autosave and restore"): the journal in
// a folder replayed, on a worker thread, into the state it describes (the file open, its look and
// render settings, the painting session) without touching the studio. The studio then applies the
// finished result at once, or, when any entry does not apply, changes nothing. No widgets here.
#pragma once

#include <QString>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "glint/denoise/session.h"
#include "model/document.h"
#include "model/journal_codec.h"

namespace glint::studio {

/// One look property as the journal left it.
struct LookValue {
    std::string item, property;
    std::array<double, 3> value{};
};

/// One step of the studio's undo stack as the journal built it: `edits` session edits (a look
/// edit has none) or a look edit (`before` and `after`), named as the studio names it (editText).
struct RestoredStep {
    int edits = 0;
    std::optional<LookValue> before, after;
    QString text;
};

/// The state a journal restores to.
struct Recovered {
    QString path;                              ///< the file open at the crash ("": none)
    std::shared_ptr<Document::Loaded> file;    ///< that file, loaded
    std::vector<LookValue> look;               ///< look edits, in order (checked against the file)
    std::optional<render::Settings> settings;  ///< the render settings chosen (checked)
    std::vector<double> lasso;  ///< the region of interest: x, y pairs (empty: the whole image)
    std::optional<journal_codec::View> view;    ///< the last "view" line's (none: never changed)
    std::shared_ptr<denoise::Session> session;  ///< null: no session
    FramePtr input, filterInput;                ///< shared copies of the session's render
    /// The journal's last "reference" entry, if any (after the last "open"): what the
    /// reference became (nullopt: cleared) and, for a rendered one, its pixels.
    bool referenceSet = false;
    std::optional<ReferenceInfo> referenceInfo;
    FramePtr reference;
    /// The undo history since the session started, oldest first, and the steps undone (the next
    /// redo last): the studio's undo stack at the crash.
    std::vector<RestoredStep> undo, redo;
    int edits = 0;           ///< journal entries replayed
    bool complete = true;    ///< false: the journal ended in an unreadable entry (cut by the crash)
    std::thread::id worker;  ///< the thread that did the work (tests check it is not the UI's)
};

/// Replays the journal in `folder` (Journal::read). Everything runs on the calling thread and
/// touches nothing else. The journal's undo and redo are replayed step for step (one step per
/// undoable edit, as the studio's undo stack had them). Throws glint::Error naming the journal
/// file, the entry's line and what does not fit (a layer the session does not have, a look
/// property the scene lacks, render settings out of range, a file that no longer opens);
/// Cancelled when `progress` returns false.
Recovered recover(const QString& folder, const denoise::ProgressFn& progress = {});

}  // namespace glint::studio
