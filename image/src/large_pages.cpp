#include "glint/image/large_pages.h"

#include <algorithm>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace glint {

namespace {

// AddressSanitizer's allocator keeps its redzones only for blocks it hands out itself.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

constexpr bool usesHugePages(std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    return !kAddressSanitizer && bytes >= kLargePageBlock;
#else
    (void)bytes;
    return false;
#endif
}

}  // namespace

void* allocateLarge(std::size_t bytes, std::size_t alignment) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (usesHugePages(bytes)) {
        // Through malloc, so a freed block goes back to the heap for the next frame-sized buffer
        // (glint::retainFreedMemory) instead of to the kernel. Starting on a 2 MiB boundary,
        // every whole 2 MiB of the block can be one page; the last part under 2 MiB stays in
        // small pages.
        void* block = nullptr;
        if (posix_memalign(&block, kLargePageBlock, bytes) != 0) throw std::bad_alloc();
        // Advice only: where the kernel refuses (THP off, an old kernel), the block is ordinary
        // memory.
        (void)madvise(block, bytes, MADV_HUGEPAGE);
        return block;
    }
#endif
    return ::operator new(bytes, std::align_val_t(std::max(alignment, sizeof(void*))));
}

void deallocateLarge(void* block, std::size_t bytes, std::size_t alignment) noexcept {
    if (!usesHugePages(bytes)) {
        ::operator delete(block, std::align_val_t(std::max(alignment, sizeof(void*))));
        return;
    }
    std::free(block);
}

}  // namespace glint
