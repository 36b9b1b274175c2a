// The commands external denoisers may run (docs/external-denoiser.md). A file never runs a
// program by itself: a session, bank folder or scene naming an external member opens with that
// member unavailable unless the user allowed its program, by full path, in this process — from
// the command line (--allow-command), the user's config file, or the studio's settings.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace glint::denoise {

/// Allows external members to run `program` (a full path) in this process. Throws
/// glint::Error(InvalidArgument) for a path that is not absolute.
void allowCommand(const std::filesystem::path& program);
/// True when `program` (or the file it resolves to) was allowed.
bool commandAllowed(const std::filesystem::path& program);
/// The programs allowed so far, in the order given.
std::vector<std::filesystem::path> allowedCommands();
/// Forgets every allowance (the studio when its settings change; tests).
void clearAllowedCommands();

/// The user's file of allowed commands: $XDG_CONFIG_HOME/glint/allowed-commands, or
/// ~/.config/glint/allowed-commands without XDG_CONFIG_HOME (empty when neither is set).
std::filesystem::path allowedCommandsFile();
/// Allows every program listed in `file`, one full path a line ('#' starts a comment line). A
/// missing file allows nothing. Throws glint::Error(Format) naming the file and line for a
/// relative path, (Io) for a file that cannot be read.
void allowCommandsFromFile(const std::filesystem::path& file);

/// What an unavailable external member's message says to do: how to allow `program`.
std::string howToAllow(const std::filesystem::path& program);

}  // namespace glint::denoise
