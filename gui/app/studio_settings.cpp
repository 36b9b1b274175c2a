#include "app/studio_settings.h"

#include <QFileInfo>
#include <QMainWindow>
#include <QSettings>

#include "glint/denoise/external.h"

namespace glint::studio {

namespace {
const QString kRecent = QStringLiteral("recentFiles");
// Never read from a session or scene: only the user adds to it (docs/external-denoiser.md).
const QString kAllowedCommands = QStringLiteral("externalDenoiser/allowedCommands");
}  // namespace

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

QStringList allowedCommands() {
    QStringList out;
    for (const QString& p : QSettings().value(kAllowedCommands).toStringList())
        if (QFileInfo(p).isAbsolute()) out << p;
    return out;
}

bool allowCommandForGood(const QString& program) {
    if (!QFileInfo(program).isAbsolute()) return false;
    QStringList list = allowedCommands();
    if (!list.contains(program)) list << program;
    QSettings().setValue(kAllowedCommands, list);
    denoise::allowCommand(program.toStdString());
    return true;
}

void applyAllowedCommands() {
    denoise::clearAllowedCommands();
    for (const QString& p : allowedCommands()) denoise::allowCommand(p.toStdString());
}

namespace {
// Version 2: Compare moved under Look (the window fits 1366×768); version 3: panels narrower
// (the window fits 1280×720). Older layouts are not restored.
constexpr int kStateVersion = 3;
}  // namespace

void saveWindowState(const QMainWindow& window) {
    QSettings s;
    s.setValue(QStringLiteral("window/geometry"), window.saveGeometry());
    s.setValue(QStringLiteral("window/state"), window.saveState(kStateVersion));
}

bool restoreWindowState(QMainWindow& window) {
    QSettings s;
    window.restoreGeometry(s.value(QStringLiteral("window/geometry")).toByteArray());
    return window.restoreState(s.value(QStringLiteral("window/state")).toByteArray(),
                               kStateVersion);
}

TevSettings tevSettings() {
    QSettings s;
    TevSettings t;
    t.listenPort = s.value(QStringLiteral("tev/listenPort"), -1).toInt();
    t.anyInterface = s.value(QStringLiteral("tev/anyInterface"), false).toBool();
    t.display = s.value(QStringLiteral("tev/display")).toString();
    return t;
}

}  // namespace glint::studio
