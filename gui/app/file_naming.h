// The names of files the studio shows and proposes: the window title's name of a scene, the folder
// and file name a save dialog opens on, and the extension a save dialog's answer gets (the chosen
// filter's, added when the name does not end with it).
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

/// What names an opened file in the window title: its folder and its name ("cornell/scene.json",
/// "glTF/DamagedHelmet.gltf"), since many assets share a file name (scene.json, scene.gltf).
/// Empty for an empty path.
QString documentTitle(const QString& path);

/// The base of the names the save dialogs propose for what was opened from `path`: the file's
/// name without its extensions ("DamagedHelmet"), or its folder's name when that is a generic
/// "scene" ("cornell" for cornell/scene.json). "untitled" for an empty path.
QString defaultBaseName(const QString& path);

/// True when files can be written in `folder`: it exists, the user may write there and its
/// permissions allow writing to someone (a folder without any write permission counts as
/// read-only even for the super-user).
bool isWritableFolder(const QString& folder);

/// The first of `preferred` that isWritableFolder(), else the user's Documents folder, else the
/// home folder.
QString writableFolder(const QStringList& preferred);

}  // namespace glint::studio
