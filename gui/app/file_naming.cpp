#include "app/file_naming.h"

#include <QDir>
#include <QFileInfo>
#include <QRegularExpression>
#include <QStandardPaths>

namespace glint::studio {

QStringList filterExtensions(const QString& filter) {
    // The patterns are inside the last parentheses: "Name (*.a *.b)".
    const qsizetype open = filter.lastIndexOf(QLatin1Char('('));
    const qsizetype close = filter.lastIndexOf(QLatin1Char(')'));
    const QString patterns =
        open >= 0 && close > open ? filter.mid(open + 1, close - open - 1) : filter;
    QStringList out;
    for (const QString& p :
         patterns.split(QRegularExpression(QStringLiteral("\\s+")), Qt::SkipEmptyParts))
        if (p.startsWith(QStringLiteral("*.")) && p.size() > 2 &&
            p.indexOf(QLatin1Char('*'), 1) < 0)
            out << p.mid(1);
    return out;
}

QString withFilterExtension(const QString& path, const QString& filter) {
    if (path.isEmpty()) return path;
    const QStringList extensions = filterExtensions(filter);
    if (extensions.isEmpty()) return path;
    const QString name = QFileInfo(path).fileName();
    for (const QString& ext : extensions)
        if (name.endsWith(ext, Qt::CaseInsensitive) && name.size() > ext.size()) return path;
    // What is written is of the filter's kind: "render", "render." and "shot.v2" get its
    // extension (a file the Open dialog's filter would hide otherwise).
    QString base = path;
    if (base.endsWith(QLatin1Char('.'))) base.chop(1);
    return base + extensions.first();
}

QString documentTitle(const QString& path) {
    if (path.isEmpty()) return {};
    const QFileInfo info(path);
    const QString folder = info.absoluteDir().dirName();
    return folder.isEmpty() ? info.fileName() : folder + QLatin1Char('/') + info.fileName();
}

QString defaultBaseName(const QString& path) {
    if (path.isEmpty()) return QStringLiteral("untitled");
    const QFileInfo info(path);
    const QString base = info.baseName();  // before the first dot: "a.glint-session.json" is "a"
    const QString folder = info.absoluteDir().dirName();
    if ((base.isEmpty() || base.compare(QStringLiteral("scene"), Qt::CaseInsensitive) == 0) &&
        !folder.isEmpty())
        return folder;
    return base.isEmpty() ? QStringLiteral("untitled") : base;
}

bool isWritableFolder(const QString& folder) {
    if (folder.isEmpty()) return false;
    const QFileInfo info(folder);
    // The permission bits (not WriteUser, which asks access() and is true for the super-user).
    const QFile::Permissions write = QFile::WriteOwner | QFile::WriteGroup | QFile::WriteOther;
    return info.isDir() && info.isWritable() && (info.permissions() & write);
}

QString writableFolder(const QStringList& preferred) {
    for (const QString& folder : preferred)
        if (isWritableFolder(folder)) return QFileInfo(folder).absoluteFilePath();
    const QString documents = QStandardPaths::writableLocation(QStandardPaths::DocumentsLocation);
    if (isWritableFolder(documents)) return documents;
    return QDir::homePath();
}

}  // namespace glint::studio
