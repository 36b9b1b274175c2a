// Running a user's program for the external filter: argv without a shell, stdin from /dev/null,
// stdout discarded, stderr captured, in its own process group, waited for with a timeout and a
// cancel test. Private to the external filter.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace glint::denoise::detail {

/// How a program run ended.
struct ProcessOutcome {
    enum class End { Exited, Signalled, TimedOut, Stopped } end = End::Exited;
    int code = 0;            ///< exit code (Exited) or signal number (Signalled)
    std::string stderrTail;  ///< the last lines the program wrote to stderr (at most ~4 KiB)
};

/// Runs argv[0] (an absolute path) with `argv` in folder `workDir`, as its own process group.
/// Polls `keepGoing` about every 20 ms; when it returns false, or after `timeoutSeconds`, the
/// whole group is killed (SIGKILL) and reaped. Throws glint::Error(Io) when the program cannot
/// be started. Never leaves a child behind, even when `keepGoing` throws.
ProcessOutcome runProcess(const std::vector<std::string>& argv,
                          const std::filesystem::path& workDir, double timeoutSeconds,
                          const std::function<bool()>& keepGoing);

/// The last non-empty lines of `text` (at most `count`), joined by " | ".
std::string lastLines(const std::string& text, int count);

}  // namespace glint::denoise::detail
