#include "app/file_naming.h"

#include <QFileInfo>
#include <QRegularExpression>

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

}  // namespace glint::studio
