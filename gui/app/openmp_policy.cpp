#include "app/openmp_policy.h"

#include <unistd.h>

#include <cstdlib>

namespace glint::studio {

namespace {
constexpr const char* kVariable = "OMP_WAIT_POLICY";
/// Set beside the variable for the run again: the value is the studio's, not the user's.
constexpr const char* kSetByStudio = "GLINT_STUDIO_SET_OMP_WAIT_POLICY";
}  // namespace

bool runAgainForPassiveWait(const char* current) {
    return current == nullptr;
}

void usePassiveOpenMpWait(char** argv, const char* program) {
    if (std::getenv(kSetByStudio) != nullptr) {
        // Run again: libgomp has read the variable as it loaded. Take both out, so that what the
        // studio starts (an external denoiser, a render) gets the user's environment back.
        unsetenv(kVariable);
        unsetenv(kSetByStudio);
        return;
    }
    if (!runAgainForPassiveWait(std::getenv(kVariable))) return;
    // Set: the process run again sees them and goes on (no loop).
    if (setenv(kVariable, "PASSIVE", 1) != 0 || setenv(kSetByStudio, "1", 1) != 0) {
        unsetenv(kVariable);
        unsetenv(kSetByStudio);
        return;
    }
    execv(program, argv);
    // Not replaced (no /proc mounted, say): go on as launched, with the user's environment.
    unsetenv(kVariable);
    unsetenv(kSetByStudio);
}

}  // namespace glint::studio
