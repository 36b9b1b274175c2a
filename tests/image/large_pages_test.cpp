// Frame-sized arrays (glint/image/large_pages.h): a block of 2 MiB or more starts on a 2 MiB
// boundary and its mapping carries the kernel's huge-page advice, so its first touch faults a
// 2 MiB page at a time; smaller blocks are ordinary; Image's pixels and vectors over the allocator
// hold what is written to them.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "glint/image/image.h"
#include "glint/image/large_pages.h"
#include "sanitizer.h"

namespace glint {
namespace {

// The VmFlags line of /proc/self/smaps for the mapping that holds `address` ("" if none).
std::string vmFlagsOf(const void* address) {
    const auto at = reinterpret_cast<std::uintptr_t>(address);
    std::ifstream smaps("/proc/self/smaps");
    std::string line;
    bool inside = false;
    while (std::getline(smaps, line)) {
        std::uintptr_t begin = 0, end = 0;
        char dash = 0;
        std::istringstream head(line);
        if (head >> std::hex >> begin >> dash >> end && dash == '-' &&
            line.find(':') > line.find(' ')) {
            inside = begin <= at && at < end;
            continue;
        }
        if (inside && line.rfind("VmFlags:", 0) == 0) return line;
    }
    return {};
}

bool alignedTo(const void* p, std::size_t alignment) {
    return reinterpret_cast<std::uintptr_t>(p) % alignment == 0;
}

TEST(LargePages, AFrameSizedBlockIsAdvisedForHugePages) {
    constexpr std::size_t kBytes = std::size_t(12) << 20;  // a 1024² RGB float frame
    void* block = allocateLarge(kBytes, alignof(float));
    ASSERT_NE(block, nullptr);
    static_cast<volatile char*>(block)[0] = 1;
    static_cast<volatile char*>(block)[kBytes - 1] = 2;
#if defined(__linux__) && !defined(GLINT_TEST_ASAN)
    EXPECT_TRUE(alignedTo(block, kLargePageBlock));
    const std::string flags = vmFlagsOf(block);
    ASSERT_FALSE(flags.empty()) << "no mapping in /proc/self/smaps holds the block";
    // A kernel built without transparent huge pages refuses the advice; the block is ordinary.
    if (std::filesystem::exists("/sys/kernel/mm/transparent_hugepage/enabled"))
        EXPECT_NE(flags.find(" hg"), std::string::npos) << flags;
    else
        EXPECT_EQ(flags.find(" hg"), std::string::npos) << flags;
#elif defined(GLINT_TEST_ASAN)
    // AddressSanitizer's own allocator serves the block, with its redzones: no advice.
    EXPECT_EQ(vmFlagsOf(block).find(" hg"), std::string::npos);
#endif
    deallocateLarge(block, kBytes, alignof(float));
}

TEST(LargePages, ASmallBlockIsOrdinaryAndKeepsItsAlignment) {
    constexpr std::size_t kBytes = 4096;
    void* block = allocateLarge(kBytes, 64);
    ASSERT_NE(block, nullptr);
    EXPECT_TRUE(alignedTo(block, 64));
    deallocateLarge(block, kBytes, 64);
}

TEST(LargePages, VectorsAndImagesOverTheAllocatorHoldTheirValues) {
    std::vector<double, LargePageAllocator<double>> big(std::size_t(1) << 20);  // 8 MiB
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = double(i);
    std::vector<double, LargePageAllocator<double>> copy = big;
    EXPECT_EQ(copy.back(), double(big.size() - 1));
    copy.resize(16);
    copy.shrink_to_fit();
    EXPECT_EQ(copy[15], 15.0);

    Image frame(1024, 1024, 3, 0.25f);
    frame(1023, 1023, 2) = 7.0f;
    const Image moved = std::move(frame);
    EXPECT_EQ(moved(1023, 1023, 2), 7.0f);
    EXPECT_EQ(moved(0, 0, 0), 0.25f);
#if defined(__linux__) && !defined(GLINT_TEST_ASAN)
    EXPECT_TRUE(alignedTo(moved.data().data(), kLargePageBlock));
#endif
    const Image copied = moved;
    EXPECT_EQ(copied(1023, 1023, 2), 7.0f);
}

TEST(LargePages, AnImpossibleCountThrowsBadAlloc) {
    LargePageAllocator<double> allocator;
    EXPECT_THROW((void)allocator.allocate(std::size_t(-1) / 4), std::bad_alloc);
}

}  // namespace
}  // namespace glint
