// glint-denoise bank | oracle | navigate: build a filter bank, measure what it can reach, walk
// its navigation tree as a simulated user (docs/navigation.md).
#include "commands.h"

namespace glint::denoise::cli {

std::vector<Command> addBankCommands(CLI::App&) {
    return {};
}

}  // namespace glint::denoise::cli
