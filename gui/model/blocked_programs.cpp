#include "model/blocked_programs.h"

#include <algorithm>
#include <filesystem>

#include "glint/denoise/external.h"
#include "glint/denoise/session.h"

namespace glint::studio {

std::vector<BlockedProgram> blockedPrograms(const denoise::Session& session) {
    std::vector<BlockedProgram> out;
    for (std::size_t i = 0; i < session.layerCount(); ++i) {
        const denoise::SessionLayer& layer = session.layer(i);
        if (layer.unavailable.empty() || layer.filter != "external") continue;
        const auto command = layer.params.strings.find("command");
        if (command == layer.params.strings.end() || command->second.empty()) continue;
        // Only a program named by its full path can be allowed.
        const std::filesystem::path path(command->second.front());
        if (!path.is_absolute() || denoise::commandAllowed(path)) continue;
        const QString program = QString::fromStdString(command->second.front());
        auto it = std::find_if(out.begin(), out.end(),
                               [&](const BlockedProgram& b) { return b.program == program; });
        if (it == out.end())
            out.push_back({program, {i}, QString::fromStdString(layer.unavailable)});
        else
            it->layers.push_back(i);
    }
    return out;
}

}  // namespace glint::studio
