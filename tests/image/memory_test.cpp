// Memory budgets (glint/image/memory.h): sizes parse strictly, the machine's available memory is
// read and lowered by GLINT_MEMORY_LIMIT, checkMemory refuses with one clear error, and
// retainFreedMemory keeps a freed frame-sized buffer for reuse.
#include <gtest/gtest.h>

#include <cstdlib>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <fstream>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/memory.h"
#include "sanitizer.h"

namespace glint {
namespace {

TEST(Memory, SizesParseInBinaryUnits) {
    EXPECT_EQ(parseMemorySize("123", "x"), 123u);
    EXPECT_EQ(parseMemorySize("512M", "x"), 512ull << 20);
    EXPECT_EQ(parseMemorySize("1.5G", "x"), 3ull << 29);
    EXPECT_EQ(parseMemorySize("2GiB", "x"), 2ull << 30);
    EXPECT_EQ(parseMemorySize("64KB", "x"), 64ull << 10);
    EXPECT_EQ(parseMemorySize("1T", "x"), 1ull << 40);
    for (const char* bad : {"", "G", "-1G", "1X", "1e300", "nan", "12 M", "1GG"}) {
        try {
            parseMemorySize(bad, "--memory-limit");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_EQ(e.where(), "--memory-limit");
        }
    }
}

TEST(Memory, BytesFormatWithThreeSignificantDigits) {
    EXPECT_EQ(formatBytes(12), "12 B");
    EXPECT_EQ(formatBytes(1ull << 30), "1.00 GiB");
    EXPECT_EQ(formatBytes(24ull << 30), "24.0 GiB");
    EXPECT_EQ(formatBytes(640ull << 10), "640 KiB");
}

TEST(Memory, AvailableMemoryIsAtMostTheMachineAndFollowsTheEnvironmentLimit) {
    // MemTotal bounds MemAvailable (and a cgroup only lowers it).
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    std::uint64_t totalKib = 0;
    while (meminfo >> key)
        if (key == "MemTotal:" && (meminfo >> totalKib)) break;
    ASSERT_GT(totalKib, 0u);
    const std::uint64_t available = availableMemory();
    EXPECT_GT(available, 0u);
    EXPECT_LE(available, totalKib * 1024);
    ASSERT_EQ(setenv("GLINT_MEMORY_LIMIT", "3M", 1), 0);
    EXPECT_EQ(availableMemory(), 3ull << 20);
    ASSERT_EQ(setenv("GLINT_MEMORY_LIMIT", "lots", 1), 0);
    EXPECT_THROW(availableMemory(), Error);
    unsetenv("GLINT_MEMORY_LIMIT");
    EXPECT_LE(availableMemory(), totalKib * 1024);
}

TEST(Memory, CheckRefusesWithWhatItNeedsAndWhatThereIs) {
    EXPECT_NO_THROW(checkMemory(1000, 1000, "a thing"));
    try {
        checkMemory(3ull << 30, 1ull << 30, "a 8192x8192 path render", "scene.json", "/film");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
        EXPECT_EQ(std::string(e.what()),
                  "scene.json: /film: a 8192x8192 path render needs 3.00 GiB but only 1.00 GiB is "
                  "allowed (memory limit); nothing was allocated");
    }
    // The default budget is the machine's: no machine has 2^64 - 1 bytes.
    EXPECT_THROW(checkMemory(UINT64_MAX - 1, 0, "everything"), Error);
    EXPECT_EQ(saturatingMul(1ull << 40, 1ull << 40), UINT64_MAX);
    EXPECT_EQ(saturatingAdd(UINT64_MAX - 1, 5), UINT64_MAX);
    EXPECT_EQ(errorKindName(ErrorKind::OutOfMemory), std::string("out-of-memory"));
}

TEST(Memory, RetainFreedMemoryKeepsAFrameSizedBufferInTheHeap) {
#if defined(GLINT_TEST_ASAN)
    // AddressSanitizer (make test-sanitize) replaces malloc: glibc's settings cannot take there,
    // and the function says so.
    EXPECT_FALSE(retainFreedMemory());
#elif defined(__GLIBC__)
    ASSERT_TRUE(retainFreedMemory());
    // A 12 MiB buffer (a 1024² RGB float frame): from the heap, not a mapping of its own (which
    // glibc's default 128 KiB threshold would give it), and still held by the allocator once
    // freed, for the next frame to reuse without faulting fresh pages.
    constexpr std::size_t kBytes = std::size_t(12) << 20;
    const std::size_t mappedBefore = mallinfo2().hblkhd;
    {
        std::vector<float> frame(kBytes / sizeof(float), 1.0f);
        volatile float sink = frame[frame.size() / 2];
        (void)sink;
        EXPECT_LT(mallinfo2().hblkhd, mappedBefore + kBytes) << "the buffer was mapped";
    }
    EXPECT_GE(mallinfo2().fordblks, kBytes) << "the freed buffer went back to the kernel";
#else
    EXPECT_FALSE(retainFreedMemory());
#endif
}

}  // namespace
}  // namespace glint
