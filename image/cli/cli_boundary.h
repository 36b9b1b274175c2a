// The one catch boundary shared by Glint's command-line tools (glint-image, glint-render,
// glint-denoise): parse errors and glint::Error become one line on stderr and an exit code.
// Private to the CLIs (it includes CLI11); the libraries never see it.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <optional>

#include "glint/image/error.h"

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
        std::fprintf(stderr, "%s: command line: %s\n", tool, e.what());
        return 2;
    }
    return std::nullopt;
}

/// Runs `body` (which returns the exit code): a glint::Error prints "tool: file: place: message"
/// and exits 2 for bad input or 1 for a broken invariant; any other exception is an internal
/// error (exit 1).
template <class Body>
int runGuarded(const char* tool, Body&& body) {
    try {
        return body();
    } catch (const Error& e) {
        std::fprintf(stderr, "%s: %s\n", tool, e.what());
        return e.kind() == ErrorKind::Internal ? 1 : 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", tool, e.what());
        return 1;
    }
}

}  // namespace glint::cli
