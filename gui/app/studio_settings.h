// What the studio remembers between runs (QSettings): recent files, the window layout and the
// programs the user allowed external denoisers to run.
#pragma once

#include <QStringList>

class QMainWindow;

namespace glint::studio {

/// The recent files, newest first (at most kMaxRecent, existing files only).
QStringList recentFiles();
/// Puts `path` first in the recent files.
void addRecentFile(const QString& path);
inline constexpr int kMaxRecent = 8;

/// The programs the user allowed external denoisers to run (full paths), as saved.
QStringList allowedCommands();
/// Allows `program` (a full path) for good: saved in the settings and allowed in this process
/// (glint/denoise/external.h). Returns false, changing nothing, for a path that is not absolute.
bool allowCommandForGood(const QString& program);
/// Allows in this process exactly the saved programs (called at start).
void applyAllowedCommands();

void saveWindowState(const QMainWindow& window);
/// Restores the saved geometry and panel layout; false when there was no layout of this version
/// to restore (the window keeps its own).
bool restoreWindowState(QMainWindow& window);

/// The tev settings (QSettings "tev/listenPort", "tev/anyInterface", "tev/display"; docs/studio.md,
/// "Receiving images"): all off unless set, the command line's options win over them.
struct TevSettings {
    int listenPort = -1;  ///< -1: do not listen
    bool anyInterface = false;
    QString display;  ///< HOST:PORT, empty: do not send
};
TevSettings tevSettings();

}  // namespace glint::studio
