// The process-wide list of programs external denoisers may run (glint/denoise/external.h).
#include <cstdlib>
#include <fstream>
#include <mutex>

#include "glint/denoise/external.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace fs = std::filesystem;

namespace {

struct AllowList {
    std::mutex mutex;
    std::vector<fs::path> programs;
};

AllowList& allowList() {
    static AllowList list;
    return list;
}

// The file a path names once symbolic links are followed (the path itself when it does not
// exist), so that /usr/bin/python3 and the python3.12 it links to are one program.
fs::path resolved(const fs::path& program) {
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(program, ec);
    return ec ? program.lexically_normal() : canonical;
}

}  // namespace

void allowCommand(const fs::path& program) {
    if (!program.is_absolute())
        throw Error(ErrorKind::InvalidArgument,
                    "'" + program.string() +
                        "' is not a full path (an allowed command is named "
                        "by its absolute path, e.g. /opt/oidn/bin/oidnDenoise)",
                    {}, "--allow-command");
    AllowList& list = allowList();
    std::lock_guard lock(list.mutex);
    list.programs.push_back(program.lexically_normal());
}

bool commandAllowed(const fs::path& program) {
    if (!program.is_absolute()) return false;
    const fs::path normal = program.lexically_normal();
    const fs::path target = resolved(program);
    AllowList& list = allowList();
    std::lock_guard lock(list.mutex);
    for (const fs::path& allowed : list.programs)
        if (allowed == normal || resolved(allowed) == target) return true;
    return false;
}

std::vector<fs::path> allowedCommands() {
    AllowList& list = allowList();
    std::lock_guard lock(list.mutex);
    return list.programs;
}

void clearAllowedCommands() {
    AllowList& list = allowList();
    std::lock_guard lock(list.mutex);
    list.programs.clear();
}

fs::path allowedCommandsFile() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME");
        xdg && *xdg && fs::path(xdg).is_absolute())
        return fs::path(xdg) / "glint" / "allowed-commands";
    if (const char* home = std::getenv("HOME"); home && *home)
        return fs::path(home) / ".config" / "glint" / "allowed-commands";
    return {};
}

void allowCommandsFromFile(const fs::path& file) {
    std::error_code ec;
    if (file.empty() || !fs::exists(file, ec)) return;
    std::ifstream in(file);
    if (!in) throw Error(ErrorKind::Io, "cannot read the allowed-commands file", file.string());
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
            line.pop_back();
        if (line.empty() || line.front() == '#') continue;
        if (!fs::path(line).is_absolute())
            throw Error(ErrorKind::Format,
                        "'" + line + "' is not a full path (one absolute path a line)",
                        file.string(), "line " + std::to_string(number));
        allowCommand(line);
    }
}

std::string howToAllow(const fs::path& program) {
    return "allow it with --allow-command " + program.string() + " (or list it in " +
           (allowedCommandsFile().empty() ? std::string("$XDG_CONFIG_HOME/glint/allowed-commands")
                                          : allowedCommandsFile().string()) +
           ")";
}

}  // namespace glint::denoise
