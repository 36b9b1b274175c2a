// Frame-sized arrays backed by transparent huge pages: the first touch of a fresh 2 MiB region
// takes one page fault instead of 512. A film or an image of a megapixel is hundreds of MiB of
// fresh memory that is zeroed before the first sample lands in it; on a virtual machine each 4 KiB
// fault costs microseconds, and they were a second of a 1-spp render at 1024² (docs/lab/
// tradeoffs.md, "Glint against Cycles at equal time").
#pragma once

#include <cstddef>
#include <new>

namespace glint {

/// Blocks of at least this many bytes ask the kernel for huge pages.
inline constexpr std::size_t kLargePageBlock = std::size_t(2) << 20;

/// `bytes` aligned to `alignment`. From kLargePageBlock on, the block starts on a 2 MiB boundary
/// and is marked for transparent huge pages (madvise MADV_HUGEPAGE; the kernel's
/// /sys/kernel/mm/transparent_hugepage/enabled decides whether it gives them). Smaller blocks,
/// other systems and AddressSanitizer builds allocate as operator new does. Throws
/// std::bad_alloc.
void* allocateLarge(std::size_t bytes, std::size_t alignment);
/// Frees a block of allocateLarge with the same `bytes` and `alignment`.
void deallocateLarge(void* block, std::size_t bytes, std::size_t alignment) noexcept;

/// A standard allocator over allocateLarge, for std::vector's of frame size.
template <class T>
struct LargePageAllocator {
    using value_type = T;

    LargePageAllocator() noexcept = default;
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(allocateLarge(n * sizeof(T), alignof(T)));
    }
    void deallocate(T* p, std::size_t n) noexcept { deallocateLarge(p, n * sizeof(T), alignof(T)); }

    template <class U>
    bool operator==(const LargePageAllocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace glint
