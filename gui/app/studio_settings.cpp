#include "app/studio_settings.h"

#include <QFileInfo>
#include <QMainWindow>
#include <QSettings>

namespace glint::studio {

namespace {
const QString kRecent = QStringLiteral("recentFiles");
}

QStringList recentFiles() {
    QStringList out;
    for (const QString& f : QSettings().value(kRecent).toStringList())
        if (QFileInfo::exists(f)) out << f;
    return out;
}

void addRecentFile(const QString& path) {
    QStringList files = QSettings().value(kRecent).toStringList();
    const QString absolute = QFileInfo(path).absoluteFilePath();
    files.removeAll(absolute);
    files.prepend(absolute);
    while (files.size() > kMaxRecent) files.removeLast();
    QSettings().setValue(kRecent, files);
}

namespace {
// Version 2: Compare moved under Look (the window fits 1366×768); older layouts are not restored.
constexpr int kStateVersion = 2;
}  // namespace

void saveWindowState(const QMainWindow& window) {
    QSettings s;
    s.setValue(QStringLiteral("window/geometry"), window.saveGeometry());
    s.setValue(QStringLiteral("window/state"), window.saveState(kStateVersion));
}

void restoreWindowState(QMainWindow& window) {
    QSettings s;
    window.restoreGeometry(s.value(QStringLiteral("window/geometry")).toByteArray());
    window.restoreState(s.value(QStringLiteral("window/state")).toByteArray(), kStateVersion);
}

}  // namespace glint::studio
