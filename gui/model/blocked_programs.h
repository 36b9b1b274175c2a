// The programs a session's unavailable layers wait for: an external member (filter `external`,
// docs/external-denoiser.md) whose program the user has not allowed is loaded without running;
// the studio offers to allow that program, by its full path. No widgets here.
#pragma once

#include <QString>

#include <cstddef>
#include <vector>

namespace glint::denoise {
class Session;
}

namespace glint::studio {

/// One program not allowed to run, and the session's layers that name it.
struct BlockedProgram {
    QString program;                  ///< its full path, as the layers name it
    std::vector<std::size_t> layers;  ///< indices of the layers waiting for it
    QString reason;                   ///< why the first of them did not run (SessionLayer)
};

/// The programs `session`'s unavailable external layers name by full path and the user has not
/// allowed (glint/denoise/external.h), in layer order, each once.
std::vector<BlockedProgram> blockedPrograms(const denoise::Session& session);

}  // namespace glint::studio
