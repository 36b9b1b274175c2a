// The one catch boundary shared by Glint's command-line tools (glint-image, glint-render,
// glint-denoise): parse errors and glint::Error become one line on stderr and an exit code.
// Private to the CLIs (it includes CLI11); the libraries never see it.
#pragma once

#include <CLI/CLI.hpp>

#include <atomic>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <system_error>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <initializer_list>
#include <mutex>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include <signal.h>
#include <unistd.h>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::cli {

/// Parses the command line. Returns an exit code when the tool should stop now (help printed:
/// 0; a parse error: "tool: command line: ..." and 2), or nullopt to go on.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv, const char* tool) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "%s: command line: %s\n", tool, oneLine(e.what()).c_str());
        return 2;
    }
    return std::nullopt;
}

/// Checks before any work that `path` can be written as a file with one of `extensions` (e.g.
/// ".exr"; compared without case): the extension, an existing folder, not a folder itself.
/// Throws glint::Error(InvalidArgument) naming the flag and what is accepted.
inline void checkOutputPath(const std::string& path, std::initializer_list<const char*> extensions,
                            const char* flag) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    std::string ext = p.extension().string(), accepted;
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    bool ok = false;
    for (const char* e : extensions) {
        ok = ok || ext == e;
        accepted += (accepted.empty() ? "" : ", ") + std::string(e);
    }
    if (!ok)
        throw Error(ErrorKind::InvalidArgument,
                    "cannot write '" + path + "': expected a file ending in " + accepted, {}, flag);
    std::error_code ec;
    if (fs::is_directory(p, ec))
        throw Error(ErrorKind::InvalidArgument, "'" + path + "' is a folder, expected a file", {},
                    flag);
    const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    if (!fs::is_directory(folder, ec))
        throw Error(
            ErrorKind::InvalidArgument,
            "cannot write '" + path + "': the folder '" + folder.string() + "' does not exist", {},
            flag);
    if (::access(folder.c_str(), W_OK) != 0)
        throw Error(
            ErrorKind::InvalidArgument,
            "cannot write '" + path + "': the folder '" + folder.string() + "' is not writable", {},
            flag);
}

/// Parses `text` as a whole unsigned decimal integer in [0, max] (no sign, no spaces, no
/// overflow: "-1" is not 2^64 - 1 and a 20-digit number is not saturated). Throws
/// glint::Error(InvalidArgument) naming `flag` and the range.
inline std::uint64_t parseUnsigned(const std::string& text, std::uint64_t max, const char* flag) {
    std::uint64_t value = 0;
    const char* end = text.data() + text.size();
    const auto [stop, ec] = std::from_chars(text.data(), end, value);
    if (text.empty() || ec != std::errc() || stop != end || value > max)
        throw Error(ErrorKind::InvalidArgument,
                    "expected an integer in [0, " + std::to_string(max) + "], got '" + text + "'",
                    {}, flag);
    return value;
}

/// The largest seed any Glint tool takes (2^63 - 1, as glint-render's settings).
inline constexpr std::uint64_t kMaxSeed = (std::uint64_t(1) << 63) - 1;

/// An input of a command: the path given and the flag (or argument) that gave it.
struct NamedInput {
    std::string path;
    std::string flag;
};

/// Refuses before any work an output that is one of the command's inputs, compared by file
/// identity (device and inode), not by spelling: "./a.exr", a symlink and a hard link to an input
/// are that input. Writing there would replace the input (a reference, the noisy render) with the
/// result. Throws glint::Error(InvalidArgument) naming both flags.
inline void checkOutputIsNoInput(const std::string& output, const char* outputFlag,
                                 const std::vector<NamedInput>& inputs) {
    namespace fs = std::filesystem;
    if (output.empty()) return;
    std::error_code ec;
    if (!fs::exists(output, ec)) return;  // an input exists, so a missing output is none of them
    for (const NamedInput& in : inputs) {
        if (in.path.empty()) continue;
        if (fs::equivalent(output, in.path, ec) && !ec)
            throw Error(ErrorKind::InvalidArgument,
                        "'" + output + "' is the same file as the input given by " + in.flag +
                            " ('" + in.path + "'); writing it would destroy that input",
                        {}, outputFlag);
    }
}

