#include "glint/image/process_clock.h"

#if defined(__linux__)
#include <time.h>
#include <unistd.h>
#endif

#include <fstream>
#include <sstream>
#include <string>

namespace glint {

std::optional<double> processAgeSeconds() {
#if defined(__linux__)
    std::ifstream in("/proc/self/stat");
    std::string stat;
    if (!std::getline(in, stat)) return std::nullopt;
    // Field 2, the command's name in parentheses, may hold spaces and ')': the fields after it
    // start past the last ')'. Field 22 is the start time in clock ticks since boot.
    const std::size_t close = stat.rfind(')');
    if (close == std::string::npos) return std::nullopt;
    std::istringstream fields(stat.substr(close + 1));
    std::string skipped;
    for (int field = 3; field < 22; ++field)
        if (!(fields >> skipped)) return std::nullopt;
    unsigned long long ticks = 0;
    const long hz = sysconf(_SC_CLK_TCK);
    timespec now{};
    if (!(fields >> ticks) || hz <= 0 || clock_gettime(CLOCK_BOOTTIME, &now) != 0)
        return std::nullopt;
    const double age = double(now.tv_sec) + 1e-9 * double(now.tv_nsec) - double(ticks) / double(hz);
    if (!(age >= 0.0)) return std::nullopt;
    return age;
#else
    return std::nullopt;
#endif
}

}  // namespace glint
