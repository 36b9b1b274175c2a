// glint-lab's subcommands, one file each: oracle_command.cpp (oracle), navigate_command.cpp
// (navigate --simulate [--local]), auto_command.cpp (auto with every tuning flag). They reuse
// glint-denoise's command-line helpers (denoise/cli/commands.h). Private to the CLI.
#pragma once

#include <string>
#include <vector>

#include "commands.h"

namespace glint::lab::cli {

using denoise::cli::Command;

std::vector<Command> addOracleCommand(CLI::App& app);
std::vector<Command> addNavigateCommand(CLI::App& app);
std::vector<Command> addAutoCommand(CLI::App& app);

/// "#m filter p1=v1 …": member `m` of `bank` for the text reports.
std::string memberText(const denoise::FilterBank& bank, int m);

}  // namespace glint::lab::cli
