// glint-denoise paint | composite: script a painting session, apply a saved session to a new
// render (docs/navigation.md).
#include "commands.h"

namespace glint::denoise::cli {

std::vector<Command> addSessionCommands(CLI::App&) {
    return {};
}

}  // namespace glint::denoise::cli
