// glint-denoise auto's command line (auto_commands.cpp), which glint-lab's auto extends with
// every tuning flag and the measurement outputs (lab/cli/auto_command.cpp). Private to the CLIs.
#pragma once

#include <CLI/CLI.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "commands.h"

namespace glint::denoise::cli {

/// What auto's flags set. The product's flags fill some; glint-lab's the rest (left at these
/// defaults by glint-denoise).
struct AutoArgs {
    std::string input, bank, out, reference, choiceMap, noiseOut, filters, estimator = "auto";
    std::string quality = "balanced";
    std::string session;  // --session: the session that starts from the result
    // Integers are parsed strictly from their text (parseInteger, parseUnsigned). An empty size
    // is the quality's.
    std::string size, bankSeed = "1", seed = "1", memoryLimit;
    float exposure = 0.0f;
    bool prefilter = false, json = false;
    std::vector<std::string> filterParams;  // --filter-param FILTER.NAME=VALUE
    /// The tuning flags given (autoTuningSpecs), by parameter name: their text, or "1" for a
    /// flag without a value.
    std::map<std::string, std::string> tuning;
};

/// Adds the `auto` subcommand with the product's flags to `app`, filling `a`.
CLI::App* addAutoFlags(CLI::App& app, const std::shared_ptr<AutoArgs>& a);

/// Adds the flag of one tuning parameter (autoTuningFlag; its help from the spec) to `cmd`: its
/// text lands in a->tuning.
void addTuningFlag(CLI::App* cmd, const std::shared_ptr<AutoArgs>& a, const ParamSpec& spec);

/// A tuning parameter that is a flag without a value: an integer over 0 … 1 that defaults to 0.
bool isTuningSwitch(const ParamSpec& spec);

/// Runs auto as the flags in `a` say (docs/auto.md, "Command line").
void runAuto(const AutoArgs& a);

}  // namespace glint::denoise::cli
