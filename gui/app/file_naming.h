// The name a save dialog's answer gets: the chosen filter's extension is added when the name does
// not end with it (a session, a scene or an export typed without one).
#pragma once

#include <QString>
#include <QStringList>

namespace glint::studio {

/// The extensions of a dialog filter such as "Glint sessions (*.glint-session.json)" or
/// "Images (*.exr *.png)", in order, each with its leading dot (".glint-session.json").
QStringList filterExtensions(const QString& filter);

/// `path` with the first extension of `filter` appended when its file name ends with none of the
/// filter's extensions (a trailing dot is dropped first); `path` itself otherwise (and when
/// empty, or when the filter names no extension, "All files (*)").
QString withFilterExtension(const QString& path, const QString& filter);

}  // namespace glint::studio
