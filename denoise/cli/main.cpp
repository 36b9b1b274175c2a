// glint-denoise: list and apply filters, build and explore filter banks, choose among them
// automatically, paint and composite (docs/denoise.md, docs/navigation.md, docs/auto.md). Each
// group of subcommands has its own file.
#include <CLI/CLI.hpp>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/image/memory.h"

int main(int argc, char** argv) {
    // The filters allocate and free frame-sized buffers by the hundred (glint/image/memory.h).
    glint::retainFreedMemory();
    CLI::App app{"Denoise layered EXRs: filters, filter banks, navigation, painting.",
                 "glint-denoise"};
    app.require_subcommand(1);
    // Programs external denoisers named by a session or bank may run (docs/external-denoiser.md);
    // given before or after the subcommand.
    std::vector<std::string> allowed;
    app.add_option("--allow-command", allowed,
                   "Let external members run this program (full path; repeatable; also read "
                   "from $XDG_CONFIG_HOME/glint/allowed-commands)");
    app.fallthrough();
    std::vector<glint::denoise::cli::Command> commands;
    for (auto add : {glint::denoise::cli::addFilterCommands, glint::denoise::cli::addBankCommands,
                     glint::denoise::cli::addSessionCommands, glint::denoise::cli::addAutoCommands})
        for (glint::denoise::cli::Command& c : add(app)) commands.push_back(std::move(c));
    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-denoise"))
        return *code;
    return glint::cli::runGuarded("glint-denoise", [&] {
        glint::denoise::cli::allowCommands(allowed);
        for (const glint::denoise::cli::Command& c : commands)
            if (*c.app) c.run();
        return 0;
    });
}
