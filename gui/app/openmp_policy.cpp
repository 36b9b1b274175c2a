#include "app/openmp_policy.h"

#include <unistd.h>

#include <cstdlib>

namespace glint::studio {

namespace {
constexpr const char* kVariable = "OMP_WAIT_POLICY";
}

bool runAgainForPassiveWait(const char* current) {
    return current == nullptr;
}

void usePassiveOpenMpWait(char** argv, const char* program) {
    if (!runAgainForPassiveWait(std::getenv(kVariable))) return;
    // Set: the process run again sees it and goes on (no loop).
    if (setenv(kVariable, "PASSIVE", 1) != 0) return;
    execv(program, argv);
    // Not replaced (no /proc mounted, say): go on as launched, children without the variable.
    unsetenv(kVariable);
}

}  // namespace glint::studio
