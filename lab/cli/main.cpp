// glint-lab: the researchers' measurements of Glint's denoiser, which need a reference or tune
// what the product keeps fixed: the oracle, the simulated user and the local artist, and auto with
// every tuning flag (docs/lab/README.md). The artist's commands are glint-denoise's.
#include <CLI/CLI.hpp>

#include "cli_boundary.h"
#include "glint/image/memory.h"
#include "lab_commands.h"

int main(int argc, char** argv) {
    // The filters allocate and free frame-sized buffers by the hundred (glint/image/memory.h).
    glint::retainFreedMemory();
    CLI::App app{"Glint's lab: oracles, simulated users and auto's tuning, against a reference.",
                 "glint-lab"};
    app.require_subcommand(1);
    // Programs external denoisers named by a bank may run (docs/external-denoiser.md).
    std::vector<std::string> allowed;
    app.add_option("--allow-command", allowed,
                   "Let external members run this program (full path; repeatable; also read "
                   "from $XDG_CONFIG_HOME/glint/allowed-commands)");
    app.fallthrough();
    std::vector<glint::lab::cli::Command> commands;
    for (auto add : {glint::lab::cli::addOracleCommand, glint::lab::cli::addNavigateCommand,
                     glint::lab::cli::addAutoCommand})
        for (glint::lab::cli::Command& c : add(app)) commands.push_back(std::move(c));
    if (const auto code = glint::cli::parseCommandLine(app, argc, argv, "glint-lab")) return *code;
    return glint::cli::runGuarded("glint-lab", [&] {
        glint::denoise::cli::allowCommands(allowed);
        for (const glint::lab::cli::Command& c : commands)
            if (*c.app) c.run();
        return 0;
    });
}