namespace detail {
// The temporary files and folders of this process's outputs, in the order given, as a list a
// signal handler may walk at any moment: a node is whole before it is linked, nodes are never
// freed, and the list's head needs no initialisation at run time (constinit). A function-local
// static here would deadlock: a signal arriving while the first registration initialises it
// re-entered its initialisation guard from the handler.
struct SignalTemporary {
    const char* path = nullptr;
    std::atomic<SignalTemporary*> next{nullptr};
};
static_assert(std::atomic<SignalTemporary*>::is_always_lock_free);
constinit inline SignalTemporary signalTemporaryHead{};  // no path: the list starts at next
constinit inline SignalTemporary* signalTemporaryTail = &signalTemporaryHead;
constinit inline std::mutex
    signalTemporaryMutex{};  // for registering threads; never in the handler

inline void addSignalTemporary(const std::string& path) {
    char* copy = new char[path.size() + 1];
    std::memcpy(copy, path.c_str(), path.size() + 1);
    auto* node = new SignalTemporary;
    node->path = copy;
    const std::lock_guard<std::mutex> lock(signalTemporaryMutex);
    signalTemporaryTail->next.store(node, std::memory_order_release);
    signalTemporaryTail = node;
}

extern "C" inline void removeTemporariesAndDie(int sig) {
    // unlink a file, rmdir an (emptied) folder: both are async-signal-safe.
    for (const SignalTemporary* n = signalTemporaryHead.next.load(std::memory_order_acquire); n;
         n = n->next.load(std::memory_order_acquire))
        if (::unlink(n->path) != 0) ::rmdir(n->path);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}
}  // namespace detail

/// The one signal rule of every Glint tool (docs/reliability.md, "Signals"): SIGINT and SIGTERM
/// remove the temporary files registered below and then kill the process as the signal would;
/// a signal the process started with ignored stays ignored (the POSIX and GNU convention: a
/// background job of a non-interactive shell, or `nohup`, must not die of the terminal's ^C).
/// runGuarded installs it before the command runs; calling it again does nothing.
inline void installSignalRule() {
    static const bool installed = [] {
        for (const int sig : {SIGINT, SIGTERM}) {
            struct sigaction old {};
            if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
            struct sigaction handler {};
            handler.sa_handler = detail::removeTemporariesAndDie;
            sigemptyset(&handler.sa_mask);
            ::sigaction(sig, &handler, nullptr);
        }
        return true;
    }();
    (void)installed;
}

/// Registers the temporary files (glint::temporaryPathFor) of `outputs` for removal on SIGINT or
/// SIGTERM (installSignalRule): an interrupted write leaves neither a partial output nor a hidden
/// temporary file, and the old output stays intact. Call before the work starts.
inline void removeTemporariesOnSignal(const std::vector<std::string>& outputs) {
    for (const std::string& o : outputs)
        if (!o.empty()) detail::addSignalTemporary(temporaryPathFor(o).string());
    installSignalRule();
}

/// The same for temporary files known by their own names (Session::temporaries).
inline void removeOnSignal(const std::vector<std::string>& temporaries) {
    for (const std::string& t : temporaries)
        if (!t.empty()) detail::addSignalTemporary(t);
    installSignalRule();
}

/// Runs `body` (which returns the exit code) under the signal rule (installSignalRule): a
/// glint::Error prints "tool: file: place: message" and exits 2 for bad input or 1 for a broken
/// invariant; any other exception is an internal error (exit 1).
template <class Body>
int runGuarded(const char* tool, Body&& body) {
    installSignalRule();
    try {
        return body();
    } catch (const Error& e) {
        std::fprintf(stderr, "%s: %s\n", tool, e.what());
        return e.kind() == ErrorKind::Internal ? 1 : 2;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: out of memory: the work needs more memory than is available\n",
                     tool);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", tool, oneLine(e.what()).c_str());
        return 1;
    }
}

}  // namespace glint::cli
