// The files the studio opens, by name: scene.json (and .glint-session.json), every asset format
// the renderer registers (glint/render/asset_formats.h) and layered EXRs. The Open dialog, drag
// and drop and the document's choice between a scene and an EXR all read this one list.
#pragma once

#include <QString>
#include <QStringList>

namespace glint::studio {

/// The name patterns of the files the studio opens: "*.json", each asset extension
/// ("*.obj", ...), "*.exr".
QStringList openablePatterns();

/// The Open dialog's filter: "Scenes, assets, renders and sessions (PATTERNS);;All files (*)".
QString openDialogFilter();

/// True when the studio opens `path` (its name ends with an openable extension, in any case).
bool isOpenableFile(const QString& path);

/// True when `path` is a scene the renderer loads: a scene.json or an asset of a registered
/// format.
bool isScenePath(const QString& path);

}  // namespace glint::studio
