#include "glint/image/memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "glint/image/error.h"

namespace glint {
namespace {

constexpr std::uint64_t kUnlimited = UINT64_MAX;

/// The first whitespace-separated number of a one-line file, or kUnlimited ("max", missing).
std::uint64_t readNumberFile(const char* path) {
    std::ifstream in(path);
    std::string token;
    if (!(in >> token) || token == "max") return kUnlimited;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(token.c_str(), &end, 10);
    return (end && *end == '\0') ? std::uint64_t(v) : kUnlimited;
}

/// MemAvailable of /proc/meminfo in bytes, or kUnlimited.
std::uint64_t memAvailable() {
    std::ifstream in("/proc/meminfo");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("MemAvailable:", 0) != 0) continue;
        std::istringstream fields(line.substr(13));
        std::uint64_t kib = 0;
        if (fields >> kib) return saturatingMul(kib, 1024);
    }
    return kUnlimited;
}

/// What the process's cgroup still allows (limit - usage), or kUnlimited.
std::uint64_t cgroupHeadroom() {
    // cgroup v2 (unified hierarchy) first, then v1's memory controller.
    std::uint64_t limit = readNumberFile("/sys/fs/cgroup/memory.max");
    std::uint64_t usage = readNumberFile("/sys/fs/cgroup/memory.current");
    if (limit == kUnlimited) {
        limit = readNumberFile("/sys/fs/cgroup/memory/memory.limit_in_bytes");
        usage = readNumberFile("/sys/fs/cgroup/memory/memory.usage_in_bytes");
    }
    // v1 reports "no limit" as a huge page-aligned number.
    if (limit == kUnlimited || limit >= (std::uint64_t(1) << 62)) return kUnlimited;
    if (usage == kUnlimited) usage = 0;
    return limit > usage ? limit - usage : 0;
}

}  // namespace

bool retainFreedMemory() {
#if defined(__GLIBC__)
    // 32 MiB is the largest threshold glibc accepts on 64-bit. Setting both also turns off its
    // sliding threshold, which rises to the size of each freed mapping and trims at twice that.
    const bool mmap = mallopt(M_MMAP_THRESHOLD, 32 << 20) == 1;
    const bool trim = mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max()) == 1;
    return mmap && trim;
#else
    return false;
#endif
}

std::uint64_t parseMemorySize(const std::string& text, const std::string& where) {
    const auto bad = [&] {
        return Error(ErrorKind::InvalidArgument,
                     "'" + text +
                         "' is not a memory size; expected bytes or a number with K, "
                         "M, G or T (e.g. 512M, 1.5G)",
                     {}, where);
    };
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || !std::isfinite(v) || v < 0.0) throw bad();
    std::string unit(end);
    for (const char* suffix : {"iB", "B"})
        if (unit.size() > 1 && unit.size() >= std::string(suffix).size() &&
            unit.compare(unit.size() - std::string(suffix).size(), std::string::npos, suffix) ==
                0) {
            unit.resize(unit.size() - std::string(suffix).size());
            break;
        }
    double scale = 1.0;
    if (unit.empty() || unit == "B")
        scale = 1.0;
    else if (unit == "K" || unit == "k")
        scale = 0x1p10;
    else if (unit == "M" || unit == "m")
        scale = 0x1p20;
    else if (unit == "G" || unit == "g")
        scale = 0x1p30;
    else if (unit == "T" || unit == "t")
        scale = 0x1p40;
    else
        throw bad();
    const double bytes = v * scale;
    if (bytes >= 0x1p64) throw bad();
    // No work fits in nothing, and 0 would read as "no limit given" (the default budget).
    if (bytes < 1.0)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text +
                        "' is no memory at all; expected a size of at least 1 byte (omit "
                        "the option for the default, what the machine has available)",
                    {}, where);
    return std::uint64_t(bytes);
}

std::uint64_t availableMemory() {
    std::uint64_t bytes = std::min(memAvailable(), cgroupHeadroom());
    if (const char* env = std::getenv("GLINT_MEMORY_LIMIT"); env && *env)
        bytes = std::min(bytes, parseMemorySize(env, "GLINT_MEMORY_LIMIT"));
    return bytes;
}

std::string formatBytes(std::uint64_t bytes) {
    static const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = double(bytes);
    int u = 0;
    while (v >= 1024.0 && u < 6) v /= 1024.0, ++u;
    char text[32];
    if (u == 0)
        std::snprintf(text, sizeof text, "%llu B", (unsigned long long)bytes);
    else
        std::snprintf(text, sizeof text,
                      v < 10.0    ? "%.2f %s"
                      : v < 100.0 ? "%.1f %s"
                                  : "%.0f %s",
                      v, units[u]);
    return text;
}

void checkMemory(std::uint64_t bytes, std::uint64_t limit, const std::string& what,
                 const std::string& file, const std::string& where) {
    const bool machine = limit == 0;
    const std::uint64_t allowed = machine ? availableMemory() : limit;
    if (bytes <= allowed) return;
    throw Error(ErrorKind::OutOfMemory,
                what + " needs " + formatBytes(bytes) + " but only " + formatBytes(allowed) +
                    (machine ? " is available on this machine" : " is allowed (memory limit)") +
                    "; nothing was allocated",
                file, where);
}

}  // namespace glint
