// What the studio remembers between runs (QSettings): recent files and the window layout.
#pragma once

#include <QStringList>

class QMainWindow;

namespace glint::studio {

/// The recent files, newest first (at most kMaxRecent, existing files only).
QStringList recentFiles();
/// Puts `path` first in the recent files.
void addRecentFile(const QString& path);
inline constexpr int kMaxRecent = 8;

void saveWindowState(const QMainWindow& window);
void restoreWindowState(QMainWindow& window);

}  // namespace glint::studio
