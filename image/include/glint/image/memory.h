// Memory budgets: how much this process may still allocate, and a refusal, before allocating,
// of work that would need more (docs/numerics.md).
#pragma once

#include <cstdint>
#include <string>

namespace glint {

/// Bytes this process may still allocate: the kernel's MemAvailable (/proc/meminfo), lowered by
/// a cgroup memory limit (v2 memory.max or v1 limit_in_bytes, less what the group already uses)
/// and by the environment variable GLINT_MEMORY_LIMIT (bytes, or a number with K, M, G or T);
/// 2^64 - 1 when none of them can be read.
std::uint64_t availableMemory();

/// Parses a memory size: "123", "512M", "1.5G", "2T" (binary units; K, M, G, T, optionally
/// followed by "iB" or "B"), at least 1 byte. Throws glint::Error(InvalidArgument) naming
/// `where` otherwise.
std::uint64_t parseMemorySize(const std::string& text, const std::string& where);

/// "1.50 GiB", "640 KiB", "12 B".
std::string formatBytes(std::uint64_t bytes);

/// Throws glint::Error(OutOfMemory) when `bytes` exceeds `limit` (0: availableMemory()). The
/// message names `what` needs how much and how much is available; `file`/`where` locate it.
void checkMemory(std::uint64_t bytes, std::uint64_t limit, const std::string& what,
                 const std::string& file = {}, const std::string& where = {});

/// Keeps memory the process frees for its own reuse instead of returning it to the kernel: with
/// glibc, blocks up to 32 MiB come from the heap (not a fresh mapping each) and the heaps are not
/// trimmed below 2 GiB of free space. The filters and the auto composite allocate and free
/// frame-sized buffers by the hundred; without this, each comes back as fresh zeroed pages
/// (the kernel's page clearing took about a tenth of a `bench_auto` run;
/// docs/lab/auto-notebook-2.md, "Speed of the halves"). A process-wide setting for
/// command-line tools and benchmarks (not a long-running application, whose memory after a large
/// job would stay at its peak); does nothing on other C libraries or under an allocator that
/// replaces glibc's (AddressSanitizer's).
/// Returns whether the setting took.
bool retainFreedMemory();

/// a * b, or 2^64 - 1 when the product does not fit (for memory estimates).
constexpr std::uint64_t saturatingMul(std::uint64_t a, std::uint64_t b) {
    return (a != 0 && b > UINT64_MAX / a) ? UINT64_MAX : a * b;
}
/// a + b, or 2^64 - 1 when the sum does not fit.
constexpr std::uint64_t saturatingAdd(std::uint64_t a, std::uint64_t b) {
    return b > UINT64_MAX - a ? UINT64_MAX : a + b;
}

}  // namespace glint
