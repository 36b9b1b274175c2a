// What is at a path a scene names (a mesh, an MTL, a texture, a glTF buffer or image), told the
// same way by every reader: a missing file, a folder, or something that is not a regular file
// (a device or a pipe, which would be read without end) — docs/reliability.md.
#pragma once

#include <filesystem>
#include <string>

namespace glint::render::detail {

/// What is at a path, without following a name the file system refuses (too long...): that is
/// Missing, never an exception.
enum class InputKind { Missing, Folder, Special, Regular };

/// What is at `path` (symbolic links followed).
InputKind inputKind(const std::filesystem::path& path);

/// For a Folder or Special path: "is a folder, expected EXPECTED" or "is not a regular file (a
/// device or a pipe), expected EXPECTED"; empty for the other kinds.
std::string notARegularFile(InputKind kind, const std::string& expected);

/// Throws glint::Error(Io) naming `file` (the file that names the path) and `where` unless
/// `path` is a regular file: "WHAT file 'PATH' not found", "WHAT 'PATH' is a folder, expected
/// EXPECTED" or "WHAT 'PATH' is not a regular file (a device or a pipe), expected EXPECTED".
void requireRegularFile(const std::filesystem::path& path, const std::string& what,
                        const std::string& expected, const std::string& file,
                        const std::string& where);

}  // namespace glint::render::detail
