#include "model/openable_files.h"

#include <QObject>

#include "glint/render/asset_formats.h"

namespace glint::studio {

namespace {

/// The extensions of the scenes the renderer loads: ".json" and the asset formats'.
QStringList sceneExtensions() {
    QStringList out{QStringLiteral(".json")};
    for (const std::string& ext : render::assetExtensions()) out << QString::fromStdString(ext);
    return out;
}

bool endsWithOneOf(const QString& path, const QStringList& extensions) {
    for (const QString& ext : extensions)
        if (path.endsWith(ext, Qt::CaseInsensitive)) return true;
    return false;
}

}  // namespace

QStringList openablePatterns() {
    QStringList out;
    for (const QString& ext : sceneExtensions()) out << QLatin1Char('*') + ext;
    out << QStringLiteral("*.exr");
    return out;
}

QString openDialogFilter() {
    return QObject::tr("Scenes, assets, renders and sessions (%1);;All files (*)")
        .arg(openablePatterns().join(QLatin1Char(' ')));
}

bool isOpenableFile(const QString& path) {
    return isScenePath(path) || path.endsWith(QStringLiteral(".exr"), Qt::CaseInsensitive);
}

bool isScenePath(const QString& path) {
    return endsWithOneOf(path, sceneExtensions());
}

}  // namespace glint::studio
